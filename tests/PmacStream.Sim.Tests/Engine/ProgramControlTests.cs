namespace PmacStream.Sim.Tests.Engine;

public class ProgramControlTests
{
    private static SimHarness Loaded(SimOptions? options = null, int moves = 5)
    {
        var h = new SimHarness(options);
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F600");
        for (var i = 1; i <= moves; i++)
        {
            h.Ok($"M0=={i} X{i * 10}");
        }

        h.Ok("CLOSE");
        return h;
    }

    [Fact]
    public void Feed_override_slews_rather_than_jumps()
    {
        using var h = Loaded(new SimOptions { OverrideSlewPercentPerSecond = 100 });
        h.Ok("%50");
        h.Ok("%").Should().Be("100", "the override has not slewed yet");
        h.Ok("R");
        h.Advance(0.25);
        h.Ok("%").Should().Be("75");
        h.Advance(0.25);
        h.Ok("%").Should().Be("50");
        h.Sim.RunUntilIdle();
        // Move 1: 0.5 s slewing 100->50 covers 0.375 s of program time; the rest 0.625 at half speed = 1.25 s.
        h.Sim.ExecutedMoves[0].Duration.Should().BeApproximately(1.75, 1e-6);
        h.Sim.ExecutedMoves[1].Duration.Should().BeApproximately(2.0, 1e-6);
    }

