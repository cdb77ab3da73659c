using System.Globalization;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 20 item 1: the controller is the truth on resume. A host dies mid-job and a new session resumes on the
/// simulator (still running the job) from a job record that is rewound, advanced, damaged, or older than a send whose
/// reply was lost: every program line runs once and in order, or the resume is refused with both positions before
/// anything is sent.
/// </summary>
public sealed class ResumeTruthTests : IDisposable
{
    private const int Moves = 3000;
    private readonly TestFolder _temp = new("truth");

    public void Dispose() => _temp.Dispose();

    /// <summary>Moves of 0.25 mm at F1500 (10 ms each, 100 blocks a second) with coolant and spindle lines between them.</summary>
    private string Source() => TestPrograms.Write(Path.Combine(_temp.Path, "part.nc"), TestPrograms.Text(TestPrograms.Metric + "F1500\n", Moves, TestPrograms.Raster, after: n =>
    {
        var i = n - 1; // the raster's moves counted from 0, as the spindle speeds below were
        return i % 97 != 50 ? null : i % 2 == 0 ? "M08" : string.Create(CultureInfo.InvariantCulture, $"S{1000 + i}");
    }));

    private SimRig NewRig(StrategyKind strategy) =>
        new(Source(), 500, new StreamingOptions { Strategy = strategy }, simOptions: new SimOptions { RecordRotaryLines = true });

    /// <summary>Ticks the job until M0 reaches <paramref name="line"/>.</summary>
    private static async Task TickUntilAsync(SimRig rig, StreamingSession session, int line)
    {
        for (var i = 0; i < 20_000 && session.Status.CurrentLine < line; i++)
        {
            await session.TickAsync();
            session.State.Should().Be(SessionState.Running, session.Status.Message);
            rig.Sim.Advance(TimeSpan.FromSeconds(0.05));
        }

        session.Status.CurrentLine.Should().BeGreaterThanOrEqualTo(line);
    }

