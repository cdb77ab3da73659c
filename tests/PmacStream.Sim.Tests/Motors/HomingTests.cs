
namespace PmacStream.Sim.Tests.Motors;

/// <summary>Homing as a Turbo PMAC does it: HM at Ixx23 to the home switch, zero at Ixx26/16 counts from the trigger; HMZ.</summary>
public class HomingTests
{
    private static SimOptions Unhomed(double homeSwitch)
    {
        var o = new SimOptions { StartHomed = false };
        o.MotorSettings[1] = new MotorSettings { HomeSwitchPosition = homeSwitch };
        return o;
    }

    [Fact]
    public void The_simulator_starts_homed_unless_told_otherwise()
    {
        using var homed = new SimHarness();
        homed.MotorBit(1, 2, 10).Should().BeTrue("the in-process simulator of demo and --sim is homed");
        using var unhomed = new SimHarness(new SimOptions { StartHomed = false });
        unhomed.MotorBit(1, 2, 10).Should().BeFalse("a machine with incremental encoders is not homed at power-on");
    }

    [Fact]
    public void HM_finds_the_switch_at_the_home_speed_and_ends_at_the_home_offset()
    {
        using var h = new SimHarness(Unhomed(5000));
        h.Ok("I123=20 I126=-16000 I119=100 I121=1"); // 20 counts/ms positive; zero 1000 counts before the trigger
        h.Ok("#1HM");
        h.Advance(0.1);
        h.MotorBit(1, 1, 10).Should().BeTrue("home search in progress");
        h.MotorBit(1, 2, 10).Should().BeFalse("Home Complete is 0 until the trigger is found");
        h.Sim.Motor(1).Velocity.Should().BeApproximately(20_000, 1e-6, "Ixx23 counts/ms");
        var used = h.Sim.RunUntilIdle();
        used.TotalSeconds.Should().BeInRange(0.15, 0.5, "5000 counts at 20 counts/ms, then back 1000 counts");
        h.MotorBit(1, 2, 10).Should().BeTrue("Home Complete");
        h.MotorBit(1, 1, 10).Should().BeFalse("search over");
        h.Ok("#1P").Should().Be("0", "the motor stops at its new zero");
        h.Sim.Motor(1).Machine.Should().BeApproximately(4000, 1e-9, "switch at 5000 plus Ixx26/16 = -1000");
        h.MotorBit(1, 2, 0).Should().BeTrue("in position at home");
    }

    [Fact]
    public void A_negative_home_speed_searches_in_the_negative_direction()
    {
        using var h = new SimHarness(Unhomed(-3000));
        h.Ok("I123=-32 I126=800 I119=100 I121=1");
        h.Ok("#1HM");
        h.Advance(0.05);
        h.Sim.Motor(1).Velocity.Should().BeLessThan(0);
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("0");
        h.Sim.Motor(1).Machine.Should().BeApproximately(-3000 + 50, 1e-9);
        h.Sim.Motor(1).HomeComplete.Should().BeTrue();
    }

    [Fact]
    public void Homing_again_clears_Home_Complete_until_the_trigger()
    {
        using var h = new SimHarness(Unhomed(1000));
        h.Ok("I119=100 I121=1 #1HM");
        h.Sim.RunUntilIdle();
        h.Sim.Motor(1).HomeComplete.Should().BeTrue();
        h.Ok("#1J:-5000");
        h.Sim.RunUntilIdle();
        h.Ok("#1HM");
        h.MotorBit(1, 2, 10).Should().BeFalse("a second homing move clears the bit at its start");
        h.Sim.RunUntilIdle();
        h.MotorBit(1, 2, 10).Should().BeTrue();
        h.Ok("#1P").Should().Be("0");
    }

    [Fact]
    public void A_search_started_past_the_switch_stops_on_the_travel_limit_unhomed_and_homes_after_jogging_back()
    {
        // The flag's edge is never seen from beyond the switch: a real machine runs on to its overtravel switch.
        var o = new SimOptions { StartHomed = false };
        o.MotorSettings[1] = new MotorSettings { HomeSwitchPosition = 0, PlusLimitPosition = 3000, MinusLimitPosition = -3000 };
        using var h = new SimHarness(o);
        h.Ok("#1J:10");
        h.Sim.RunUntilIdle();
        h.Ok("#1HM");
        h.Sim.RunUntilIdle();
        h.Sim.Motor(1).Machine.Should().BeInRange(3000, 3100, "it stops just past the + limit switch (a servo step at the home speed), not for ever");
        h.Sim.Motor(1).HomeComplete.Should().BeFalse("the switch was never found");
        h.Sim.Motor(1).StoppedOnLimit.Should().BeTrue();
        h.Ok("#1J:-3100");
        h.Sim.RunUntilIdle();
        h.Ok("#1HM");
        h.Sim.RunUntilIdle();
        h.Sim.Motor(1).HomeComplete.Should().BeTrue("approached from the search's side, the switch is found");
        h.Sim.Motor(1).Machine.Should().BeApproximately(0, 1e-6);
    }

    [Fact]
    public void HMZ_declares_the_present_position_home_without_moving()
    {
        using var h = new SimHarness(new SimOptions { StartHomed = false });
        h.Ok("I119=100 I121=1 #1J:1234");
        h.Sim.RunUntilIdle();
        h.Ok("#1HMZ");
        h.Ok("#1P").Should().Be("0");
        h.Sim.Motor(1).Machine.Should().Be(1234);
        h.MotorBit(1, 2, 10).Should().BeTrue();
    }

    [Fact]
    public void A_program_after_homing_moves_from_the_home_position()
    {
        using var h = new SimHarness(Unhomed(5000));
        h.Ok("#1->1000X");
        h.Ok("I123=50 I119=100 I121=1 #1HM");
        h.Sim.RunUntilIdle();
        h.Ok("&1 OPEN PROG 1 CLEAR LINEAR INC F600 X2 CLOSE B1 R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves[^1].X.Should().BeApproximately(2, 1e-9, "the axis starts from the homed zero");
        h.Ok("#1P").Should().Be("2000");
        h.Sim.Motor(1).Machine.Should().BeApproximately(7000, 1e-6);
    }
}