    [Fact]
    public void Hold_slews_to_a_stop_and_run_resumes()
    {
        using var h = Loaded(new SimOptions { OverrideSlewPercentPerSecond = 1e9 });
        h.Ok("R");
        h.Advance(0.5);
        h.Ok("H");
        h.Advance(0.001);
        var x = h.Sim.Position()[0];
        x.Should().BeApproximately(5, 1e-3);
        h.Advance(10);
        h.Sim.Position()[0].Should().Be(x, "held: no motion");
        h.Sim.IsRunning().Should().BeTrue();
        h.Sim.RunUntilIdle().Should().Be(TimeSpan.Zero, "held motion cannot progress");
        h.Ok("R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Should().HaveCount(5);
        h.Sim.ExecutedMoves[0].Duration.Should().BeApproximately(11.0, 1e-3);
    }

    [Fact]
    public void Quit_stops_after_the_calculated_moves_and_run_continues()
    {
        using var h = Loaded(moves: 8);
        h.Ok("R");
        h.Advance(0.5);
        h.Ok("Q");
        h.Sim.RunUntilIdle();
        h.Sim.IsRunning().Should().BeFalse();
        h.Sim.ExecutedMoves.Select(m => m.SourceLine).Should().Equal(1, 2, 3);
        h.Ok("R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Select(m => m.SourceLine).Should().Equal(1, 2, 3, 4, 5, 6, 7, 8);
    }

    [Fact]
    public void Step_runs_one_move()
    {
        using var h = Loaded();
        h.Ok("S");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Should().HaveCount(1);
        h.Sim.IsRunning().Should().BeFalse();
        h.Ok("S");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Select(m => m.X).Should().Equal(10, 20);
    }

    [Fact]
    public void Abort_stops_where_the_axes_are_and_drops_calculated_moves()
    {
        using var h = Loaded();
        h.Ok("R");
        h.Advance(1.5);
        h.Ok("A");
        h.Sim.IsRunning().Should().BeFalse();
        h.Sim.Position()[0].Should().BeApproximately(15, 1e-9);
        h.Ok("#1P").Should().Be("15");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Should().HaveCount(1);
        h.Ok("K");
    }

    [Fact]
    public void Program_buffers_with_labels_call_gosub_goto_read_and_return()
    {
        using var h = new SimHarness();
        h.Download(
            "OPEN PROG 20 CLEAR",
            "N0 READ(X,Y,F) P10=Q100 LINEAR ABS F(Q106) X(Q124) Y(Q125) RET",
            "N500 P11=P11+1 RET",
            "CLOSE",
            "OPEN PROG 1 CLEAR",
            "P11=0",
            "CALL 20 X10 Y20 F600",
            "GOSUB 100",
            "GOSUB 100",
            "GOTO 200",
            "P12=99",
            "N200 CALL 20.005",
            "CALL 20.005",
            "RET",
            "N100 P13=P13+1 RET",
            "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Should().ContainSingle();
        var m = h.Sim.ExecutedMoves[0];
        (m.X, m.Y).Should().Be((10, 20));
        m.Duration.Should().BeApproximately(Math.Sqrt(500) / 10, 1e-9);
        h.Sim.ReadVariable('P', 10).Should().Be((1 << ('X' - 'A')) | (1 << ('Y' - 'A')) | (1 << ('F' - 'A')));
        h.Sim.ReadVariable('P', 11).Should().Be(2, "CALL 20.005 jumps to N500");
        h.Sim.ReadVariable('P', 12).Should().Be(0, "GOTO skipped it");
        h.Sim.ReadVariable('P', 13).Should().Be(2);
        h.Sim.IsRunning().Should().BeFalse("RET at the top level ends the program");
        h.Ok("??")[5].Should().Be('0');
    }

    [Fact]
    public void If_else_and_while_in_a_motion_program()
    {
        using var h = new SimHarness();
        h.Download(
            "OPEN PROG 2 CLEAR",
            "LINEAR INC F600 P1=0",
            "WHILE (P1<3)",
            "  X10",
            "  P1=P1+1",
            "ENDWHILE",
            "IF (P1=3 AND P2=0)",
            "  Y5",
            "ELSE",
            "  Y-5",
            "ENDIF",
            "IF (P1!=3) P3=1",
            "IF (P1>2) P4=1",
            "CLOSE");
        h.Ok("&1 B2 R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Select(m => (m.X, m.Y)).Should().Equal((10, 0), (20, 0), (30, 0), (30, 5));
        h.Sim.ReadVariable('P', 3).Should().Be(0);
        h.Sim.ReadVariable('P', 4).Should().Be(1);
    }

    [Fact]
    public void Missing_g_code_labels_and_libraries_are_ignored_silently()
    {
        using var h = new SimHarness();
        h.Ok("&1 B0 OPEN ROT G17 G99 M08 T1 D1 LINEAR F600 X10 CLOSE R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Should().ContainSingle().Which.X.Should().Be(10);
        h.Sim.Counters.Errors.Should().Be(0);
        h.Download("OPEN PROG 1002 CLEAR", "N1000 P20=P20+1 RET", "CLOSE");
        h.Ok("OPEN ROT T1 CLOSE");
        h.Sim.RunUntilIdle();
        h.Sim.ReadVariable('P', 20).Should().Be(1);
        h.Ok("OPEN ROT T1.5 T1 CLOSE");
        h.Sim.RunUntilIdle();
        h.Sim.ReadVariable('P', 20).Should().Be(2, "T1.5 is label 1500: missing, ignored; T1 ran N1000");
    }

    [Fact]
    public void Opening_a_running_program_is_refused()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 3 CLEAR", "LINEAR F60 X100", "CLOSE");
        h.Ok("&1 B3 R");
        h.Send("OPEN PROG 3").Should().Be("<BEL>ERR001<CR>");
        h.Send("B3").Should().Be("<BEL>ERR001<CR>");
        h.Ok("A B3");
    }

    [Fact]
    public void Clock_thread_in_instant_mode_runs_lines_as_they_arrive()
    {
        using var h = new SimHarness(new SimOptions { Speed = SimSpeed.Instant });
        h.Sim.StartClock();
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F600 X10 X20 Y5");
        h.Ok("R");
        h.Ok("X30");
        var deadline = DateTime.UtcNow.AddSeconds(20);
        while (h.Sim.ExecutedMoves.Count < 2 && DateTime.UtcNow < deadline)
        {
            Thread.Sleep(5);
        }

        h.Sim.StopClock();
        h.Sim.ExecutedMoves.Select(m => m.X).Should().Equal(20, 30);
        h.Sim.Now.Should().BeGreaterThanOrEqualTo(h.Sim.ExecutedMoves[^1].EndTime);
    }

    [Fact]
    public void Move_executed_event_reports_every_move_in_order()
    {
        using var h = Loaded();
        var seen = new List<long>();
        h.Sim.MoveExecuted += m => seen.Add(m.Sequence);
        h.Ok("R");
        h.Sim.RunUntilIdle();
        seen.Should().Equal(1, 2, 3, 4, 5);
    }

    [Fact]
    public void Speed_parses_the_cli_forms()
    {
        SimSpeed.Parse("realtime").Should().Be(SimSpeed.Realtime);
        SimSpeed.Parse("instant").IsInstant.Should().BeTrue();
        SimSpeed.Parse("50x").Multiplier.Should().Be(50);
        SimSpeed.Factor(2.5).ToString().Should().Be("2.5x");
        var act = () => SimSpeed.Parse("fast");
        act.Should().Throw<FormatException>();
    }
}
