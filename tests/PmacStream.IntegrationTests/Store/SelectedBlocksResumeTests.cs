using System.Globalization;
using System.Text;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// A selected-block job (lines A..B of a stored revision) interrupted in the middle of its range, by a host that
/// stops without a word (a crash: the job object abandoned, its record left running) or by an alarm (an amplifier
/// fault: the job ends faulted; the alarm is cleared), and resumed by a new job service: across both runs the
/// simulator executes every block of A..B once, in order, and nothing after B; the record ends completed with
/// blocks executed = the range's blocks. On both engines.
/// </summary>
public sealed class SelectedBlocksResumeTests : IDisposable
{
    private const int Moves = 400;
    private readonly TestFolder _folder = new("selected-resume");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_range_whose_host_crashed_mid_range_resumes_to_B_exactly(string engine)
    {
        var rig = await Rig.StartAsync(_folder, Location(engine), rules: null);

        // The host dies here: no end is recorded, nothing more is sent; the controller runs on with what it holds.
        await rig.TickUntilAsync(rig.Job, () => rig.Sim.ReadVariable('M', 0) >= rig.Middle);
        rig.Sim.Advance(TimeSpan.FromSeconds(1));

        var service = new JobService(new JobServiceOptions { Store = rig.Location });
        var resumable = service.OpenResumable(service.FindJob(rig.JobId));
        resumable.Program.Manifest.TotalMotionBlocks.Should().Be(rig.Expected.Count, "the record names the range's own split");
        var result = await service.ResumeAsync(rig.Controller, new ResumeRequest(resumable, rig.Settings, _ => Task.FromResult(true)) { Profile = rig.Profile });
        result.Kind.Should().Be(ResumeKind.Continued, result.Reason);
        await rig.FinishAsync(result.Job!);
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_range_stopped_by_an_alarm_mid_range_resumes_to_B_exactly_after_the_clear(string engine)
    {
        var rules = new Machine.MachineRules(Machine.MachineAxis.Default, true);
        var rig = await Rig.StartAsync(_folder, Location(engine), rules);

        await rig.TickUntilAsync(rig.Job, () => rig.Sim.ReadVariable('M', 0) >= rig.Middle);
        rig.Sim.InjectFault(FaultKind.AmpFault, 1);
        await rig.TickUntilAsync(rig.Job, () => rig.Job.Status.State == SessionState.Stopped);
        (await rig.Job.RunAsync()).Should().Be(JobOutcome.Stopped, "the alarm holds the job");
        rig.Job.Status.State.Should().Be(SessionState.Faulted);
        await rig.Job.DisposeAsync();

        var service = new JobService(new JobServiceOptions { Store = rig.Location, Rules = rules });
        service.FindJob(rig.JobId).Outcome.Should().Be("alarm");
        (await new Machine.MachineConsole(service, rig.Controller).ClearAlarmsAsync()).Done.Should().BeTrue();
        var resumable = service.OpenResumable(service.FindJob(rig.JobId));
        var result = await service.ResumeAsync(rig.Controller, new ResumeRequest(resumable, rig.Settings, _ => Task.FromResult(true)) { Profile = rig.Profile });
        result.Kind.Should().Be(ResumeKind.Restart, result.Reason);
        await result.Job!.StartAsync();
        await rig.FinishAsync(result.Job!);
    }

    private StoreLocation Location(string engine)
    {
        if (engine == "sqlite")
        {
            return StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        }

        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        return StoreLocation.Parse(station);
    }

    /// <summary>A stored revision, its range's job started on an in-process simulator whose clock the test steps.</summary>
    private sealed class Rig
    {
        private Rig(StoreLocation location, PmacSimulator sim, ControllerLink controller, Job job, List<int> expected, int middle, RunSettings settings, MachineProfile profile)
        {
            (Location, Sim, Controller, Job, Expected, Middle, Settings, Profile) = (location, sim, controller, job, expected, middle, settings, profile);
        }

        public StoreLocation Location { get; }

        public PmacSimulator Sim { get; }

        public ControllerLink Controller { get; }

        public Job Job { get; }

        public long JobId => Job.Id!.Value;

        /// <summary>The stored moves of A..B, in order.</summary>
        public List<int> Expected { get; }

        /// <summary>The line in the middle of the range.</summary>
        public int Middle { get; }

        public RunSettings Settings { get; }

        public MachineProfile Profile { get; }

        public static async Task<Rig> StartAsync(TestFolder folder, StoreLocation location, Machine.MachineRules? rules)
        {
            var source = Path.Combine(folder.Path, "range.nc");
            File.WriteAllText(source, Program(), new UTF8Encoding(false));
            long id;
            List<DecodedBlock> moves;
            using (var store = ProgramStores.Open(location))
            {
                id = store.ImportRevision(source, MachineProfile.Default).Id;
                moves = store.ReadStoredBlocks(id).Select(b => b.Block).Where(b => b.Motion != MotionKind.None).ToList();
            }

            var (a, b) = (moves[moves.Count / 4].Line, moves[moves.Count * 3 / 4].Line);
            var expected = moves.Where(m => m.Line >= a && m.Line <= b).Select(m => m.Line).ToList();
            // Small chunks, so that the range spans many and the interruption leaves some unsent.
            var settings = RunSettings.Default with { BlocksPerChunk = 25 };
            var service = new JobService(new JobServiceOptions { Store = location, Rules = rules });
            var prepared = await service.PrepareAsync(new PrepareRequest(source, settings) { ProgramId = id, OutDir = Path.Combine(folder.Path, "chunks") });
            service.CheckRange(id, prepared.Program, a, b, settings, prepared.Profile).Should().Be(expected.Count);
            var plan = service.PlanStartFor(id, prepared.Program, a, settings, prepared.Profile);

            var sim = new PmacSimulator(new SimOptions { RetainExecutedMoves = true, StartHomed = true });
            var controller = new ControllerLink(ConnectionSpec.Ethernet("127.0.0.1:1025"), new InProcessConnection(sim.OpenPort("host"), "controller"));
            var job = await service.CreateJobAsync(controller, new JobRequest(prepared.Program, StrategyKind.Chunk)
            {
                Settings = settings, Profile = prepared.Profile, Library = LibraryPolicy.Load, Plan = plan, ToLine = b, ProgramId = id,
            });
            job.Program.Manifest.TotalMotionBlocks.Should().Be(expected.Count);
            job.Program.TotalChunks.Should().BeGreaterThan(3);
            await job.StartAsync();
            return new Rig(location, sim, controller, job, expected, expected[expected.Count / 2], settings, prepared.Profile);
        }

        public async Task TickUntilAsync(Job job, Func<bool> done)
        {
            for (var i = 0; i < 20_000 && !done(); i++)
            {
                Sim.Advance(TimeSpan.FromSeconds(0.1));
                await job.TickAsync();
            }

            done().Should().BeTrue(job.Status.Message);
        }

        /// <summary>Runs the resumed job to its end and checks the executed moves and the record.</summary>
        public async Task FinishAsync(Job resumed)
        {
            await using (resumed)
            {
                await TickUntilAsync(resumed, () => resumed.Status.State is SessionState.Completed or SessionState.Faulted or SessionState.Aborted);
                resumed.Status.State.Should().Be(SessionState.Completed, resumed.Status.Message);
            }

            Sim.RunUntilIdle(TimeSpan.FromHours(1));
            var executed = Sim.ExecutedMoves.Where(m => m.SourceLine > 0 && m.BlockStart).Select(m => m.SourceLine).ToList();
            executed.Should().Equal(Expected, "every block of A..B once, in order, across both runs, and nothing after B");
            Sim.ExecutedMoves.Where(m => m.SourceLine > 0).Max(m => m.SourceLine).Should().Be(Expected[^1]);

            var record = new JobService(new JobServiceOptions { Store = Location }).FindJob(JobId);
            record.Outcome.Should().Be("completed");
            record.ToLine.Should().Be(Expected[^1]);
            record.History.BlocksExecuted.Should().Be(Expected.Count, "blocks executed counts the range's blocks across both runs");
            record.History.BlocksTotal.Should().Be(Expected.Count);
            await Controller.DisposeAsync();
            Sim.Dispose();
        }

        /// <summary>Short feed moves with arcs among them, every line a block; a guid comment so that a shared store gets a new revision.</summary>
        private static string Program()
        {
            var sb = new StringBuilder();
            sb.Append(CultureInfo.InvariantCulture, $"({Guid.NewGuid():N})\nG21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F1200\n");
            for (var i = 1; i <= Moves; i++)
            {
                var x = (i % 20) * 2.0;
                var y = (i / 20) * 2.0;
                sb.Append(i % 10 == 0 ? "G2" : "G1").Append(CultureInfo.InvariantCulture, $" X{x:0.###} Y{y:0.###}").Append(i % 10 == 0 ? " R50\n" : "\n");
            }

            sb.Append("G0 Z5\nM30\n");
            return sb.ToString();
        }
    }
}
