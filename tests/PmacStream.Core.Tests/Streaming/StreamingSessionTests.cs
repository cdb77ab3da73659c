using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class StreamingSessionTests
{
    private static List<int> Raw(FakeRig rig) => rig.Controller.Moves.Select(m => m.SourceLine).ToList();

    [Theory]
    [InlineData(StrategyKind.Chunk, 50, 0.6, 0.7, 0.01)]
    [InlineData(StrategyKind.Chunk, 137, 0.2, 0.3, 0.002)]
    [InlineData(StrategyKind.Chunk, 1000, 0.85, 0.95, 0.005)]
    [InlineData(StrategyKind.Chunk, 333, 0.6, 0.7, 0.05)]
    [InlineData(StrategyKind.Pr, 100, 0.6, 0.7, 0.01)]
    [InlineData(StrategyKind.Pr, 1000, 0.6, 0.7, 0.001)]
    [InlineData(StrategyKind.Adaptive, 100, 0.6, 0.7, 0.01)]
    [InlineData(StrategyKind.Adaptive, 1000, 0.6, 0.7, 0.001)]
    [InlineData(StrategyKind.Adaptive, 77, 0.6, 0.7, 0.05)]
    public async Task Every_block_executes_exactly_once_in_order(StrategyKind strategy, int chunkLines, double w0, double w1, double moveSeconds)
    {
        using var temp = new TestFolder("exact");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(2500, chunkLines), chunkLines);
        var rig = new FakeRig(program, new StreamingOptions { Strategy = strategy, WindowStart = w0, WindowEnd = w1, BufferWords = 20_000 }, moveSeconds: moveSeconds, capacityWords: 20_000);
        await rig.Session.StartAsync();
        (await rig.RunAsync()).Should().BeTrue(rig.Session.Status.Message);

        var expected = program.TrackedLines().ToList();
        expected.Should().HaveCount(program.Manifest.TotalMotionBlocks);
        Raw(rig).Should().Equal(expected);
        rig.Controller.Violations.Should().BeEmpty("no online command may be stored in an open buffer");
        rig.Session.Status.ExecutedBlocks.Should().Be(expected.Count);
        rig.Session.Status.Percent.Should().Be(100);
    }

    [Theory]
    [InlineData(100, 0.6, 0.7)]
    [InlineData(250, 0.2, 0.3)]
    [InlineData(1000, 0.6, 0.7)]
    public async Task Chunk_strategy_downloads_each_next_chunk_once_inside_its_window_never_early(int chunkLines, double w0, double w1)
    {
        using var temp = new TestFolder("once");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(5000, 3), chunkLines);
        // Slow moves against a 50 ms tick: M0 passes through every window, so every download must be on time.
        var rig = new FakeRig(program, new StreamingOptions { Strategy = StrategyKind.Chunk, WindowStart = w0, WindowEnd = w1, BufferWords = 30_000 }, moveSeconds: 0.02, capacityWords: 30_000);
        var downloads = new List<StreamingEvent>();
        rig.Session.EventRaised += (_, e) =>
        {
            if (e.Kind is StreamingEventKind.ChunkDownloaded or StreamingEventKind.ChunkDownloadedLate)
            {
                downloads.Add(e);
            }
        };

        await rig.Session.StartAsync();
        (await rig.RunAsync()).Should().BeTrue();

        // Chunk 1 at start, then each chunk k+1 exactly once.
        downloads.Select(d => d.Chunk).Should().Equal(Enumerable.Range(1, program.TotalChunks));
        downloads.Should().NotContain(d => d.Kind == StreamingEventKind.ChunkDownloadedLate);
        foreach (var d in downloads.Skip(1))
        {
            var prev = program.Chunk(d.Chunk - 1);
            var size = prev.LastSourceLine - prev.FirstSourceLine + 1;
            var pos = (double)(d.TrackedLine - prev.FirstSourceLine + 1) / size;
            pos.Should().BeGreaterThanOrEqualTo(w0, $"chunk {d.Chunk} must not be downloaded before the window of chunk {d.Chunk - 1}");
            pos.Should().BeLessThanOrEqualTo(w1 + 0.02, $"chunk {d.Chunk} should be downloaded inside the window");
        }

        // Each chunk file went to the controller once: count OPEN ROT framing lines in the command log.
        // (The start clears the buffer once first: OPEN ROT, CLEAR, CLOSE.)
        var log = rig.Controller.Log;
        Enumerable.Range(0, log.Count - 1).Count(i => log[i].Equals("OPEN ROT", StringComparison.OrdinalIgnoreCase) && log[i + 1] != "CLEAR").Should().Be(program.TotalChunks);
        Enumerable.Range(0, log.Count - 1).Count(i => log[i] == "CLEAR").Should().Be(1);
        Raw(rig).Should().Equal(program.TrackedLines());
    }

    [Fact]
    public async Task A_missed_window_gives_one_late_download_and_still_no_block_lost()
    {
        using var temp = new TestFolder("late");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(3000, 5), 100);
        // Very fast moves: a 50 ms tick jumps over whole windows.
        var rig = new FakeRig(program, new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = 30_000 }, moveSeconds: 0.004, capacityWords: 30_000);
        var events = new List<StreamingEvent>();
        rig.Session.EventRaised += (_, e) => events.Add(e);
        await rig.Session.StartAsync();
        (await rig.RunAsync()).Should().BeTrue();

        events.Should().Contain(e => e.Kind == StreamingEventKind.ChunkDownloadedLate);
        events.Where(e => e.Kind is StreamingEventKind.ChunkDownloaded or StreamingEventKind.ChunkDownloadedLate)
            .Select(e => e.Chunk).Should().OnlyHaveUniqueItems().And.HaveCount(program.TotalChunks);
        Raw(rig).Should().Equal(program.TrackedLines());
    }

    [Fact]
    public async Task A_chunk_is_never_sent_without_room_in_the_buffer()
    {
        using var temp = new TestFolder("room");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(2000, 9), 200);
        var biggest = program.Manifest.Chunks.Max(c => c.EstimatedWords);
        // Room for about 1.3 chunks: in the window the next chunk does not fit yet, so it must wait.
        var words = (int)(biggest * 1.3) + 64;
        var rig = new FakeRig(program, new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = words }, moveSeconds: 0.01, capacityWords: words);
        await rig.Session.StartAsync();
        (await rig.RunAsync()).Should().BeTrue(rig.Session.Status.Message);

        rig.Session.State.Should().Be(SessionState.Completed, "an ERR006 would have faulted the session");
        Raw(rig).Should().Equal(program.TrackedLines());
    }

    [Fact]
    public async Task Paper_placement_lags_one_line_exact_placement_does_not()
    {
        var source = FakeSplit.Program(400, 11);
        using var temp = new TestFolder("exactp");
        var exact = FakeSplit.Write(temp.Path, source, 100, TrackingPlacement.Exact);
        using var temp2 = new TestFolder("paperp");
        var paper = FakeSplit.Write(temp2.Path, source, 100, TrackingPlacement.Paper);
        var r1 = new FakeRig(exact, new StreamingOptions { BufferWords = 20_000 }, capacityWords: 20_000);
        var r2 = new FakeRig(paper, new StreamingOptions { BufferWords = 20_000 }, capacityWords: 20_000);
        await r1.Session.StartAsync();
        await r2.Session.StartAsync();
        (await r1.RunAsync()).Should().BeTrue();
        (await r2.RunAsync()).Should().BeTrue();

        var lines = exact.TrackedLines().ToList();
        Raw(r1).Should().Equal(lines, "with the marker before the move, M0 names the executing block");
        // Paper placement: while block i moves, M0 still shows the block before it (0 for the first).
        Raw(r2).Should().Equal(new[] { 0 }.Concat(lines.Take(lines.Count - 1)));
    }

    [Fact]
    public async Task Setup_sends_B0_before_the_first_OPEN_ROT_and_R_after_it()
    {
        using var temp = new TestFolder("setup");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(300, 1), 100);
        var rig = new FakeRig(program, new StreamingOptions());
        await rig.Session.StartAsync();
        var log = rig.Controller.Log;
        var b0 = log.FindIndex(l => l.Replace(" ", string.Empty) == "&1B0");
        var open = log.FindIndex(l => l == "OPEN ROT");
        var run = log.FindIndex(l => l.Replace(" ", string.Empty) == "&1R");
        b0.Should().BeGreaterThanOrEqualTo(0);
        b0.Should().BeLessThan(open);
        run.Should().BeGreaterThan(log.FindLastIndex(l => l == "OPEN ROT"));
        rig.Controller.Open.Should().BeFalse();
    }

    [Fact]
    public async Task Hold_resume_feed_and_abort_reach_the_controller_and_are_never_stored_in_the_buffer()
    {
        using var temp = new TestFolder("ops");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(1500, 2), 100);
        var rig = new FakeRig(program, new StreamingOptions { Strategy = StrategyKind.Pr }, moveSeconds: 0.01);
        await rig.Session.StartAsync();
        for (var i = 0; i < 10; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        await rig.Session.SetFeedAsync(750);
        rig.Controller.P[500].Should().Be(750);
        rig.Session.Status.Feed.Should().Be(750);

        await rig.Session.HoldAsync();
        rig.Controller.Held.Should().BeTrue();
        var movesAtHold = rig.Controller.Moves.Count;
        for (var i = 0; i < 10; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        rig.Controller.Moves.Count.Should().BeLessThanOrEqualTo(movesAtHold + 1, "a hold stops motion");
        rig.Session.State.Should().Be(SessionState.Held);
        await rig.Session.ResumeMotionAsync();
        rig.Controller.Held.Should().BeFalse();
        for (var i = 0; i < 5; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        await rig.Session.AbortAsync();
        rig.Controller.Running.Should().BeFalse();
        rig.Session.State.Should().Be(SessionState.Aborted);
        rig.Controller.Violations.Should().BeEmpty();
        rig.Sink.Last!.State.Should().Be(SessionState.Aborted);
    }

    [Fact]
    public async Task Override_mode_changes_feed_with_percent()
    {
        using var temp = new TestFolder("ovr");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(300, 2), 100);
        var rig = new FakeRig(program, new StreamingOptions { Feed = FeedMode.Override, Strategy = StrategyKind.Adaptive });
        await rig.Session.StartAsync();
        await rig.Session.SetFeedAsync(50);
        rig.Controller.Override.Should().Be(50);
        (await rig.RunAsync()).Should().BeTrue();
        Raw(rig).Should().Equal(program.TrackedLines());
    }

    [Fact]
    public async Task Single_block_mode_runs_one_block_per_start()
    {
        using var temp = new TestFolder("sb");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(200, 4), 100);
        var rig = new FakeRig(program, new StreamingOptions { SingleBlock = true }, moveSeconds: 0.01);
        await rig.Session.StartAsync();
        for (var i = 0; i < 20; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        rig.Controller.Moves.Should().HaveCount(1);
        await rig.Session.StepAsync();
        for (var i = 0; i < 20; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        rig.Controller.Moves.Should().HaveCount(2);
        Raw(rig).Should().Equal(program.TrackedLines().Take(2));
    }

    [Fact]
    public async Task Starting_from_a_line_sends_the_preamble_then_that_block_and_the_rest()
    {
        using var temp = new TestFolder("from");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(1200, 6), 100);
        var all = program.TrackedLines().ToList();
        var from = all[500];
        var rig = new FakeRig(program, new StreamingOptions { BufferWords = 20_000 }, capacityWords: 20_000);
        await rig.Session.StartAsync(from, ["G90", "G00 Z10", "G00 X1 Y1", "G01 Z0 F(P500)"]);
        (await rig.RunAsync()).Should().BeTrue();
        var raw = Raw(rig);
        raw.Take(3).Should().AllBeEquivalentTo(0, "the preamble's moves run before the block, tracked as 0");
        raw.Skip(3).Should().Equal(all.Skip(500));
    }

    [Theory]
    [InlineData(0.95)]
    [InlineData(0.65)]
    [InlineData(0.3)]
    public async Task A_start_from_a_line_late_in_its_chunk_downloads_the_next_chunk_at_once_not_late(double into)
    {
        // A start mid-chunk loads the rest of that chunk behind the preamble: when the start lies in or past the
        // download window, execution joined the chunk there; the next chunk goes at once and no window was missed.
        using var temp = new TestFolder("from-late");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(1200, 6), 100);
        var chunk = program.Chunk(5);
        var size = chunk.LastSourceLine - chunk.FirstSourceLine + 1;
        var all = program.TrackedLines().ToList();
        var from = all.First(l => l >= chunk.FirstSourceLine + (int)(into * size));
        var rig = new FakeRig(program, new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = 30_000 }, moveSeconds: 0.02, capacityWords: 30_000);
        var downloads = new List<StreamingEvent>();
        rig.Session.EventRaised += (_, e) =>
        {
            if (e.Kind is StreamingEventKind.ChunkDownloaded or StreamingEventKind.ChunkDownloadedLate)
            {
                downloads.Add(e);
            }
        };

        await rig.Session.StartAsync(from, ["G90", "G00 Z10", "G00 X1 Y1", "G01 Z0 F(P500)"]);
        (await rig.RunAsync()).Should().BeTrue();

        downloads.Should().NotContain(d => d.Kind == StreamingEventKind.ChunkDownloadedLate, "the start, not a slow timer, put execution past the window");
        downloads.Select(d => d.Chunk).Should().Equal(Enumerable.Range(5, program.TotalChunks - 4));
        var next = downloads[1];
        if (into >= 0.6)
        {
            next.TrackedLine.Should().BeLessThanOrEqualTo(from + 2, "the next chunk goes as soon as the job runs");
        }
        else
        {
            ((double)(next.TrackedLine - chunk.FirstSourceLine + 1) / size).Should().BeInRange(0.6, 0.72, "a start before the window waits for it");
        }

        Raw(rig).Skip(3).Should().Equal(all.Where(l => l >= from));
    }

    [Fact]
    public async Task Status_reports_chunks_lines_percent_and_eta()
    {
        using var temp = new TestFolder("status");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(1000, 8), 250);
        var times = new MoveTimeTable(program.TrackedLines().Select(l => (l, 0.01)));
        var rig = new FakeRig(program, new StreamingOptions());
        rig.Session = new StreamingSession(rig.Connection, program, rig.Options, rig.Sink, times, rig.Time);
        await rig.Session.StartAsync();
        for (var i = 0; i < 30; i++)
        {
            rig.Advance(0.05);
            await rig.Session.TickAsync();
        }

        var s = rig.Session.Status;
        s.TotalChunks.Should().Be(4);
        s.TotalBlocks.Should().Be(program.Manifest.TotalMotionBlocks);
        s.CurrentLine.Should().Be(rig.Controller.M0);
        s.CurrentChunk.Should().Be(program.ChunkOfTracked(rig.Controller.M0));
        s.ExecutedBlocks.Should().Be(rig.Controller.Moves.Count);
        s.Percent.Should().BeApproximately(100.0 * s.ExecutedBlocks / s.TotalBlocks, 1e-9);
        s.Eta!.Value.TotalSeconds.Should().BeApproximately((s.TotalBlocks - s.ExecutedBlocks) * 0.01, 0.02);
        s.Elapsed.TotalSeconds.Should().BeApproximately(1.5, 0.06);
    }

    [Fact]
    public async Task A_chunk_larger_than_the_buffer_is_refused_before_anything_is_sent()
    {
        using var temp = new TestFolder("big");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(1000, 8), 1000);
        var rig = new FakeRig(program, new StreamingOptions { BufferWords = 500 });
        var act = () => rig.Session.StartAsync();
        (await act.Should().ThrowAsync<InvalidOperationException>()).WithMessage("*needs about*words*");
        rig.Controller.Log.Should().BeEmpty();
    }
}

