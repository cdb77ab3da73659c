using System.Security.Cryptography;
using System.Text;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// Execution reads the store: a second station (its own job service, its own copy of the source, no chunk folder)
/// runs a revision prepared at another station with every chunk written from the stored preparation, byte for byte,
/// nothing split; a chunk file in the folder that is not the stored bytes (edited to the same size, or truncated) is
/// replaced from the store before anything is sent. On both engines (SQLite: two services on one file).
/// </summary>
public sealed class StoredExecutionTests : IDisposable
{
    private readonly TestFolder _folder = new("stored-execution");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_second_station_runs_a_revision_prepared_elsewhere_from_the_stored_chunks_and_replaces_a_changed_chunk(string engine)
    {
        var location = Location(engine);
        var settings = RunSettings.Default with { BlocksPerChunk = 20 };

        // Station A imports, splits and stores the preparation.
        var fileA = Path.Combine(_folder.NewFolder("station-a"), "part.nc");
        File.WriteAllText(fileA, Program(), new UTF8Encoding(false));
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(fileA, MachineProfile.Default).Id;
        }

        var a = new JobService(new JobServiceOptions { Store = location });
        var atA = await a.PrepareAsync(new PrepareRequest(fileA, settings) { ProgramId = id, OutDir = Path.Combine(_folder.Path, "station-a", "chunks") });
        a.PreparationsStored.Should().Be(1);
        var split = Chunks(atA.Program.Folder);
        split.Should().HaveCountGreaterThan(3);

        // Station B: its own copy of the source (exported from the store) and no chunk folder.
        var fileB = Path.Combine(_folder.NewFolder("station-b"), "part.nc");
        using (var store = ProgramStores.Open(location))
        using (var f = File.Create(fileB))
        {
            store.ExportSource(id, f).Should().BeTrue();
        }

        var outB = Path.Combine(_folder.Path, "station-b", "chunks");
        Directory.Exists(outB).Should().BeFalse();
        var b = new JobService(new JobServiceOptions { Store = location });
        var atB = await b.PrepareAsync(new PrepareRequest(fileB, settings) { ProgramId = id, OutDir = outB });
        (b.PreparationsReused, b.PreparationsStored).Should().Be((1L, 0L), "nothing split at station B: every chunk from the store");
        atB.Reused.Should().BeTrue();
        Chunks(outB).Should().Equal(split, "every chunk written from the store, byte for byte");
        atB.Program.Manifest.SourcePath.Should().Be(Path.GetFullPath(fileB), "the manifest names station B's copy");
        await RunAsync(b, atB);

        // A chunk edited in place to the same size (another line number in a tracking assignment) and one truncated:
        // not the stored bytes, so written again from the store, never sent as they are.
        var second = Path.Combine(outB, split[1].Name);
        var bytes = File.ReadAllBytes(second);
        var at = Encoding.ASCII.GetString(bytes).IndexOf("M0==", StringComparison.Ordinal) + 4;
        bytes[at] = (byte)(bytes[at] == '9' ? '8' : bytes[at] + 1);
        File.WriteAllBytes(second, bytes);
        new FileInfo(second).Length.Should().Be(atA.Program.Manifest.Chunks[1].ByteSize, "the same size: only its bytes tell");
        Chunks(outB).Should().NotEqual(split);
        var again = await b.PrepareAsync(new PrepareRequest(fileB, settings) { ProgramId = id, OutDir = outB });
        (b.PreparationsReused, b.PreparationsStored).Should().Be((2L, 0L));
        Chunks(outB).Should().Equal(split, "the edited chunk replaced from the store");
        var third = Path.Combine(outB, split[2].Name);
        File.WriteAllBytes(third, File.ReadAllBytes(third)[..10]);
        again = await b.PrepareAsync(new PrepareRequest(fileB, settings) { ProgramId = id, OutDir = outB });
        Chunks(outB).Should().Equal(split, "the truncated chunk replaced from the store");
        await RunAsync(b, again);
    }

    /// <summary>Runs a prepared program on a fresh simulator: every tracked block once, in order.</summary>
    private static async Task RunAsync(JobService service, PreparedProgram prepared)
    {
        using var sim = new PmacSimulator(new SimOptions { RetainExecutedMoves = true, StartHomed = true });
        await using var controller = new ControllerLink(ConnectionSpec.Ethernet("127.0.0.1:1025"), new InProcessConnection(sim.OpenPort("host"), "controller"));
        await using var job = await service.CreateJobAsync(controller, new JobRequest(prepared.Program, StrategyKind.Chunk)
        {
            Profile = prepared.Profile, Library = LibraryPolicy.Load, Record = false,
        });
        await job.StartAsync();
        for (var i = 0; i < 20_000 && job.Status.State != SessionState.Completed; i++)
        {
            sim.Advance(TimeSpan.FromSeconds(0.25));
            await job.TickAsync();
        }

        job.Status.State.Should().Be(SessionState.Completed, job.Status.Message);
        sim.RunUntilIdle(TimeSpan.FromHours(1));
        sim.ExecutedMoves.Where(m => m.SourceLine > 0 && m.BlockStart).Select(m => m.SourceLine)
            .Should().Equal(prepared.Program.TrackedLines(), "every block once, in order");
    }

    private static List<(string Name, string Sha)> Chunks(string folder) =>
        Directory.GetFiles(folder, "*.pmc").Order(StringComparer.Ordinal).Select(f => (Path.GetFileName(f), Convert.ToHexString(SHA256.HashData(File.ReadAllBytes(f))))).ToList();

    /// <summary>Short moves; a guid comment so that a shared store gets a new revision.</summary>
    private static string Program()
    {
        var sb = new StringBuilder($"({Guid.NewGuid():N})\nG21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F1200\n");
        for (var i = 1; i <= 120; i++)
        {
            sb.Append(i % 2 == 0 ? "G1 X" : "G1 Y").Append((i % 7).ToString(System.Globalization.CultureInfo.InvariantCulture)).Append('\n');
        }

        return sb.Append("G0 Z5\nM30\n").ToString();
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
