namespace PmacStream.Sim.Tests.Engine;

public class MotionTests
{
    internal static readonly string[] Library =
    [
        "OPEN PROG 1000 CLEAR",
        "N0 RAPID RET",
        "N1000 LINEAR RET",
        "N2000 CIRCLE1 RET",
        "N3000 CIRCLE2 RET",
        "N4000 READ(P) DWELL(Q116) RET",
        "N17000 NORMAL K-1 RET",
        "N90000 ABS RET",
        "N91000 INC RET",
        "CLOSE",
        "OPEN PROG 1001 CLEAR",
        "N3000 M1=1 RET",
        "N5000 DWELL0 M1=0 RET",
        "CLOSE",
    ];

    private static SimHarness WithLibrary(SimOptions? options = null)
    {
        var h = new SimHarness(options);
        h.Download(Library);
        h.Ok("P500=600");
        return h;
    }

    [Fact]
    public void Streamed_program_through_the_library_executes_the_expected_path()
    {
        using var h = WithLibrary();
        h.Download(
            "&1 B0",
            "OPEN ROT",
            "G90 G17",
            "M0==1 G00 X10 Y0",
            "M0==2 F(P500) G01 X20 Y0",
            "M0==3 G02 X30 Y0 I5 J0",
            "M0==4 G03 X20 Y0 R5",
            "M0==5 G04 P500",
            "M0==6 G91 G01 X5 Y5",
            "M0==7 G90 G03 X25 Y-5 R5",
            "M0==8 M03",
            "M0==9 G01 Z-1",
            "M0==10 M05",
            "CLOSE");
        h.Ok("&1R");
        h.Sim.RunUntilIdle();

        var moves = h.Sim.ExecutedMoves;
        moves.Select(m => m.SourceLine).Should().Equal(1, 2, 3, 4, 5, 6, 7, 9, 10);
        moves.Select(m => m.Kind).Should().Equal(
            MoveKind.Rapid, MoveKind.Linear, MoveKind.Circle1, MoveKind.Circle2, MoveKind.Dwell, MoveKind.Linear,
            MoveKind.Circle2, MoveKind.Linear, MoveKind.Dwell);

        // Rapid: 10 units at the rapid feed (5000/min).
        moves[0].Should().Match<ExecutedMove>(m => m.X == 10 && m.Y == 0 && m.StartTime == 0);
        moves[0].Duration.Should().BeApproximately(10.0 / 5000 * 60, 1e-9);

        // Linear at F(P500)=600 units/min: 10 units take 1 s.
        moves[1].Duration.Should().BeApproximately(1.0, 1e-9);

        // CW half circle centre (25,0) r 5: length 5*pi.
        moves[2].CenterX.Should().BeApproximately(25, 1e-9);
        moves[2].CenterY.Should().BeApproximately(0, 1e-9);
        moves[2].Radius.Should().BeApproximately(5, 1e-9);
        moves[2].Duration.Should().BeApproximately(5 * Math.PI / 600 * 60, 1e-9);
        moves[2].X.Should().Be(30);

        // R form half circle back.
        moves[3].CenterX.Should().BeApproximately(25, 1e-9);
        moves[3].X.Should().Be(20);

        // G04 P500: READ(P) into Q116, DWELL 500 ms.
        moves[4].Duration.Should().BeApproximately(0.5, 1e-9);
        moves[4].StartTime.Should().BeApproximately(moves[3].EndTime, 1e-9);

        // G91 incremental.
        moves[5].X.Should().Be(25);
        moves[5].Y.Should().Be(5);

        // Quarter circle CCW from (25,5)? No: from (25,5) to (25,-5) with R5 is a half circle; centre (25,0).
        moves[6].CenterX.Should().BeApproximately(25, 1e-9);
        moves[6].CenterY.Should().BeApproximately(0, 1e-9);

        // M03 is a call with no motion; M05 is DWELL0 then M1=0.
        moves[7].Z.Should().Be(-1);
        moves[8].Duration.Should().Be(0);
        h.M(1).Should().Be(0);
        h.Sim.ReadVariable('Q', 116).Should().Be(500);

        // Timeline is continuous and ordered.
        for (var i = 1; i < moves.Count; i++)
        {
            moves[i].StartTime.Should().BeApproximately(moves[i - 1].EndTime, 1e-9);
            moves[i].Sequence.Should().Be(moves[i - 1].Sequence + 1);
        }

        h.Sim.Counters.MovesExecuted.Should().Be(9);
        h.Sim.Counters.Underruns.Should().Be(0, "the buffer was closed: the program was at its end");
    }

