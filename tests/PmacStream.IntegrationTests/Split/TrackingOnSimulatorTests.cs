using PmacStream.GCode;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;

namespace PmacStream.IntegrationTests.Split;

/// <summary>
/// The splitter's chunks and PROG 1000/1001 library run on the simulated PMAC: one executed move per counted motion
/// block, and the tracking placement proven — exact reports the executing move's own line, the Paper placement
/// reports the previous motion line (the move of line i runs while M0 still holds the line before it).
/// </summary>
public sealed class TrackingOnSimulatorTests : IDisposable
{
    private readonly TestFolder _temp = new("split-sim");

    public void Dispose() => _temp.Dispose();

    private static async Task<(SplitResult Split, IReadOnlyList<ExecutedMove> Moves)> RunAsync(string source, string outDir, TrackingPlacement tracking)
    {
        var split = Splitter.Split(source, new SplitOptions { OutDir = outDir, Tracking = tracking, AllowErrors = true });
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Instant });
        using var port = sim.OpenPort("split-test");
        var conn = new InProcessConnection(port, "sim");
        await conn.DownloadAsync(SimRig.Library);

        await conn.GetResponseAsync("&1 DEFINE ROT 200000");
        await conn.GetResponseAsync("&1 B0");
        foreach (var chunk in split.ChunkPaths)
        {
            await conn.DownloadAsync(File.ReadAllText(chunk).Split("\r\n", StringSplitOptions.RemoveEmptyEntries));
        }

        await conn.GetResponseAsync("&1 R");
        sim.RunUntilIdle(TimeSpan.FromHours(10));
        return (split, sim.ExecutedMoves.ToList());
    }

    private static List<int> MotionLines(string path)
    {
        var lines = new List<int>();
        foreach (var b in GCodeReader.ReadAll(path))
        {
            var motion = b.Words.Any(w => "XYZABC".Contains(w.Letter)) || b.Words.Any(w => w.Letter == 'G' && w.CodeTimesTen == 40);
            if (motion && !b.IsTapeMark)
            {
                lines.Add(b.LineNumber);
            }
        }

        return lines;
    }

    [Fact]
    public async Task Exact_tracking_reports_the_executing_line_and_paper_tracking_the_line_before()
    {
        var source = Path.Combine(_temp.Path, "p.nc");
        File.WriteAllText(source, string.Join('\n',
            "%", "O1 (TRACK)", "G21 G17 G90", "S1000 M03", "G00 X10 Y0", "G01 Z-1 F300", "(ARC)", "G02 X0 Y10 I-10 J0",
            "G04 P100", "G03 X-10 Y0 I0 J-10", "G01 X0 Y0", "N99 G00 Z5", "M05", "M30", "%") + "\n");
        var motion = MotionLines(source);
        motion.Should().Equal(5, 6, 8, 9, 10, 11, 12);

        var exact = await RunAsync(source, Path.Combine(_temp.Path, "exact"), TrackingPlacement.Exact);
        Folded(exact.Moves).Should().Equal(motion, "M0==i before the move of line i: every move reports its own line");
        Folded(exact.Moves).Should().HaveCount(exact.Split.Manifest.TotalMotionBlocks);

        // Same program, same moves; only the marker moved to the end of the line. Where the exact run starts the
        // move of motion line i, the paper run still reports the motion line before it.
        var paper = await RunAsync(source, Path.Combine(_temp.Path, "paper"), TrackingPlacement.Paper);
        paper.Moves.Should().HaveCount(exact.Moves.Count);
        var checkedMoves = 0;
        for (var k = 0; k < exact.Moves.Count; k++)
        {
            var line = exact.Moves[k].SourceLine;
            if (line > 0 && (k == 0 || exact.Moves[k - 1].SourceLine != line))
            {
                var j = motion.IndexOf(line);
                paper.Moves[k].SourceLine.Should().Be(j == 0 ? 0 : motion[j - 1], $"the move of line {line} under paper tracking");
                checkedMoves++;
            }
        }

        checkedMoves.Should().Be(motion.Count);
    }

    /// <summary>Source lines of the executed moves, consecutive repeats folded and 0 (before any marker) left out, as the demo counts.</summary>
    private static List<int> Folded(IReadOnlyList<ExecutedMove> moves)
    {
        var list = new List<int>();
        foreach (var m in moves)
        {
            if (m.SourceLine > 0 && (list.Count == 0 || list[^1] != m.SourceLine))
            {
                list.Add(m.SourceLine);
            }
        }

        return list;
    }

    [Fact]
    public async Task Demo_sample_executes_one_move_per_counted_motion_block()
    {
        var sample = RepoRoot.DemoProgram;
        var run = await RunAsync(sample, Path.Combine(_temp.Path, "demo"), TrackingPlacement.Exact);
        Folded(run.Moves).Should().HaveCount(run.Split.Manifest.TotalMotionBlocks, "pmacstream demo prints executed N of N from these two numbers");
        Folded(run.Moves).Should().Equal(MotionLines(sample));
    }
}