public class ResumeTests
{
    [Fact]
    public async Task A_new_session_resumes_from_the_checkpoint_while_the_controller_keeps_running()
    {
        using var temp = new TestFolder("resume");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(1500, 12), 150);
        var rig = new FakeRig(program, new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = 20_000 }, capacityWords: 20_000);
        await rig.Session.StartAsync();
        for (var i = 0; i < 40; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        // The host "dies": the controller runs on for a while with what it holds, then a new session resumes.
        rig.Advance(0.5);
        rig.Session = rig.NewSession();
        await rig.Session.ResumeAsync(rig.Sink.Last!);
        (await rig.RunAsync()).Should().BeTrue(rig.Session.Status.Message);
        rig.Controller.Moves.Select(m => m.SourceLine).Should().Equal(program.TrackedLines());
    }

    [Fact]
    public async Task Resume_refuses_a_controller_that_no_longer_runs_the_job()
    {
        using var temp = new TestFolder("aborted");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(800, 13), 100);
        var rig = new FakeRig(program, new StreamingOptions());
        await rig.Session.StartAsync();
        for (var i = 0; i < 10; i++)
        {
            await rig.Session.TickAsync();
            rig.Advance(0.05);
        }

        var cp = rig.Session.Checkpoint;
        rig.Controller.Execute("&1A");
        rig.Session = rig.NewSession();
        var act = () => rig.Session.ResumeAsync(cp);
        (await act.Should().ThrowAsync<InvalidOperationException>()).WithMessage("*not running the job*restart from line*");
        rig.Session.State.Should().Be(SessionState.Idle, "nothing was taken over; a start from the line can follow");
    }
}
