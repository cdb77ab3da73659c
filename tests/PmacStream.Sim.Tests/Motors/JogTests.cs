
namespace PmacStream.Sim.Tests.Motors;

/// <summary>Jog commands on the virtual clock: speed Ixx22, acceleration from Ixx19/Ixx20/Ixx21 (docs/turbo-pmac-motors.md).</summary>
public class JogTests
{
    [Fact]
    public void J_plus_runs_at_the_jog_speed_and_J_slash_stops_it()
    {
        using var h = new SimHarness();
        h.Ok("I122=10 I119=10 I120=10 I121=0"); // 10 counts/ms, reached in 10 ms
        h.Ok("#1J+");
        h.Advance(1);
        h.Sim.Motor(1).Velocity.Should().BeApproximately(10_000, 1e-6, "counts/s at the jog speed");
        h.Number("#1P").Should().BeApproximately(10_000 - 50, 1, "1 s at 10 counts/ms less half the 10 ms ramp");
        h.Number("#1V").Should().BeApproximately(10 * 3713991 / 8388608.0, 0.051, "V is counts per servo cycle (I10)");
        h.MotorBit(1, 1, 13).Should().BeFalse("desired velocity is not zero while jogging");
        h.MotorBit(1, 2, 0).Should().BeFalse("not in position while jogging");
        h.Ok("#1J/");
        h.Sim.RunUntilIdle();
        h.Sim.Motor(1).Moving.Should().BeFalse();
        h.Number("#1V").Should().Be(0);
        h.MotorBit(1, 1, 13).Should().BeTrue("desired velocity zero once stopped");
        h.MotorBit(1, 2, 0).Should().BeTrue("in position once stopped");
    }

    [Fact]
    public void J_colon_moves_the_distance_in_the_time_of_its_speed_and_acceleration()
    {
        using var h = new SimHarness();

        // Defaults: Ixx22 32 counts/ms; Ixx20 0 and Ixx21 50 ms give 100 ms to full speed, 320 counts/ms^2, which
        // Ixx19 (0.15625 counts/ms^2) caps: 204.8 ms of ramp. 100000 counts take 100000/32 ms + 204.8 ms.
        h.Ok("#1J:100000");
        var used = h.Sim.RunUntilIdle();
        used.TotalSeconds.Should().BeApproximately(3.125 + 0.2048, 0.01);
        h.Ok("#1P").Should().Be("100000");
        h.Sim.Motor(1).Moving.Should().BeFalse();
    }

    [Fact]
    public void J_equals_J_colon_J_caret_and_the_pre_jog_position()
    {
        using var h = new SimHarness();
        h.Ok("I119=100 I121=1");
        h.Ok("#1J=500");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("500");
        h.Ok("#1J:-200");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("300");
        h.Ok("#1J^50");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("350");
        h.Ok("#1J=");
        h.Sim.RunUntilIdle();
        h.Ok("#1P").Should().Be("0", "J= returns to where the motor was before its first jog");
    }

    [Fact]
    public void Several_motors_report_on_one_line_and_jog_independently()
    {
        using var h = new SimHarness();
        h.Ok("I119=100 I219=100 I121=1 I221=1");
        h.Ok("#1J:100 #2J:-40");
        h.Sim.RunUntilIdle();
        h.Ok("#1P#2P").Should().Be("100\n-40");
        h.Ok("#1F#2F").Should().Be("0\n0");
        h.Ok("#1V#2V").Should().Be("0\n0");
    }

    [Fact]
    public void Jogging_a_motor_of_a_running_program_is_refused()
    {
        using var h = new SimHarness();
        h.Ok("&1 OPEN PROG 1 CLEAR LINEAR ABS F600 X100 CLOSE B1 R");
        h.Advance(1);
        h.Send("#1J+").Should().Be("<BEL>ERR001<CR>");
        h.Send("#1HM").Should().Be("<BEL>ERR001<CR>");
        h.Send("#1K").Should().Be("<BEL>ERR001<CR>", "K is not permitted on a motor of a running program");
    }

    [Fact]
    public void Following_error_is_the_servo_lag_and_sets_the_warning_bit_over_Ixx12()
    {
        using var h = new SimHarness(new SimOptions { ServoLagMs = 10 });
        h.Ok("I112=1600 I119=100 I121=1"); // warning at 100 counts
        h.Ok("#1J+");
        h.Advance(0.5);
        h.Number("#1F").Should().BeApproximately(320, 1e-6, "32 counts/ms x 10 ms");
        h.Number("#1P").Should().BeApproximately(h.Sim.Motor(1).Commanded - 320, 1e-6);
        h.MotorBit(1, 2, 1).Should().BeTrue("warning following error");
        h.CsBit(2, 18).Should().BeTrue("the C.S. shows a motor's warning following error");
        h.Ok("#1J/");
        h.Sim.RunUntilIdle();
        h.MotorBit(1, 2, 1).Should().BeFalse();
        h.Ok("#1F").Should().Be("0");
    }

    [Fact]
    public void A_fatal_following_error_from_the_lag_kills_the_motor()
    {
        using var h = new SimHarness(new SimOptions { ServoLagMs = 10 });
        h.Ok("I111=3200 I119=100 I121=1"); // fatal at 200 counts
        h.Ok("#1J+");
        h.Advance(0.5);
        h.Sim.Motor(1).Enabled.Should().BeFalse();
        h.MotorBit(1, 2, 2).Should().BeTrue("fatal following error");
        h.MotorBit(1, 1, 18).Should().BeTrue("open loop");
        h.CsBit(2, 19).Should().BeTrue();
        h.Ok("#1J/");
        h.MotorBit(1, 2, 2).Should().BeFalse("re-enabling clears it");
        h.CsBit(2, 19).Should().BeFalse();
    }

    [Fact]
    public void PMATCH_moves_the_axis_to_where_its_motor_was_jogged()
    {
        using var h = new SimHarness();
        h.Ok("#1->1000X I119=100 I121=1 #1J:2500");
        h.Sim.RunUntilIdle();
        h.Sim.Position()[0].Should().Be(0, "the axis does not know of the jog yet");
        h.Ok("&1 PMATCH");
        h.Sim.Position()[0].Should().Be(2.5);
        h.Ok("#1P").Should().Be("2500");
    }
}
