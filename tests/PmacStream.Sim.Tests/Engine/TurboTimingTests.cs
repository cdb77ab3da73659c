namespace PmacStream.Sim.Tests.Engine;

/// <summary>
/// The simulator's move times as a Turbo PMAC's (issue 28, docs/turbo-pmac-timing.md): the acceleration time (TA, or
/// 2 TS when TS is more than TA/2) is the shortest a blended move takes, 0.5 ms when TA and TS are both 0 (Turbo SRM
/// p. 188), and a blended sequence that starts from rest pays one acceleration time.
/// </summary>
public class TurboTimingTests
{
    private static SimHarness Run(SimOptions? options, params string[] lines)
    {
        var h = new SimHarness(options);
        h.Download(["&1 B0", "OPEN ROT", .. lines, "CLOSE"]);
        h.Ok("&1R");
        h.Sim.RunUntilIdle();
        return h;
    }

    [Fact]
    public void With_TA_and_TS_0_a_blended_move_takes_at_least_half_a_millisecond_so_at_most_2000_blocks_a_second()
    {
        // 0.01 mm at 6000 mm/min would be 0.1 ms.
        var lines = Enumerable.Range(1, 100).Select(i => $"M0=={i} LINEAR X{i * 0.01:0.00} F6000").ToArray();
        using var h = Run(null, lines);
        var moves = h.Sim.ExecutedMoves;
        moves.Should().HaveCount(100);
        moves.Should().OnlyContain(m => Math.Abs(m.Duration - 0.0005) < 1e-9);
        moves[^1].EndTime.Should().BeApproximately(0.05, 1e-9, "100 blocks at the 0.5 ms floor: 2,000 blocks/s");
        moves.Select(m => m.SourceLine).Should().Equal(Enumerable.Range(1, 100), "every block once, in order");
    }

    [Fact]
    public void The_acceleration_time_is_the_least_move_time_and_a_sequence_from_rest_pays_it_once()
    {
        // TA 50: 1 mm at 600 mm/min is 100 ms (longer than TA), 0.1 mm is 10 ms (done in 50 ms instead).
        using var h = Run(null, "TA50", "M0==1 LINEAR X1 F600", "M0==2 X1.1", "M0==3 X2.1");
        var moves = h.Sim.ExecutedMoves;
        moves.Select(m => m.Duration).Should().Equal([0.1 + 0.05, 0.05, 0.1], (a, b) => Math.Abs(a - b) < 1e-9,
            "the first move starts from rest (+TA); the short one takes TA; the last one blends on");
        moves[^1].EndTime.Should().BeApproximately(0.3, 1e-9, "sum of move times plus one acceleration time");
    }

    [Fact]
    public void An_S_curve_time_over_half_TA_makes_the_acceleration_twice_TS()
    {
        using var h = Run(null, "TA10 TS20", "M0==1 LINEAR X0.01 F600", "M0==2 X0.02");
        var moves = h.Sim.ExecutedMoves;
        moves[1].Duration.Should().BeApproximately(0.04, 1e-9, "2 x TS = 40 ms, more than TA's 10 ms");
    }

    [Fact]
    public void A_dwell_breaks_the_blend_and_the_next_move_starts_from_rest_again()
    {
        using var h = Run(null, "TA20", "M0==1 LINEAR X1 F600", "DWELL10", "M0==2 X2");
        var moves = h.Sim.ExecutedMoves;
        moves.Select(m => m.Kind).Should().Equal(MoveKind.Linear, MoveKind.Dwell, MoveKind.Linear);
        moves[0].Duration.Should().BeApproximately(0.12, 1e-9);
        moves[2].Duration.Should().BeApproximately(0.12, 1e-9, "after the dwell the axes start from rest");
    }

    [Fact]
    public void The_power_on_acceleration_comes_from_Isx87_and_Isx88_and_rapids_keep_their_speed()
    {
        using var h = Run(new SimOptions { AccelerationTimeMs = 30 }, "M0==1 RAPID X10", "M0==2 LINEAR X10.01 F600");
        var moves = h.Sim.ExecutedMoves;
        moves[0].Duration.Should().BeApproximately(10.0 / 5000 * 60, 1e-9, "rapids are not blended moves");
        moves[1].Duration.Should().BeApproximately(0.03 + 0.03, 1e-9, "Isx87 = 30 ms: the least move time, and the start from rest");
    }
}
