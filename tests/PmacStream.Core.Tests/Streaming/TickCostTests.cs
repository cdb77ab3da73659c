using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>
/// What a tick of a running job does besides reading M0: the status query only when it can tell something, the
/// executed count from running totals, a checkpoint only when it says something new; the job itself unchanged.
/// </summary>
public class TickCostTests
{
    // 300 source lines in 3 chunks of 100 body lines: a move on every line but each tenth, which is an M08.
    private static readonly string[] Source = Enumerable.Range(1, 300).Select(i => i % 10 == 0 ? "M08" : $"G01 X{i} Y0").ToArray();

    [Fact]
    public void The_stop_watch_asks_every_tick_where_nothing_is_ahead_and_otherwise_every_nth_tick_the_line_stands()
    {
        var watch = new ProgramStopWatch(askEvery: 4);
        watch.Reset(0);
        watch.MustAsk(12, running: true, nothingAhead: false).Should().BeFalse("the line moved on");
        var asked = Enumerable.Range(1, 12).Select(_ => watch.MustAsk(12, running: true, nothingAhead: false)).ToList();
        asked.Should().Equal([false, false, false, true, false, false, false, true, false, false, false, true], "a long move: every fourth tick it stands");
        watch.MustAsk(13, running: true, nothingAhead: false).Should().BeFalse("moved on: the count starts again");
        watch.MustAsk(13, running: true, nothingAhead: true).Should().BeTrue("nothing ahead: a stop must not pass for a dry buffer");
        watch.MustAsk(13, running: false, nothingAhead: true).Should().BeFalse("held: no stop is looked for");
        watch.Observe(programRunning: false, () => new ProgramStop(13, "M00"), out _).Should().Be(new ProgramStop(13, "M00"));
        watch.MustAsk(13, running: false, nothingAhead: false).Should().BeTrue("while stopped every tick asks");
    }

    [Fact]
    public void The_running_executed_count_is_the_programs_count_for_any_line_in_any_order()
    {
        using var temp = new TestFolder("executed-count");
        var program = FakeSplit.Write(temp.Path, Source, 100);
        var count = new ExecutedBlockCount(program);
        var lines = Enumerable.Range(-1, 305).ToList();
        var shuffled = lines.ToArray();
        new Random(7).Shuffle(shuffled);
        var order = lines.Concat(Enumerable.Reverse(lines)).Concat(shuffled).Concat([150, 150, 40, 40, 299, 1]);
        foreach (var line in order)
        {
            count.Through(line).Should().Be(program.BlocksThrough(line), $"line {line}");
        }

        count.Through(300).Should().Be(program.Manifest.TotalMotionBlocks);
    }

    [Fact]
    public void A_checkpoint_that_says_what_the_last_one_said_is_not_written_again_unless_durable()
    {
        var sink = new MemorySink();
        var cp = new Checkpoint(120, 2, new StreamPosition(3, 0), true, 2, SessionState.Running, DateTimeOffset.UnixEpoch);
        var writer = new CheckpointWriter(sink, () => cp);
        writer.Save(durable: false);
        sink.Writes.Should().Be(1);
        sink.Durable.Should().Be(1, "the first one in a chunk is durable");

        cp = cp with { TimeUtc = cp.TimeUtc.AddSeconds(1) };
        writer.Save(durable: false);
        sink.Writes.Should().Be(1, "only the time differs");
        writer.Save(durable: true);
        sink.Writes.Should().Be(2, "asked to be durable: written");

        foreach (var changed in new[]
        {
            cp with { LastExecutedLine = 121 }, cp with { Next = new StreamPosition(3, 5) }, cp with { NextExact = false },
            cp with { ChunksDownloaded = 3 }, cp with { State = SessionState.Held }, cp with { Started = false }, cp with { Loaded = false },
        })
        {
            var before = sink.Writes;
            cp = changed;
            writer.Save(durable: false);
            sink.Writes.Should().Be(before + 1, $"{changed} says something new");
            sink.Last.Should().Be(changed);
        }
    }

    [Fact]
    public async Task Over_moves_longer_than_a_tick_a_tick_reads_m0_alone_and_the_job_still_runs_every_block_once_in_order()
    {
        using var temp = new TestFolder("tick-cost");
        var program = FakeSplit.Write(temp.Path, Source, 100);
        var options = new StreamingOptions { BufferWords = 8000 };
        var rig = new FakeRig(program, options, moveSeconds: 0.4, capacityWords: 8000);
        await rig.Session.StartAsync();
        var ticks = 0;
        (await rig.RunAsync(everyTick: _ =>
        {
            ticks++;
            return Task.CompletedTask;
        })).Should().BeTrue(rig.Session.Status.Message);

        rig.ExecutedLines().Should().Equal(program.TrackedLines(), "every block once, in order");
        var log = rig.Controller.Log;
        var m0 = log.Count(c => c == "M0");
        var status = log.Count(c => c == "&1??");
        m0.Should().BeGreaterThanOrEqualTo(ticks);
        status.Should().BeLessThan(ticks / 5, $"a move of 8 ticks asks the status at most once while it runs ({status} in {ticks} ticks)");
        rig.Sink.Writes.Should().BeLessThan(ticks / 3, $"a checkpoint when the position changed, not every tick ({rig.Sink.Writes} in {ticks} ticks)");
        rig.Sink.Last!.State.Should().Be(SessionState.Completed);
        rig.Sink.Last.LastExecutedLine.Should().Be(program.FinalTrackedLine);
    }
}
