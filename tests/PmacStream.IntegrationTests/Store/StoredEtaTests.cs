using System.Text;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// A range's ETA from the store: the move times of lines A..B read from a stored revision's blocks are the times the
/// interpreter gives when it reads the file from the top (every span within 1e-6 s, the feed in force the same), for a
/// corpus program with arcs and a program with arcs, cycles, a dwell and cutter compensation's inside corners; and a
/// selected-block job's ETA is that table (its blocks are the range's), on both engines.
/// </summary>
public sealed class StoredEtaTests : IDisposable
{
    /// <summary>Arcs (I/J and R), a dwell, drilling cycles with K repeats and G91, G41 inside corners, G40.</summary>
    private const string Cycles =
        "G21 G90 G17 G40 G49 G80\nG0 X0 Y0 Z5\nS1000 M3\nG1 Z-1 F300\nG1 X10\nG2 X20 Y10 I10 J0\nG3 X10 Y20 R10\nG4 P500\nG0 Z5\n" +
        "G81 X30 Y30 Z-3 R1 F200\nX35\nG91 X5 K3\nG90 G80\nG83 X50 Y50 Z-10 R1 Q2 F150\nG80\nG0 Z5\nG1 Z-1 F300\n" +
        "G41 D1 G1 X60 Y0 F400\nG1 X80\nG1 Y20\nG1 X60\nG1 Y30\nG40 G1 X50 Y40\nG0 Z10\nG1 X0 Y0 F900\nM30\n";

    private readonly TestFolder _folder = new("stored-eta");

    public static TheoryData<string, string> Cases => new()
    {
        { "sqlite", "corpus" }, { "postgres", "corpus" }, { "sqlite", "cycles" }, { "postgres", "cycles" },
    };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Cases))]
    public void The_stored_times_of_a_range_are_the_reinterpreted_times(string engine, string program)
    {
        var location = Location(engine);
        var (source, profile) = Program(program);
        long id;
        List<int> moves;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(source, profile).Id;
            moves = store.ReadMoveTimes(id).Select(m => m.Line).ToList();
        }

        moves.Should().HaveCountGreaterThan(15);
        var file = MoveTimeTable.FromProgram(source, profile: profile);
        file.BlockCount.Should().Be(moves.Count, "the store holds a row with a time for every move the interpreter times");
        var service = new JobService(new JobServiceOptions { Store = location });
        var sha = FileHash.Sha256Hex(source, CancellationToken.None);
        foreach (var (a, b) in new[] { (moves[moves.Count / 5], moves[moves.Count * 4 / 5]), (moves[0], moves[^1]), (moves[moves.Count / 2], int.MaxValue) })
        {
            var stored = service.MoveTimesFromStore(id, sha, a, b, profile);
            stored.Should().NotBeNull();
            var lines = moves.Where(l => l >= a && l <= b).ToList();
            stored!.BlockCount.Should().Be(lines.Count);
            var before = a - 1;
            for (var i = 0; i < lines.Count; i++)
            {
                stored.SecondsBetween(before, lines[i]).Should().BeApproximately(file.SecondsBetween(before, lines[i]), 1e-6, $"lines {a}..{lines[i]}");
                stored.SecondsBetween(lines[i], lines[^1]).Should().BeApproximately(file.SecondsBetween(lines[i], lines[^1]), 1e-6, $"after line {lines[i]}");
                stored.ProgrammedFeedAt(lines[i]).Should().Be(file.ProgrammedFeedAt(lines[i]), $"the feed at line {lines[i]}");
            }
        }

        service.MoveTimesFromStore(id, new string('0', 64), moves[0], moves[^1], profile).Should().BeNull("another program's times are not this one's");
        service.MoveTimesFromStore(id, sha, moves[0], moves[^1], MachineProfile.Resolve("linuxcnc-mill")).Should().BeNull("times interpreted under another profile");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_selected_block_job_takes_its_eta_from_the_store(string engine)
    {
        var location = Location(engine);
        var (source, profile) = Program("cycles");
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(source, profile).Id;
        }

        var service = new JobService(new JobServiceOptions { Store = location });
        var prepared = await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { ProgramId = id, Profile = profile, OutDir = Path.Combine(_folder.Path, "chunks") });
        var (a, b) = (5, 18); // arcs, a dwell and both cycles; B a plain move
        var plan = service.PlanStartFor(id, prepared.Program, a, RunSettings.Default, prepared.Profile);
        using var sim = new PmacSimulator(new SimOptions { StartHomed = true });
        await using var controller = new ControllerLink(ConnectionSpec.Ethernet("127.0.0.1:1025"), new InProcessConnection(sim.OpenPort("host"), "controller"));
        await using var job = await service.CreateJobAsync(controller, new JobRequest(prepared.Program, StrategyKind.Chunk)
        {
            Profile = prepared.Profile, Library = LibraryPolicy.Load, Plan = plan, ToLine = b, ProgramId = id, Record = false,
        });
        var times = job.Session.MoveTimes.Should().BeOfType<MoveTimeTable>().Which;
        times.BlockCount.Should().Be(job.Program.Manifest.TotalMotionBlocks, "the table holds the range's moves, read from the store, not the whole file's");
        var file = MoveTimeTable.FromProgram(source, profile: profile);
        times.TotalSeconds.Should().BeApproximately(file.SecondsBetween(a - 1, b), 1e-6);
    }

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    private (string Source, MachineProfile Profile) Program(string which)
    {
        // A line of its own on top, so that a shared PostgreSQL store gets a new revision every run.
        var text = which == "corpus"
            ? File.ReadAllText(Requires.Corpus().Single(p => Path.GetFileName(p) == "pete-restall__Cluck2Sesame-Prototype__Enclosure.nc"))
            : Cycles;
        var source = Path.Combine(_folder.Path, which + ".nc");
        File.WriteAllText(source, $"({Guid.NewGuid():N})\n" + text, new UTF8Encoding(false));
        var json = JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["toolRadii"] = new JsonObject { ["1"] = 2 };
        return (source, which == "corpus" ? MachineProfile.Default : MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radius"));
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
