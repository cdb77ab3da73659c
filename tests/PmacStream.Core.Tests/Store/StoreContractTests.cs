using System.Text;
using PmacStream.GCode;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Store;

/// <summary>
/// The same contract on both engines: program revisions (keyed by SHA-256 and profile, exact source, diagnostics,
/// stored modal state), jobs with their history, and checkpoints read back exactly by a new store instance. The
/// PostgreSQL half runs where <c>PMACSTREAM_TEST_PG</c> names a server and reports SKIPPED otherwise.
/// </summary>
public sealed class StoreContractTests : IDisposable
{
    private readonly TestFolder _folder = new("store-contract");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_program_is_one_revision_per_content_and_profile_with_its_exact_source(string engine)
    {
        var location = Location(engine);
        var file = Program("part.nc", "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG2 X10 Y0 I5 J0\nG1 X20\nM30\n");
        using var store = ProgramStores.Open(location);

        var first = store.ImportRevision(file, MachineProfile.Default);
        var again = store.ImportRevision(file, MachineProfile.Default);
        again.Id.Should().Be(first.Id, "the same content under the same profile is the same revision");
        again.Existing.Should().BeTrue();
        store.ImportRevision(file, MachineProfile.Resolve("linuxcnc-mill")).Id.Should().NotBe(first.Id, "another profile is another revision");

        var info = store.GetProgram(first.Id)!;
        info.Name.Should().Be("part.nc");
        info.Blocks.Should().Be(6, "a line with only a comment is no block");
        info.Errors.Should().Be(0);
        info.Sha256.Should().Be(FileSha(file));
        store.ListRevisions().Should().Contain(p => p.Id == first.Id);

        using (var exported = new MemoryStream())
        {
            store.ExportSource(first.Id, exported).Should().BeTrue();
            exported.ToArray().Should().Equal(File.ReadAllBytes(file), "export gives back the exact bytes");
        }

        // The modal state of a block reads back as the interpreter had it: G02 at line 5 (after the run's comment).
        var arc = store.GetBlockAtOrAfterLine(first.Id, 5)!;
        arc.Line.Should().Be(5);
        arc.Modal.GA.Should().Be(2);
        arc.Modal.Feed.Should().Be(100);

        File.AppendAllText(file, "(changed)\n");
        var changed = store.ImportRevision(file, MachineProfile.Default);
        changed.Id.Should().NotBe(first.Id, "a file changed after import is a new revision");
        store.GetProgram(first.Id)!.Sha256.Should().Be(info.Sha256, "the old revision stays as it was");

        store.DeleteProgram(changed.Id);
        store.GetProgram(changed.Id).Should().BeNull();
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_program_with_errors_is_stored_with_its_diagnostics(string engine)
    {
        var location = Location(engine);
        var file = Program("bad.nc", "O1\nG1 X1 Q#\nM30\n");
        using var store = ProgramStores.Open(location);
        var seen = new List<Diagnostic>();
        var result = store.ImportRevision(file, MachineProfile.Default, seen.Add);
        result.Summary.HasErrors.Should().BeTrue();
        var stored = store.GetDiagnostics(result.Id);
        stored.Select(d => d.Format("bad.nc")).Should().BeEquivalentTo(seen.Select(d => d.Format("bad.nc")), "every diagnostic is stored");
        stored.Should().Contain(d => d.Severity == Severity.Error && d.Line == 3, "line 1 is the run's own comment");
        store.GetProgram(result.Id)!.Errors.Should().Be(result.Summary.Errors);
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_job_keeps_its_history_and_its_checkpoint_reads_back_exactly(string engine)
    {
        var location = Location(engine);
        var program = Program("job.nc", "G0 X1\nM30\n");
        var cp = new Checkpoint(1234, 3, new StreamPosition(4, 1500), true, 4, SessionState.Running, new DateTimeOffset(2026, 11, 27, 5, 0, 0, TimeSpan.Zero), true, true);
        long id;
        using (var store = JobStores.Open(location))
        {
            id = store.CreateJob(program, new string('a', 64), Path.Combine(_folder.Path, "manifest.json"), StrategyKind.Full, "tcp://10.0.0.7:1025", null, "P501", null,
                ("fanuc-mill", "fanuc-mill@1"), new JobHistoryStart(42, "station-7", "mill-3", 5000));
            store.RecordStart(id, new JobStart(null, ["G90"], "P501"));
            store.SaveCheckpoint(id, cp, durable: true, executed: 2100);
        }

        using (var reopened = JobStores.Open(location))
        {
            var job = reopened.Get(id)!;
            job.Checkpoint.Should().Be(cp, "a new store instance reads the checkpoint back exactly");
            job.Preamble.Should().Equal("G90");
            job.History.ProgramId.Should().Be(42);
            job.History.Station.Should().Be("station-7");
            job.History.Machine.Should().Be("mill-3");
            job.History.BlocksExecuted.Should().Be(2100);
            job.History.BlocksTotal.Should().Be(5000);
            job.Outcome.Should().Be("running", "its process (this one) still runs");
            reopened.List().Should().Contain(j => j.Id == id);

            reopened.RecordEnd(id, "aborted", 2200, 5000, 1, 0);
            reopened.RecordResume(id, "station-8");
            reopened.SaveCheckpoint(id, cp with { State = SessionState.Completed, LastExecutedLine = 5001 }, durable: true, executed: 5000);
            reopened.RecordEnd(id, "completed", 5000, 5000, 0, 0);
        }

        using var last = JobStores.Open(location);
        var done = last.Get(id)!;
        done.Outcome.Should().Be("completed");
        done.History.Resumes.Should().Be(1);
        done.History.Stops.Should().Be(1);
        done.History.Station.Should().Be("station-8");
        done.History.Ended.Should().NotBeNull();
        done.History.BlocksExecuted.Should().Be(5000);
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_job_whose_process_is_gone_reads_as_interrupted(string engine)
    {
        var location = Location(engine);
        long id;
        using (var store = JobStores.Open(location))
        {
            id = store.CreateJob(Program("gone.nc", "G0 X1\n"), new string('b', 64), Path.Combine(_folder.Path, "m.json"), StrategyKind.Chunk, "sim", null);
        }

        // The runner recorded is this process; a record naming a process that no longer runs is an interrupted job.
        JobHistory.RunnerGone($"{Environment.MachineName}:{int.MaxValue - 1}:0").Should().BeTrue();
        JobHistory.RunnerGone(JobHistory.ThisProcess).Should().BeFalse();
        using var reopened = JobStores.Open(location);
        reopened.Get(id)!.Outcome.Should().Be("running");
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

    /// <summary>A program whose content is this test run's own (the PostgreSQL store is shared by every run).</summary>
    private string Program(string name, string text)
    {
        var path = Path.Combine(_folder.NewFolder("p"), name);
        File.WriteAllText(path, $"({Guid.NewGuid():N})\n" + text, new UTF8Encoding(false));
        return path;
    }

    private static string FileSha(string path) => Convert.ToHexStringLower(System.Security.Cryptography.SHA256.HashData(File.ReadAllBytes(path)));
}
