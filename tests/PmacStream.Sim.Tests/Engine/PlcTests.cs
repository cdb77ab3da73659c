namespace PmacStream.Sim.Tests.Engine;

public class PlcTests
{
    private const int Inputs = 0x078800;
    private const int Outputs = 0x078801;

    private static SimHarness MotorCircuit()
    {
        var h = new SimHarness();
        h.Download(
            "M800->Y:$078800,0",
            "M801->Y:$078800,1",
            "M802->Y:$078800,2",
            "M803->Y:$078800,3",
            "M900->Y:$078801,0,1",
            "M901->Y:$078801,1,1",
            "OPEN PLC 1 CLEAR",
            "M900=(M800^1)&(M801|M900)&(M901^1)&(M803^1)",
            "M901=(M800^1)&(M802|M901)&(M900^1)&(M803^1)",
            "CLOSE",
            "ENABLE PLC 1");
        return h;
    }

    private static void Press(SimHarness h, int bit)
    {
        h.Sim.SetBit('Y', Inputs, bit, true);
        h.Sim.RunPlcScan();
        h.Sim.SetBit('Y', Inputs, bit, false);
        h.Sim.RunPlcScan();
    }

    [Fact]
    public void Seed_motor_circuit_seals_in_interlocks_and_stops()
    {
        using var h = MotorCircuit();
        h.Sim.RunPlcScan();
        h.Sim.GetWord('Y', Outputs).Should().Be(0);

        Press(h, 1); // forward
        h.Sim.GetWord('Y', Outputs).Should().Be(1, "KM1 sealed in after SB2 is released");

        Press(h, 2); // reverse while forward runs
        h.Sim.GetWord('Y', Outputs).Should().Be(1, "KM2 is interlocked by KM1");

        Press(h, 0); // stop
        h.Sim.GetWord('Y', Outputs).Should().Be(0);

        Press(h, 2);
        h.Sim.GetWord('Y', Outputs).Should().Be(2, "reverse only after stop");
        h.Ok("M901").Should().Be("1");

        h.Sim.SetBit('Y', Inputs, 3, true); // thermal relay trips
        h.Sim.RunPlcScan();
        h.Sim.GetWord('Y', Outputs).Should().Be(0);
    }

    [Fact]
    public void Plc_scans_run_with_the_virtual_clock_and_stop_when_disabled()
    {
        using var h = new SimHarness(new SimOptions { PlcScanIntervalMs = 2 });
        h.Download("OPEN PLC 3 CLEAR", "P1=P1+1", "CLOSE");
        h.Advance(0.1);
        h.Sim.ReadVariable('P', 1).Should().Be(0, "a downloaded PLC waits for ENABLE");
        h.Ok("ENA PLC 3");
        h.Advance(0.1);
        h.Sim.ReadVariable('P', 1).Should().BeInRange(50, 51);
        h.Ok("DIS PLC 3");
        var p = h.Sim.ReadVariable('P', 1);
        h.Advance(0.1);
        h.Sim.ReadVariable('P', 1).Should().Be(p);
        h.Ok("I5=0 ENABLE PLC 3");
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 1).Should().Be(p, "I5=0 runs no PLC");
    }

    [Fact]
    public void While_loop_ends_the_scan_at_endwhile()
    {
        using var h = new SimHarness();
        h.Download(
            "OPEN PLC 2 CLEAR",
            "P1=P1+1",
            "WHILE (M1001=0)",
            "  P2=P2+1",
            "ENDWHILE",
            "P3=P3+1",
            "CLOSE",
            "M1001->*",
            "ENABLE PLC 2");
        h.Sim.RunPlcScan();
        h.Sim.RunPlcScan();
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 1).Should().Be(1);
        h.Sim.ReadVariable('P', 2).Should().Be(3, "one loop pass per scan");
        h.Ok("M1001=1");
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 3).Should().Be(1);
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 1).Should().Be(2, "the next scan starts from the top");
    }

    [Fact]
    public void If_else_and_byte_wide_definitions()
    {
        using var h = new SimHarness();
        h.Download(
            "M1000->Y:$078802,0,8",
            "M1002->Y:$078802,8,8",
            "M1003->X:$000010,4,4",
            "OPEN PLC 4 CLEAR",
            "IF (M1000>127 AND M1000!<200)",
            "  M1002=M1000/2",
            "ELSE",
            "  M1002=M1000+1",
            "ENDIF",
            "M1003=15",
            "CLOSE",
            "ENA PLC 4");
        h.Sim.SetWord('Y', 0x078802, 10);
        h.Sim.RunPlcScan();
        h.Sim.GetWord('Y', 0x078802).Should().Be((11 << 8) | 10);
        h.Sim.SetWord('Y', 0x078802, 250);
        h.Sim.RunPlcScan();
        h.Sim.GetWord('Y', 0x078802).Should().Be((125 << 8) | 250);
        h.Sim.GetWord('X', 0x10).Should().Be(0xF0);
        h.Ok("M1002=$1FF M1002").Should().Be("255", "writes are masked to the field width");
    }

    [Fact]
    public void Opening_a_plc_stops_it_until_enabled()
    {
        using var h = new SimHarness();
        h.Download("OPEN PLC 5 CLEAR", "P1=P1+1", "CLOSE", "ENABLE PLC 5");
        h.Sim.RunPlcScan();
        h.Download("OPEN PLC 5 CLEAR", "P1=P1+10");
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 1).Should().Be(1);
        h.Download("CLOSE");
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 1).Should().Be(1);
        h.Download("ENABLE PLC 5");
        h.Sim.RunPlcScan();
        h.Sim.ReadVariable('P', 1).Should().Be(11);
        h.Ok("LIST PLC 5").Should().Be("P1=P1+10");
    }
}