    [Fact]
    public void Quarter_arc_by_radius_picks_the_short_side_centre()
    {
        using var h = WithLibrary();
        h.Download("&1 B0", "OPEN ROT", "F600 ABS LINEAR X20 Y0", "CIRCLE2 X25 Y-5 R5", "CIRCLE2 X20 Y0 R-5", "CLOSE");
        h.Ok("R");
        h.Sim.RunUntilIdle();
        var arc = h.Sim.ExecutedMoves[1];
        arc.CenterX.Should().BeApproximately(25, 1e-9);
        arc.CenterY.Should().BeApproximately(0, 1e-9);
        arc.Length.Should().BeApproximately(Math.PI * 5 / 2, 1e-9);
        var big = h.Sim.ExecutedMoves[2];
        big.Length.Should().BeApproximately(Math.PI * 5 * 1.5, 1e-9, "a negative R takes the arc longer than 180 degrees");
    }

    [Fact]
    public void An_arc_whose_end_is_off_its_circle_runs_as_a_spiral_to_the_programmed_end()
    {
        // Turbo SRM (CIRCLE1/CIRCLE2): a destination at another distance from the centre than the start changes the
        // radius smoothly over the move; the host sends arcs inside the profile's arc tolerance so (issue 27).
        using var h = WithLibrary();
        h.Download("&1 B0", "OPEN ROT", "F600 ABS LINEAR X10 Y0", "CIRCLE2 X-10.5 Y0 I-10 J0", "CLOSE");
        h.Ok("R");
        var radii = new List<double>();
        for (var i = 0; i < 60; i++)
        {
            h.Advance(0.1);
            var p = h.Sim.Position();
            if (p[1] > 1e-6)
            {
                radii.Add(Math.Sqrt((p[0] * p[0]) + (p[1] * p[1])));
            }
        }

        radii.Should().NotBeEmpty();
        radii.Should().OnlyContain(r => r >= 10 - 1e-9 && r <= 10.5 + 1e-9, "between the start and end radii");
        radii.Should().Contain(r => r > 10.1 && r < 10.4, "the radius grows along the way, not at the end");
        h.Sim.RunUntilIdle();
        var end = h.Sim.Position();
        end[0].Should().BeApproximately(-10.5, 1e-9);
        end[1].Should().BeApproximately(0, 1e-9);
    }

    [Fact]
    public void Full_circle_with_ijk_and_helix()
    {
        using var h = WithLibrary();
        h.Download("&1 B0", "OPEN ROT", "F600 ABS LINEAR X10 Y0", "CIRCLE1 X10 Y0 Z3 I-10 J0", "CLOSE");
        h.Ok("R");
        h.Sim.RunUntilIdle();
        var arc = h.Sim.ExecutedMoves[1];
        arc.Radius.Should().BeApproximately(10, 1e-9);
        arc.CenterX.Should().BeApproximately(0, 1e-9);
        arc.Length.Should().BeApproximately(Math.Sqrt(Math.Pow(20 * Math.PI, 2) + 9), 1e-9);
        arc.Z.Should().Be(3);
    }

