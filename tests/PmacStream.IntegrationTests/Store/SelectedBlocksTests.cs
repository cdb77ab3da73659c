using System.Text;
using PmacStream.Cli;
using PmacStream.Cli.Commands;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// Selected-block execution (lines A..B of a stored revision), on both engines: the simulator executes exactly the
/// blocks of the range, every one once and in order, nothing after B, and the machine ends where the interpreter says
/// B ends; the job record keeps the range and counts its blocks. Ranges no program can run are refused with why.
/// </summary>
public sealed class SelectedBlocksTests : IDisposable
{
    /// <summary>A program with a blank and a comment line, a block without motion, and cutter compensation (G41 .. G40).</summary>
    private const string Refusals =
        "G21 G90 G17\n(comment)\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nM8\nG41 D1 G1 X20 Y5\nG1 X40\nG1 Y30\nG40 G1 X50 Y40\nG0 Z5\nM30\n";

    private readonly TestFolder _folder = new("selected-blocks");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_range_from_the_middle_of_a_corpus_program_runs_its_blocks_once_in_order_and_ends_where_the_program_says(string engine)
    {
        var location = Location(engine);
        var corpus = Requires.Corpus().Single(p => Path.GetFileName(p) == "Sienci-Labs__gsender__KB-22_test.gcode");
        var source = Path.Combine(_folder.Path, "kb22.gcode");
        // A line of its own on top, so that a shared PostgreSQL store gets a new revision every run.
        File.WriteAllText(source, $"({Guid.NewGuid():N})\n" + File.ReadAllText(corpus), new UTF8Encoding(false));
        long id;
        List<DecodedBlock> moves;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(source, MachineProfile.Default).Id;
            moves = store.ReadStoredBlocks(id).Select(b => b.Block).Where(b => b.Motion != MotionKind.None).ToList();
        }

        var (a, b) = (moves[moves.Count * 2 / 5].Line, moves[moves.Count * 3 / 5].Line);
        var expected = moves.Where(m => m.Line >= a && m.Line <= b).Select(m => m.Line).ToList();
        var service = new JobService(new JobServiceOptions { Store = location });
        var prepared = await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { ProgramId = id, OutDir = Path.Combine(_folder.Path, "chunks") });
        service.CheckRange(id, prepared.Program, a, b, RunSettings.Default, prepared.Profile).Should().Be(expected.Count, "the store counts the range's moves");
        var plan = service.PlanStartFor(id, prepared.Program, a, RunSettings.Default, prepared.Profile);
        plan.Line.Should().Be(a);

        using var sim = new PmacSimulator(new SimOptions { RetainExecutedMoves = true, StartHomed = true });
        await using var controller = new ControllerLink(ConnectionSpec.Ethernet("127.0.0.1:1025"), new InProcessConnection(sim.OpenPort("host"), "controller"));
        long jobId;
        await using (var job = await service.CreateJobAsync(controller, new JobRequest(prepared.Program, StrategyKind.Chunk)
        {
            Profile = prepared.Profile, Library = LibraryPolicy.Load, Plan = plan, ToLine = b, ProgramId = id,
        }))
        {
            jobId = job.Id!.Value;
            job.Program.Manifest.TotalMotionBlocks.Should().Be(expected.Count);
            await job.StartAsync();
            for (var i = 0; i < 50_000 && job.Status.State != SessionState.Completed; i++)
            {
                sim.Advance(TimeSpan.FromSeconds(0.25));
                await job.TickAsync();
            }

            job.Status.State.Should().Be(SessionState.Completed, job.Status.Message);
            job.Status.ExecutedBlocks.Should().Be(expected.Count);
        }

        sim.RunUntilIdle(TimeSpan.FromHours(1));
        var executed = new List<int>();
        foreach (var m in sim.ExecutedMoves.Where(m => m.SourceLine > 0))
        {
            // A block the host expands (a cycle) is several moves of one line: one block.
            if (executed.Count == 0 || executed[^1] != m.SourceLine)
            {
                executed.Add(m.SourceLine);
            }
        }

        executed.Should().Equal(expected, "every block of A..B once, in order, and nothing else");
        var last = sim.ExecutedMoves[^1];
        last.SourceLine.Should().Be(b, "no motion after B");
        var end = moves.Single(m => m.Line == b).End;
        new[] { last.X, last.Y, last.Z }.Should().Equal(new[] { end.X, end.Y, end.Z }, (x, y) => Math.Abs(x - y) < 1e-3, "the machine stands where the interpreter ends B");

        var record = service.FindJob(jobId);
        record.ToLine.Should().Be(b, "the job record keeps the range");
        record.FromLine.Should().Be(a);
        record.Outcome.Should().Be("completed");
        record.History.BlocksExecuted.Should().Be(expected.Count);
        record.History.BlocksTotal.Should().Be(expected.Count);
    }

    [Fact]
    public async Task Ranges_no_program_can_run_are_refused_with_why()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        var source = Path.Combine(_folder.Path, "refusals.nc");
        File.WriteAllText(source, Refusals, new UTF8Encoding(false));
        var json = System.Text.Json.Nodes.JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["toolRadii"] = new System.Text.Json.Nodes.JsonObject { ["1"] = 2 };
        var profile = MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radius");
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(source, profile).Id;
        }

        var service = new JobService(new JobServiceOptions { Store = location });
        var prepared = await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { ProgramId = id, Profile = profile, OutDir = Path.Combine(_folder.Path, "chunks") });
        string Refusal(int? a, int b)
        {
            var check = () => service.CheckRange(id, prepared.Program, a, b, RunSettings.Default, prepared.Profile);
            return check.Should().Throw<JobException>().Which.Message;
        }

        Refusal(5, 3).Should().Contain("before its first line 5");
        Refusal(3, 99).Should().Contain("beyond the program");
        Refusal(2, 5).Should().Contain("line 2 holds no block");
        Refusal(3, 6).Should().Contain("line 6 is not a move");
        Refusal(3, 8).Should().Contain("cutter compensation");
        Refusal(3, 7).Should().Contain("cutter compensation", "the G41 move's end is the next move's corner's too");
        service.CheckRange(id, prepared.Program, 3, 10, RunSettings.Default, prepared.Profile).Should().Be(7, "the G40 move ends where it says: lines 3, 4, 5, 7, 8, 9, 10 move");
        service.CheckRange(id, prepared.Program, null, 5, RunSettings.Default, prepared.Profile).Should().Be(3, "no A: from the top");

        // The command line: exit 1 with the reason, and a refused range prints no preamble.
        var stdout = new StringWriter();
        var refused = () => ProgramStartCommand.Run(location, id, 3, false, false, stdout, new StringWriter(), CancellationToken.None, toLine: 8);
        refused.Should().Throw<CliException>().Where(e => e.ExitCode == CliGlobals.Failed && e.Message.Contains("lines 3..8", StringComparison.Ordinal));
        stdout.ToString().Should().BeEmpty();
        var (code, _, err) = await CliRun.InProcessAsync(["stream", "--program", id.ToString(System.Globalization.CultureInfo.InvariantCulture), "--from-line", "5", "--to-line", "3", "--sim", "--store", "sqlite:" + location.Target]);
        code.Should().Be(CliGlobals.Failed);
        err.Should().Contain("before its first line 5");

        var shown = new StringWriter();
        ProgramStartCommand.Run(location, id, 3, false, false, shown, new StringWriter(), CancellationToken.None, toLine: 10).Should().Be(CliGlobals.Ok);
        shown.ToString().Should().Contain("end after line 10: 7 blocks, at X50 Y40 Z-1");
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
}