    private static void EveryLineOnceInOrder(SimRig rig)
    {
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines(), "every block once, in order");
        var sent = Enumerable.Range(1, rig.Program.TotalChunks).SelectMany(c => rig.Program.Body(c)).Select(l => l.Text).ToList();
        var ran = rig.Sim.ExecutedRotaryLines.Select(l => l.Text).ToList();
        var (motion, nonMotion) = LineAccounting.Compare(sent, ran, t => rig.Program.Classify(t) is { } l && (l.IsMotion || l.TrackedLine > 0));
        motion.Exact.Should().BeTrue($"motion lines: {motion}");
        nonMotion.Exact.Should().BeTrue($"non-motion lines: {nonMotion}");
    }

    [Theory]
    [InlineData(StrategyKind.Chunk)]
    [InlineData(StrategyKind.Pr)]
    [InlineData(StrategyKind.Adaptive)]
    public async Task A_checkpoint_rewound_to_chunk_1_while_the_controller_runs_chunk_4_resumes_after_the_controllers_last_line(StrategyKind strategy)
    {
        using var rig = NewRig(strategy);
        await rig.Session.StartAsync();
        var rewound = rig.Session.Checkpoint; // chunk 1 loaded and running, sending at chunk 2
        rewound.Next.Should().Be(new StreamPosition(2, 0));
        await TickUntilAsync(rig, rig.Session, line: 1800);

        // The host dies; the controller runs on with what it holds; the record the new host reads was rewound.
        rig.Sim.Advance(TimeSpan.FromSeconds(0.3));
        var session = new StreamingSession(rig.Connection, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        var events = new List<string>();
        session.EventRaised += (_, e) => events.Add(e.Message);
        await session.ResumeAsync(rig.Sink.Record() with { Checkpoint = rewound });

        events.Should().ContainMatch("resumed at line * the controller is ahead of the job record (it executes line *, which the record says was never sent*");
        rig.Session = session;
        (await rig.RunAsync(0.05)).Should().BeTrue(session.Status.Message);
        EveryLineOnceInOrder(rig);
    }

    [Fact]
    public async Task A_checkpoint_advanced_past_the_controller_is_refused_with_both_positions_and_nothing_is_sent()
    {
        using var rig = NewRig(StrategyKind.Chunk);
        await rig.Session.StartAsync();
        await TickUntilAsync(rig, rig.Session, line: 1100);
        var cp = rig.Session.Checkpoint;
        var ahead = rig.Program.TrackedLines().First(l => l > 2300);
        var advanced = cp with { LastExecutedLine = ahead, CurrentChunk = rig.Program.ChunkOfTracked(ahead), Next = new StreamPosition(rig.Program.ChunkOfTracked(ahead) + 1, 0) };

        var received = rig.Sim.Counters.LinesReceived;
        var session = new StreamingSession(rig.Connection, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        var act = () => session.ResumeAsync(rig.Sink.Record() with { Checkpoint = advanced });

        var refused = (await act.Should().ThrowAsync<ResumeRefusedException>()).Which;
        var m = refused.Controller.TrackedLine;
        m.Should().BeInRange(1100, 2000);
        refused.Message.Should().StartWith($"the controller executes line {m}, before line {ahead} that the record says had already executed.")
            .And.Contain($"The controller: M0={m}, running,")
            .And.Contain($"The job record: line {ahead} executed, sending had reached {advanced.Next}.")
            .And.Contain("Choices:");
        session.State.Should().Be(SessionState.Idle);
        rig.Sim.Counters.LinesReceived.Should().Be(received, "nothing reached a buffer");
        rig.Sim.IsRunning().Should().BeTrue("the controller runs on with what it holds");

        rig.Sim.Advance(TimeSpan.FromSeconds(60));
        var ran = rig.ExecutedLines();
        ran.Should().Equal(rig.Program.TrackedLines().Take(ran.Count), "what it held ran once, in order, and nothing after");
        ran[^1].Should().BeLessThan(ahead, "the lines the advanced record claims were never sent");
    }

    [Fact]
    public async Task A_checkpoint_that_contradicts_itself_is_refused_and_nothing_is_sent()
    {
        using var rig = NewRig(StrategyKind.Chunk);
        await rig.Session.StartAsync();
        await TickUntilAsync(rig, rig.Session, line: 1100);

        // A damaged record: its position went back to the start while its last executed line did not.
        var damaged = rig.Session.Checkpoint with { Next = new StreamPosition(1, 0) };
        var received = rig.Sim.Counters.LinesReceived;
        var session = new StreamingSession(rig.Connection, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        var act = () => session.ResumeAsync(rig.Sink.Record() with { Checkpoint = damaged });

        (await act.Should().ThrowAsync<ResumeRefusedException>()).WithMessage(
            $"the job record contradicts itself (line {damaged.LastExecutedLine} executed, but sending had only reached chunk 1 line 0, before that line). The controller: M0=*");
        rig.Sim.Counters.LinesReceived.Should().Be(received);
        rig.Sim.Advance(TimeSpan.FromSeconds(60));
        var ran = rig.ExecutedLines();
        ran.Should().Equal(rig.Program.TrackedLines().Take(ran.Count));
    }

    /// <summary>
    /// The controller stores a download and its reply is lost. When the host died with it and the power went (only
    /// durable checkpoints survive), the record predates the send and says those lines were never sent; when only the
    /// link failed, the record says the send was under way. Either way the resume must not send them again.
    /// </summary>
    [Theory]
    [InlineData(StrategyKind.Chunk, true)]
    [InlineData(StrategyKind.Adaptive, true)]
    [InlineData(StrategyKind.Chunk, false)]
    [InlineData(StrategyKind.Adaptive, false)]
    public async Task A_send_whose_reply_was_lost_after_the_controller_stored_it_is_never_sent_again(StrategyKind strategy, bool hostDiedWithPower)
    {
        using var rig = NewRig(strategy);
        var sink = new MemorySink { DurableOnly = hostDiedWithPower };
        var faulty = new FaultyConnection(rig.Port, new Random(1), dt => rig.Sim.Advance(TimeSpan.FromSeconds(dt)));
        var session = new StreamingSession(faulty, rig.Program, rig.Options, sink, time: rig.Time);
        await session.StartAsync();
        await TickUntilAsync(rig, session, line: 650);

        faulty.LoseNextDownloadReply = true;
        faulty.KillWithLostReply = hostDiedWithPower;
        var died = false;
        for (var i = 0; i < 2000 && faulty.LoseNextDownloadReply; i++)
        {
            try
            {
                await session.TickAsync();
            }
            catch (HostKilledException)
            {
                died = true;
            }

            rig.Sim.Advance(TimeSpan.FromSeconds(0.05));
        }

        faulty.LoseNextDownloadReply.Should().BeFalse("a download went out");
        died.Should().Be(hostDiedWithPower);
        session.State.Should().Be(hostDiedWithPower ? SessionState.Running : SessionState.Faulted, "the host died mid-tick, or the link fault stopped the session");
        faulty.Down = false;

        rig.Session = new StreamingSession(faulty, rig.Program, rig.Options, sink, time: rig.Time);
        await rig.Session.ResumeAsync(sink.Record());
        (await rig.RunAsync(0.05)).Should().BeTrue(rig.Session.Status.Message);
        EveryLineOnceInOrder(rig);
    }
}
