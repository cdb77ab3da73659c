using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>The session's smaller parts alone: recovery decisions, the coordinate system's commands, the job log.</summary>
public class SessionPartsTests
{
    private static Checkpoint Cp(bool started, bool loaded, int line = 120) =>
        new(line, 1, new StreamPosition(1, 40), true, 1, SessionState.Running, DateTimeOffset.UnixEpoch, started, loaded);

    private static JobRecord Job(Checkpoint? cp, int? fromLine = null, IReadOnlyList<string>? preamble = null) =>
        new(7, "p.nc", "", "manifest.json", StrategyKind.Chunk, "sim", fromLine, "", cp, DateTimeOffset.UnixEpoch, preamble);

    [Fact]
    public void A_job_resumes_from_its_checkpoint_once_the_start_had_loaded_and_otherwise_loads_the_start_again()
    {
        JobRecovery.RouteOf(Job(Cp(started: true, loaded: true))).Should().Be(ResumeRoute.FromCheckpoint);
        JobRecovery.RouteOf(Job(Cp(started: false, loaded: true))).Should().Be(ResumeRoute.FromCheckpoint, "loaded: only the run command is missing");
        JobRecovery.RouteOf(Job(Cp(started: false, loaded: false))).Should().Be(ResumeRoute.LoadStartAgain);
        JobRecovery.RouteOf(Job(null)).Should().Be(ResumeRoute.LoadStartAgain);
        JobRecovery.RouteOf(Job(null, fromLine: 50, preamble: ["G90"])).Should().Be(ResumeRoute.LoadStartAgain);
        FluentActions.Invoking(() => JobRecovery.RouteOf(Job(null, fromLine: 50))).Should().Throw<InvalidOperationException>()
            .WithMessage("job 7 broke off while loading its start at line 50 and the record holds no preamble*");
    }

    [Fact]
    public void The_stop_watch_asks_the_running_bit_only_when_the_line_stood_still_or_while_stopped()
    {
        var watch = new ProgramStopWatch();
        watch.Reset(0);
        watch.MustAsk(12, running: true).Should().BeFalse("the line moved on: the program runs");
        watch.MustAsk(12, running: true).Should().BeTrue("the line stood still over a tick");
        watch.MustAsk(12, running: false).Should().BeFalse("held: no stop is looked for");

        watch.Observe(programRunning: true, () => throw new InvalidOperationException("not asked"), out var left).Should().BeNull();
        left.Should().BeNull();
        watch.Observe(programRunning: false, () => new ProgramStop(12, "M00"), out _).Should().Be(new ProgramStop(12, "M00"));
        watch.Stop.Should().Be(new ProgramStop(12, "M00"));
        watch.MustAsk(12, running: false).Should().BeTrue("while stopped every tick asks");
        watch.Observe(programRunning: false, () => throw new InvalidOperationException("once per stop"), out _).Should().BeNull();
        watch.Observe(programRunning: true, () => throw new InvalidOperationException("not asked"), out left).Should().BeNull();
        left.Should().Be(new ProgramStop(12, "M00"), "the controller continued");
        watch.Stop.Should().BeNull();
        new ProgramStop(12, "M00").ToString().Should().Be("program stop (M00) at line 12");
        new ProgramStop(12, null).ToString().Should().Be("program stop at line 12");
    }

    [Fact]
    public void A_job_left_at_a_stop_is_still_there_while_the_variable_names_the_stop_block()
    {
        var stopped = Cp(true, true, line: 64) with { State = SessionState.Stopped };
        JobRecovery.StillAtStop(stopped, 64).Should().BeTrue();
        JobRecovery.StillAtStop(stopped, 70).Should().BeFalse("the program moved on since");
        JobRecovery.StillAtStop(Cp(true, true, line: 64), 64).Should().BeFalse("the checkpoint did not know of a stop");
    }

    [Fact]
    public void A_checkpoint_of_an_unfinished_load_is_refused()
    {
        FluentActions.Invoking(() => JobRecovery.EnsureLoaded(Cp(false, false))).Should().Throw<InvalidOperationException>();
        JobRecovery.EnsureLoaded(Cp(false, true));
    }

    [Fact]
    public void A_fault_message_says_where_sending_stopped_and_what_to_do()
    {
        var next = new StreamPosition(3, 17);
        JobRecovery.FaultMessage(new PmacLinkException("timeout"), 2040, next).Should()
            .StartWith("link to the controller lost (timeout); last executed line 2040, sending stopped at chunk 3 line 17").And.Contain("resume");
        JobRecovery.FaultMessage(new PmacErrorException(6, "X1"), 2040, next).Should().StartWith("controller refused 'X1' with ERR006");
        JobRecovery.FaultMessage(new InvalidDataException("p_0003.pmc changed"), 2040, next).Should().StartWith("p_0003.pmc changed;").And.Contain("split again");
    }

    [Fact]
    public void Commands_address_the_coordinate_system_and_the_feed_goes_to_the_feed_variable_or_the_override()
    {
        var paper = new CoordinateSystemCommands(2, FeedMode.Paper, " P600 ");
        paper.Run(singleBlock: false).Should().Be("&2 R");
        paper.Run(singleBlock: true).Should().Be("&2 S");
        (paper.Hold, paper.Abort, paper.PointAtRotary, paper.Status, paper.DeleteRotary).Should().Be(("&2 H", "&2 A", "&2 B0", "&2??", "&2 DELETE ROT"));
        paper.DefineRotary(30000).Should().Be("&2 DEFINE ROT 30000");
        paper.ReadFeed.Should().Be("P600");
        paper.SetFeed(812.34567, out var shown).Should().Be("P600=812.346");
        shown.Should().Be("812.346");

        var over = new CoordinateSystemCommands(1, FeedMode.Override, null);
        over.ReadFeed.Should().Be("&1 %");
        over.SetFeed(80, out _).Should().Be("&1 %80");
        new CoordinateSystemCommands(1, FeedMode.Paper, "").FeedVariable.Should().Be("P500");
    }

    [Fact]
    public void The_status_message_is_the_last_notable_event_or_note_and_every_event_reaches_the_subscribers()
    {
        var source = new object();
        var log = new JobLog(source);
        var seen = new List<(object? Sender, StreamingEvent Event)>();
        log.Raised += (s, e) => seen.Add((s, e));

        log.Raise(StreamingEventKind.Underrun, "rotary buffer ran dry at line 5", 1, 5);
        log.Raise(StreamingEventKind.ChunkEntered, "execution entered chunk 2", 2, 1001);
        log.Message.Should().Be("rotary buffer ran dry at line 5", "entering a chunk is not notable");
        log.Note("chunk 3 waits for room");
        log.Message.Should().Be("chunk 3 waits for room");
        log.Downloaded(new ChunkSent(3, 1000, Whole: true), late: true, "M0=1700, 70 % of chunk 2", 1700);
        log.Message.Should().Be("chunk 3 downloaded late (window missed) at M0=1700, 70 % of chunk 2");
        log.Downloaded(new ChunkSent(4, 12, Whole: false), late: false, "-", 1800);

        seen.Should().OnlyContain(x => ReferenceEquals(x.Sender, source));
        seen.Select(x => (x.Event.Kind, x.Event.Chunk, x.Event.TrackedLine)).Should().Equal(
            (StreamingEventKind.Underrun, 1, 5), (StreamingEventKind.ChunkEntered, 2, 1001),
            (StreamingEventKind.ChunkDownloadedLate, 3, 1700), (StreamingEventKind.ChunkDownloaded, 4, 1800));
        seen[^1].Event.Message.Should().Be("rest of chunk 4 sent (12 lines)");
    }
}