    [Theory]
    [InlineData(true)]
    [InlineData(false)]
    public void Synchronous_and_immediate_M0_differ_by_the_lookahead(bool synchronous)
    {
        using var h = new SimHarness(new SimOptions { LookaheadMoves = 2 });
        var op = synchronous ? "==" : "=";
        h.Download("&1 B0", "OPEN ROT", "LINEAR ABS F600");
        for (var i = 1; i <= 6; i++)
        {
            h.Download($"M0{op}{i} X{i * 10}");
        }

        h.Download("CLOSE");
        h.Ok("&1R");
        var seen = new List<double>();
        for (var i = 1; i <= 6; i++)
        {
            // Read M0 from the host in the middle of move i (each move takes 1 s).
            h.Advance(i == 1 ? 0.5 : 1.0);
            h.Ok("M0").Should().Be(h.M(0).ToString(System.Globalization.CultureInfo.InvariantCulture));
            seen.Add(h.M(0));
        }

        if (synchronous)
        {
            seen.Should().Equal(1, 2, 3, 4, 5, 6);
        }
        else
        {
            // Calculated two moves ahead of the executing one, capped by the end of the program.
            seen.Should().Equal(3, 4, 5, 6, 6, 6);
        }

        h.Sim.RunUntilIdle();
        // The log takes M0 at the instant a move starts, before the lookahead refills: one line ahead already.
        h.Sim.ExecutedMoves.Select(m => m.SourceLine).Should().Equal(synchronous ? [1, 2, 3, 4, 5, 6] : new[] { 2, 3, 4, 5, 6, 6 });
    }

    [Fact]
    public void Lookahead_is_configurable()
    {
        using var h = new SimHarness(new SimOptions { LookaheadMoves = 4 });
        h.Download("&1 B0", "OPEN ROT", "LINEAR ABS F600");
        for (var i = 1; i <= 8; i++)
        {
            h.Download($"M0={i} X{i * 10}");
        }

        h.Ok("R");
        h.Advance(0.5);
        h.M(0).Should().Be(5);
    }

    [Fact]
    public void Dwell_stops_lookahead_so_a_following_assignment_waits_for_the_motion()
    {
        using var h = new SimHarness();
        h.Download("&1 B0", "OPEN ROT", "LINEAR ABS F600 X10", "DWELL0", "P1=1", "X20", "CLOSE");
        h.Ok("R");
        h.Sim.ReadVariable('P', 1).Should().Be(0);
        h.Advance(0.9);
        h.Sim.ReadVariable('P', 1).Should().Be(0);
        h.Advance(0.2);
        h.Sim.ReadVariable('P', 1).Should().Be(1);

        using var d = new SimHarness();
        d.Download("&1 B0", "OPEN ROT", "LINEAR ABS F600 X10", "DELAY0", "P1=1", "X20", "CLOSE");
        d.Ok("R");
        d.Sim.ReadVariable('P', 1).Should().Be(1, "DELAY does not stop the calculation ahead");
    }

    [Fact]
    public void Feed_time_unit_and_tm_set_move_time()
    {
        using var h = new SimHarness(new SimOptions { FeedTimeUnitMs = 1000 });
        h.Download("&1 B0", "OPEN ROT", "LINEAR ABS F10 X10", "TM250 X20", "F5 X30", "CLOSE");
        h.Ok("R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Select(m => Math.Round(m.Duration, 9)).Should().Equal(1.0, 0.25, 2.0);
    }

    [Fact]
    public void Executed_log_csv_has_the_documented_header_and_rows()
    {
        using var h = WithLibrary();
        h.Download("&1 B0", "OPEN ROT", "M0==7 F(P500) G01 X10", "M0==8 G04 P250", "M0==9 G00 A90 B-45.5", "CLOSE");
        h.Ok("R");
        h.Sim.RunUntilIdle();
        using var folder = new TestFolder("simlog");
        var path = Path.Combine(folder.Path, "executed.csv");
        h.Sim.WriteExecutedLog(path);
        var rows = File.ReadAllLines(path);
        rows.Take(3).Should().Equal(
            "sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block",
            "1,7,0,1,10,0,0,0,0,0,Linear,1",
            "2,8,1,1.25,10,0,0,0,0,0,Dwell,1");
        var rotary = rows.Should().HaveCount(4).And.Subject.Last().Split(',');
        string.Join(',', rotary[1], rotary[4], rotary[5], rotary[6], rotary[7], rotary[8], rotary[9], rotary[10], rotary[11]).Should().Be("9,10,0,0,90,-45.5,0,Rapid,1", "a, b, c are the rotary axes' ends");
    }
}
