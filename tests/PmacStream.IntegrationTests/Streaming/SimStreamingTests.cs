using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

public class SimStreamingTests
{
    [Theory]
    [InlineData(StrategyKind.Chunk, 1000, 2.0)]
    [InlineData(StrategyKind.Chunk, 300, 0.5)]
    [InlineData(StrategyKind.Pr, 1000, 1.0)]
    [InlineData(StrategyKind.Adaptive, 500, 1.0)]
    public async Task Demo_program_executes_every_block_once_in_order_on_the_simulator(StrategyKind strategy, int chunkLines, double secondsPerTick)
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, chunkLines, new StreamingOptions { Strategy = strategy, BufferWords = 20_000 });
        await rig.Session.StartAsync();
        (await rig.RunAsync(secondsPerTick)).Should().BeTrue(rig.Session.Status.Message);

        var expected = rig.Program.TrackedLines().ToList();
        expected.Should().HaveCount(rig.Program.Manifest.TotalMotionBlocks);
        rig.ExecutedLines().Should().Equal(expected);
    }
}

public class SimDownloadOnceTests
{
    [Theory]
    [InlineData(1000, 0.6, 0.7, 1.0)]
    [InlineData(400, 0.3, 0.4, 0.5)]
    public async Task Each_next_chunk_is_downloaded_exactly_once_inside_its_window_on_the_simulator(int chunkLines, double w0, double w1, double secondsPerTick)
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, chunkLines, new StreamingOptions { Strategy = StrategyKind.Chunk, WindowStart = w0, WindowEnd = w1, BufferWords = 20_000 });
        var downloads = new List<(StreamingEvent Event, int PortLinesBefore)>();
        rig.Session.EventRaised += (_, e) =>
        {
            if (e.Kind is StreamingEventKind.ChunkDownloaded or StreamingEventKind.ChunkDownloadedLate)
            {
                downloads.Add((e, 0));
            }
        };
        await rig.Session.StartAsync();
        (await rig.RunAsync(secondsPerTick)).Should().BeTrue();

        downloads.Select(d => d.Event.Chunk).Should().Equal(Enumerable.Range(1, rig.Program.TotalChunks), "chunk k+1 once per window, in order");
        downloads.Should().NotContain(d => d.Event.Kind == StreamingEventKind.ChunkDownloadedLate);
        foreach (var (e, _) in downloads.Skip(1))
        {
            var prev = rig.Program.Chunk(e.Chunk - 1);
            var pos = (double)(e.TrackedLine - prev.FirstSourceLine + 1) / (prev.LastSourceLine - prev.FirstSourceLine + 1);
            pos.Should().BeInRange(w0, w1 + 0.05, $"chunk {e.Chunk}: never early, in the window of chunk {e.Chunk - 1}");
        }

        rig.Sim.Counters.LinesReceived.Should().BeGreaterThan(0);
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines());
        rig.Sim.Counters.Underruns.Should().Be(0, "on-time downloads never let the buffer run dry");
    }

    [Fact]
    public async Task Paper_tracking_placement_lags_one_line_behind_exact_on_the_simulator()
    {
        var opts = new StreamingOptions { BufferWords = 20_000 };
        using var exact = new SimRig(RepoRoot.DemoProgram, 1000, opts, TrackingPlacement.Exact);
        using var paper = new SimRig(RepoRoot.DemoProgram, 1000, opts, TrackingPlacement.Paper);
        await exact.Session.StartAsync();
        await paper.Session.StartAsync();
        (await exact.RunAsync(2.0)).Should().BeTrue();
        (await paper.RunAsync(2.0)).Should().BeTrue(paper.Session.Status.Message);

        var lines = exact.Program.TrackedLines().ToList();
        exact.ExecutedLines().Should().Equal(lines, "M0==n before the move names the executing block");
        // Paper: M0==n after the words is written at the start of the next move, so each move reports the block before it.
        var paperMoves = paper.Sim.ExecutedMoves.Where(m => m.Kind != MoveKind.Dwell || m.Duration > 0).Select(m => m.SourceLine).ToList();
        var exactMoves = exact.Sim.ExecutedMoves.Where(m => m.Kind != MoveKind.Dwell || m.Duration > 0).Select(m => m.SourceLine).ToList();
        paperMoves.Should().HaveCount(exactMoves.Count);
        paperMoves.Skip(1).Should().Equal(exactMoves.Take(exactMoves.Count - 1), "paper placement lags exactly one block");
    }
}
