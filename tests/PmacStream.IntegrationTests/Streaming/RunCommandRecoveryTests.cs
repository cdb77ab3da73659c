using System.Globalization;
using PmacStream.Pmac;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// A resume from a checkpoint written before the run command was recorded never gives a second run command to a
/// program that started: a held job stays held, a completed one is not started again.
/// </summary>
public sealed class RunCommandRecoveryTests : IDisposable
{
    private readonly TestFolder _folder = new("run-command");

    public void Dispose() => _folder.Dispose();

    private string Source(int moves) => RasterProgram.Write(Path.Combine(_folder.Path, "part.nc"), moves);

    private static async Task<int> TrackedAsync(IPmacConnection c) => int.Parse((await c.GetResponseAsync("M0")).Trim(), CultureInfo.InvariantCulture);

    [Fact]
    public async Task A_held_job_whose_run_command_was_not_recorded_stays_held_on_resume()
    {
        using var rig = new SimRig(Source(2000), 500, new StreamingOptions());
        await rig.Session.StartAsync();
        for (var i = 0; i < 400 && rig.Session.Status.CurrentLine < 30; i++)
        {
            await rig.Session.TickAsync();
            rig.Sim.Advance(TimeSpan.FromSeconds(0.05));
        }

        await using var panel = new InProcessConnection(rig.Sim.OpenPort("panel"), "panel");
        await panel.GetResponseAsync("&1 H");
        rig.Sim.Advance(TimeSpan.FromSeconds(2));
        var held = await TrackedAsync(panel);
        held.Should().BeGreaterThan(0);

        // The host died after the run command went out and before its checkpoint said so.
        var checkpoint = rig.Session.Checkpoint with { Started = false, Loaded = true };
        await using var again = new InProcessConnection(rig.Sim.OpenPort("resumed"), "resumed");
        var session = new StreamingSession(again, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        await session.ResumeAsync(checkpoint);

        rig.Sim.Advance(TimeSpan.FromSeconds(3));
        (await TrackedAsync(panel)).Should().Be(held, "a second run command would have released the operator's hold");
    }

    [Fact]
    public async Task A_recovery_after_the_run_command_s_reply_was_lost_does_not_release_the_operator_s_hold()
    {
        using var rig = new SimRig(Source(2000), 500, new StreamingOptions());
        var link = new RunReplyLost(rig.Connection);
        var session = new StreamingSession(link, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        var start = () => session.StartAsync();
        await start.Should().ThrowAsync<PmacLinkException>();
        session.State.Should().Be(SessionState.Faulted);

        rig.Sim.Advance(TimeSpan.FromSeconds(1));
        await using var panel = new InProcessConnection(rig.Sim.OpenPort("panel"), "panel");
        await panel.GetResponseAsync("&1 H");
        rig.Sim.Advance(TimeSpan.FromSeconds(2));
        var held = await TrackedAsync(panel);
        held.Should().BeGreaterThan(0, "the run command arrived: the job ran until the hold");

        (await session.RecoverAsync()).Should().BeTrue(session.Status.Message);
        link.RunCommands.Should().Be(1, "the run command is not given again to a program that started");
        rig.Sim.Advance(TimeSpan.FromSeconds(3));
        (await TrackedAsync(panel)).Should().Be(held, "the operator's hold stays");
    }

    [Fact]
    public async Task A_completed_job_whose_run_command_was_not_recorded_is_not_started_again()
    {
        using var rig = new SimRig(Source(60), 500, new StreamingOptions());
        await rig.Session.StartAsync();
        var checkpoint = rig.Session.Checkpoint with { Started = false, Loaded = true };
        (await rig.RunAsync(0.05)).Should().BeTrue(rig.Session.Status.Message);
        await using var panel = new InProcessConnection(rig.Sim.OpenPort("panel"), "panel");
        await panel.GetResponseAsync("&1 A"); // the completed job's rotary program ended: idle at its last line
        var moves = rig.Sim.ExecutedMoves.Count;

        await using var again = new InProcessConnection(rig.Sim.OpenPort("resumed"), "resumed");
        var session = new StreamingSession(again, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        var resume = () => session.ResumeAsync(checkpoint);
        (await resume.Should().ThrowAsync<ControllerLostJobException>()).Which.RestartLine.Should().Be(rig.Program.FinalTrackedLine);
        rig.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        rig.Sim.ExecutedMoves.Count.Should().Be(moves, "no run command went to the idle coordinate system");
    }

    /// <summary>The controller gets the run command, the host never gets its reply (the link drops once, there).</summary>
    private sealed class RunReplyLost(IPmacConnection inner) : IPmacConnection
    {
        public int RunCommands { get; private set; }

        public string Description => inner.Description;

        public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
        {
            var reply = await inner.GetResponseAsync(command, cancellationToken);
            if (command == "&1 R" && ++RunCommands == 1)
            {
                throw new PmacLinkException("link dropped before the reply");
            }

            return reply;
        }

        public Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default) => inner.DownloadAsync(lines, cancellationToken);

        public Task FlushAsync(CancellationToken cancellationToken = default) => inner.FlushAsync(cancellationToken);

        public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => inner.ControlAsync(control, cancellationToken);

        public ValueTask DisposeAsync() => ValueTask.CompletedTask;
    }
}
