using System.Globalization;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The library is loaded only into an idle controller, and the job service checks it before the first chunk, so every
/// face gets the same refusal.
/// </summary>
public sealed class LibraryGateTests : IDisposable
{
    private readonly TestFolder _folder = new("library-gate");

    public void Dispose() => _folder.Dispose();

    private string Source(int moves) => RasterProgram.Write(Path.Combine(_folder.Path, "part.nc"), moves);

    [Fact]
    public async Task A_library_load_is_refused_while_the_coordinate_system_runs_a_program_and_nothing_is_downloaded()
    {
        using var rig = new SimRig(Source(2000), 500, new StreamingOptions());
        await rig.Session.StartAsync();
        for (var i = 0; i < 200 && rig.Session.Status.CurrentLine < 20; i++)
        {
            await rig.Session.TickAsync();
            rig.Sim.Advance(TimeSpan.FromSeconds(0.05));
        }

        rig.Session.Status.CurrentLine.Should().BeGreaterThan(0, "the job runs");
        await using var panel = new InProcessConnection(rig.Sim.OpenPort("panel"), "panel");
        var m0 = (await panel.GetResponseAsync("M0")).Trim();
        var load = () => ControllerLibrary.EnsureAsync(panel, MachineProfile.Named("grbl"), LibraryPolicy.Load);
        var refusal = (await load.Should().ThrowAsync<JobException>()).Which.Message;
        refusal.Should().Contain("&1 is running a program at M0=").And.Contain("&1 H, &1 A").And.Contain("load the library again");
        int.Parse(refusal.Split("M0=")[1].Split(' ')[0], CultureInfo.InvariantCulture).Should().BeGreaterThanOrEqualTo(int.Parse(m0, CultureInfo.InvariantCulture));
        (await ControllerLibrary.ReadIdentityAsync(panel)).Should().Be(ControllerLibrary.ExpectedIdentity(), "the running job's library is untouched");

        // Held and aborted: idle, and the load goes through.
        await panel.GetResponseAsync("&1 A");
        rig.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        await ControllerLibrary.EnsureAsync(panel, MachineProfile.Named("grbl"), LibraryPolicy.Load);
        (await ControllerLibrary.ReadIdentityAsync(panel)).Should().Be(ControllerLibrary.ExpectedIdentity(MachineProfile.Named("grbl")));
    }

    [Fact]
    public async Task The_job_service_checks_the_library_before_recording_or_sending_anything()
    {
        var source = Source(50);
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_folder.Path, "jobs.db") });
        var prepared = await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default));
        using var sim = new PmacSimulator();
        await using var controller = new ControllerLink(ConnectionSpec.Ethernet("127.0.0.1:1025"), new InProcessConnection(sim.OpenPort("host"), "controller"));
        var request = new JobRequest(prepared.Program, StrategyKind.Chunk) { Profile = prepared.Profile };

        var create = () => service.CreateJobAsync(controller, request);
        (await create.Should().ThrowAsync<JobException>()).Which.Message.Should().Contain("no PmacStream library").And.Contain("--load-library");
        sim.Counters.LinesReceived.Should().Be(0, "nothing of the program reached a buffer");
        File.Exists(service.JobDatabase).Should().BeTrue();
        using (var store = JobStore.Open(service.JobDatabase))
        {
            store.List().Should().BeEmpty("a refused job is not recorded");
        }

        await using (var forced = await service.CreateJobAsync(controller, request with { Library = LibraryPolicy.Force }))
        {
            forced.Id.Should().NotBeNull("--force runs on anyway, as it did");
        }

        await using (var loaded = await service.CreateJobAsync(controller, request with { Library = LibraryPolicy.Load }))
        {
            (await ControllerLibrary.ReadIdentityAsync(controller.Connection)).Should().Be(ControllerLibrary.ExpectedIdentity(prepared.Profile));
        }
    }

    [Fact]
    public async Task A_completed_jobs_waiting_rotary_program_is_ended_before_a_library_load()
    {
        // The HMI's profile change after a job ran to its end: that job's rotary program still waits for lines.
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_folder.Path, "jobs.db") });
        var prepared = await service.PrepareAsync(new PrepareRequest(Source(40), RunSettings.Default));
        using var sim = new PmacSimulator();
        await using var controller = new ControllerLink(ConnectionSpec.Ethernet("127.0.0.1:1025"), new InProcessConnection(sim.OpenPort("host"), "controller"));
        await using (var job = await service.CreateJobAsync(controller, new JobRequest(prepared.Program, StrategyKind.Chunk) { Profile = prepared.Profile, Library = LibraryPolicy.Load }))
        {
            await job.StartAsync();
            for (var i = 0; i < 500 && job.Status.State != SessionState.Completed; i++)
            {
                sim.Advance(TimeSpan.FromSeconds(0.5));
                await job.TickAsync();
            }

            job.Status.State.Should().Be(SessionState.Completed);
        }

        var status = () => controller.Connection.GetResponseAsync("&1??");
        ControllerQueries.ProgramRunning(ControllerQueries.FirstValue(await status()).Replace(" ", string.Empty, StringComparison.Ordinal))
            .Should().BeTrue("the completed job's rotary program waits for lines after its end");
        var unknown = () => ControllerLibrary.EnsureAsync(controller.Connection, MachineProfile.Named("grbl"), LibraryPolicy.Load);
        (await unknown.Should().ThrowAsync<JobException>("without the job record, a running program is a running program")).Which.Message.Should().Contain("&1 is running a program");

        await service.LoadLibraryAsync(controller, MachineProfile.Named("grbl")!);
        ControllerQueries.ProgramRunning(ControllerQueries.FirstValue(await status()).Replace(" ", string.Empty, StringComparison.Ordinal))
            .Should().BeFalse("the waiting program was ended (&1A) before the load");
        (await ControllerLibrary.ReadIdentityAsync(controller.Connection)).Should().Be(ControllerLibrary.ExpectedIdentity(MachineProfile.Named("grbl")));
    }
}
