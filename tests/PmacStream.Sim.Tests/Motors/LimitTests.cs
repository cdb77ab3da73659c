
namespace PmacStream.Sim.Tests.Motors;

/// <summary>Software limits (Ixx13/Ixx14) and hardware limit switches: a limit stops the motor, a move into it is refused, a move away is allowed.</summary>
public class LimitTests
{
    [Fact]
    public void A_software_limit_stops_a_jog_there_and_only_a_move_away_is_allowed()
    {
        using var h = new SimHarness();
        h.Ok("I113=2000 I114=-500 I119=100 I121=1");
        h.Ok("#1J+");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("2000");
        h.MotorBit(1, 2, 11).Should().BeTrue("Stopped on Position Limit");
        h.Ok("#1J:100");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("2000", "a move further into the limit does not start");
        h.Ok("#1J:-300");
        h.MotorBit(1, 2, 11).Should().BeFalse("0 while moving out of the limit");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("1700");
        h.Ok("#1J-");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("-500");
    }

    [Fact]
    public void A_program_running_into_a_software_limit_is_aborted()
    {
        using var h = new SimHarness();
        h.Ok("#1->1000X I113=20000");
        h.Ok("&1 OPEN PROG 1 CLEAR LINEAR ABS F600 X100 CLOSE B1 R");
        h.Sim.RunUntilIdle();
        h.Sim.IsRunning().Should().BeFalse();
        h.Sim.Position()[0].Should().BeApproximately(20, 0.02, "stopped within a step of the limit (10 mm/s)");
        h.MotorBit(1, 2, 11).Should().BeTrue();
    }

    [Fact]
    public void A_hardware_limit_switch_stops_a_jog_and_sets_the_limit_input()
    {
        var o = new SimOptions();
        o.MotorSettings[2] = new MotorSettings { PlusLimitPosition = 1500 };
        using var h = new SimHarness(o);
        h.Ok("I219=100 I221=1");
        h.Ok("#2J+");
        h.Sim.RunUntilIdle();
        h.Number("#2P").Should().BeInRange(1500, 1533, "stopped within one step at 32 counts/ms");
        h.MotorBit(2, 1, 21).Should().BeTrue("Positive End Limit Set");
        h.MotorBit(2, 1, 22).Should().BeFalse();
        h.MotorBit(2, 2, 11).Should().BeTrue();
        h.Ok("#2J-");
        h.Advance(0.1);
        h.MotorBit(2, 1, 21).Should().BeFalse("moved off the switch");
        h.MotorBit(2, 2, 11).Should().BeFalse();
    }

    [Fact]
    public void Both_limits_are_checked_by_direction()
    {
        var o = new SimOptions();
        o.MotorSettings[3] = new MotorSettings { MinusLimitPosition = -100 };
        using var h = new SimHarness(o);
        h.Ok("I319=100 I321=1 #3J:-1000");
        h.Sim.RunUntilIdle();
        h.Number("#3P").Should().BeInRange(-133, -100);
        h.MotorBit(3, 1, 22).Should().BeTrue("Negative End Limit Set");
        h.Ok("#3J:50");
        h.Sim.RunUntilIdle();
        h.MotorBit(3, 1, 22).Should().BeFalse();
    }
}
