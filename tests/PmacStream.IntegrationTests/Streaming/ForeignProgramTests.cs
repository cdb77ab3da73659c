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
