using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>A coordinate system already running a program (another host's, or one started at the controller) is left alone.</summary>
public class ForeignProgramTests
{
    [Fact]
    public async Task Start_is_refused_while_the_coordinate_system_runs_another_program_and_nothing_is_sent_to_it()
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 1000, new StreamingOptions { BufferWords = 20_000 });
        var other = rig.Sim.OpenPort("pendant");
        foreach (var line in new[] { "OPEN PROG 7 CLEAR", "LINEAR", "F600", "X100", "X0", "CLOSE", "&1 B7 R" })
        {
            other.ExecuteText(line).Should().NotContain("ERR", line);
        }

        rig.Sim.Advance(TimeSpan.FromSeconds(1));
        var before = rig.Sim.Counters.LinesReceived;

        var act = () => rig.Session.StartAsync();

        (await act.Should().ThrowAsync<InvalidOperationException>()).WithMessage("*&1*running a program*");
        rig.Session.Status.State.Should().Be(SessionState.Idle, "a refused start can be tried again once the other program ended");
        rig.Sim.Counters.LinesReceived.Should().Be(before, "nothing went into a buffer");
        rig.Sim.Advance(TimeSpan.FromSeconds(30));
        rig.Sim.ExecutedMoves.Should().HaveCount(2, "the other program ran on, undisturbed, to its end");

        // Once it ended, the same session starts the job.
        await rig.Session.StartAsync();
        (await rig.RunAsync(2.0)).Should().BeTrue(rig.Session.Status.Message);
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines());
    }

    [Fact]
    public async Task The_rotary_program_a_completed_job_left_waiting_for_lines_is_ended_by_the_next_start_and_only_that_one()
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 1000, new StreamingOptions { BufferWords = 20_000 });
        await rig.Session.StartAsync();
        (await rig.RunAsync(2.0)).Should().BeTrue(rig.Session.Status.Message);
        var last = rig.Session.Status.CurrentLine;
        rig.Sim.Advance(TimeSpan.FromSeconds(5));
        rig.Sim.IsRunning().Should().BeTrue("a rotary program waits for more lines after its last one");

        // Without the previous job's line, a running program refuses the start, as any other would.
        var blind = new StreamingSession(rig.Connection, rig.Program, rig.Options, time: rig.Time);
        (await FluentActions.Awaiting(() => blind.StartAsync()).Should().ThrowAsync<InvalidOperationException>()).WithMessage("*&1*running a program*");

        // Another line than where the job completed: not that job's program, refused too.
        var other = new StreamingSession(rig.Connection, rig.Program, rig.Options with { CompletedJobLine = last - 1 }, time: rig.Time);
        await FluentActions.Awaiting(() => other.StartAsync()).Should().ThrowAsync<InvalidOperationException>();
        rig.Sim.IsRunning().Should().BeTrue("nothing was ended");

        // The job record says the last job completed at that line: the idle program is ended and the next job runs whole.
        var moves = rig.Sim.ExecutedMoves.Count;
        rig.Session = new StreamingSession(rig.Connection, rig.Program, rig.Options with { CompletedJobLine = last }, rig.Sink, time: rig.Time);
        await rig.Session.StartAsync();
        (await rig.RunAsync(2.0)).Should().BeTrue(rig.Session.Status.Message);
        rig.Sim.ExecutedMoves.Skip(moves).Select(m => m.SourceLine).Where(l => l > 0).Distinct().Should().Equal(rig.Program.TrackedLines());
    }

    [Fact]
    public async Task A_moving_foreign_program_is_not_taken_for_a_completed_job()
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 1000, new StreamingOptions { BufferWords = 20_000, CompletedJobLine = 0 });
        var other = rig.Sim.OpenPort("pendant");
        foreach (var line in new[] { "OPEN PROG 7 CLEAR", "LINEAR", "F600", "X100", "X0", "CLOSE", "&1 B7 R" })
        {
            other.ExecuteText(line).Should().NotContain("ERR", line);
        }

        rig.Sim.Advance(TimeSpan.FromSeconds(1));
        (await FluentActions.Awaiting(() => rig.Session.StartAsync()).Should().ThrowAsync<InvalidOperationException>()).WithMessage("*running a program*");
        rig.Sim.Advance(TimeSpan.FromSeconds(30));
        rig.Sim.ExecutedMoves.Should().HaveCount(2, "the other program ran on, undisturbed, to its end");
    }

    [Fact]
    public async Task Resuming_a_start_that_broke_off_is_refused_while_another_program_runs()
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 1000, new StreamingOptions { BufferWords = 20_000 });
        var record = rig.Sink.Record() with { Checkpoint = null };
        var other = rig.Sim.OpenPort("pendant");
        foreach (var line in new[] { "OPEN PROG 7 CLEAR", "LINEAR", "F10", "X100", "CLOSE", "&1 B7 R" })
        {
            other.ExecuteText(line).Should().NotContain("ERR", line);
        }

        var act = () => rig.Session.ResumeAsync(record);

        (await act.Should().ThrowAsync<InvalidOperationException>()).WithMessage("*running a program*");
        rig.Session.Status.State.Should().Be(SessionState.Idle);
    }
}
