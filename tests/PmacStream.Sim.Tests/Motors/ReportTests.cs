using System.Text;

namespace PmacStream.Sim.Tests.Motors;

/// <summary>P, V, F and the status words while a program moves the motors through their axis definitions.</summary>
public class ReportTests
{
    [Fact]
    public void A_program_moves_its_motors_by_the_axis_definition_and_they_report_it()
    {
        using var h = new SimHarness();
        h.Ok("#1->1000X #2->-500Y");
        h.Ok("&1 OPEN PROG 1 CLEAR LINEAR ABS F600 X100 Y100 CLOSE B1 R");
        h.Advance(2);
        var (x, y) = (h.Sim.Position()[0], h.Sim.Position()[1]);
        h.Number("#1P").Should().BeApproximately(x * 1000, 1e-6);
        h.Number("#2P").Should().BeApproximately(y * -500, 1e-6);

        // 10 mm/s along the diagonal: 7.07 mm/s an axis, 7071 counts/s on motor 1 = 7.07 counts/ms = 3.1 counts/cycle.
        h.Number("#1V").Should().BeApproximately(10 / Math.Sqrt(2) * 3713991 / 8388608.0, 0.051);
        h.Number("#2V").Should().BeLessThan(0, "a negative scale");
        h.MotorBit(1, 1, 17).Should().BeTrue("Move Timer Active while the program moves it");
        h.MotorBit(1, 1, 13).Should().BeFalse("desired velocity not zero");
        h.CsBit(2, 17).Should().BeFalse("the C.S. is not in position while it moves");
        h.Sim.RunUntilIdle();
        h.Ok("#1P#2P#1V").Should().Be("100000\n-50000\n0");
        h.MotorBit(1, 2, 0).Should().BeTrue("in position at the end");
        h.CsBit(2, 17).Should().BeTrue();
    }

    [Fact]
    public void Control_characters_report_eight_motors()
    {
        using var h = new SimHarness();
        h.Ok("I119=100 I121=1 #3J:42 #2K");
        h.Sim.RunUntilIdle();
        Encoding.ASCII.GetString(h.Port.Control('P')).Should().Be("0 0 42 0 0 0 0 0\r");
        Encoding.ASCII.GetString(h.Port.Control('F')).Should().Be("0 0 0 0 0 0 0 0\r");
        Encoding.ASCII.GetString(h.Port.Control('V')).Should().Be("0 0 0 0 0 0 0 0\r");
        var status = Encoding.ASCII.GetString(h.Port.Control('B')).TrimEnd('\r').Split(' ');
        status.Should().HaveCount(8);
        StatusBits.Bit(status[1], 1, 18).Should().BeTrue("motor 2 killed: open loop");
        StatusBits.Bit(status[0], 1, 19).Should().BeTrue("motor 1 enabled");
    }

    [Fact]
    public void The_axis_definition_code_and_coordinate_system_of_the_second_word()
    {
        using var h = new SimHarness();
        h.Ok("#4->A #7->U #10->X");
        StatusBits.Word(h.Ok("#1?"), 2).Should().Be(0x07C401, "X: code 7, assigned, enabled, homed, in position");
        ((StatusBits.Word(h.Ok("#4?"), 2) >> 16) & 0xF).Should().Be(1, "A");
        ((StatusBits.Word(h.Ok("#7?"), 2) >> 16) & 0xF).Should().Be(4, "U/V/W");
        StatusBits.Bit(h.Ok("#11?"), 2, 15).Should().BeFalse("motor 11 is assigned to no axis");
        StatusBits.Bit(h.Ok("#10?"), 2, 15).Should().BeTrue();
    }
}
