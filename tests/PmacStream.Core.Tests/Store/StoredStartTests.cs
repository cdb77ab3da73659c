using System.Text;
using PmacStream.GCode;
using PmacStream.GCode.Expansion;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

/// <summary>
/// A start from a stored revision reads the block's state from the store, and its plan is exactly the one
/// re-interpreting the source from the top gives: for the corpus programs at lines spread through each, and for a
/// program that sets tables, shifts, tool lengths, inches, compensation and cycles at every motion block, on SQLite
/// and (where <c>PMACSTREAM_TEST_PG</c> names a server) on PostgreSQL.
/// </summary>
public sealed class StoredStartTests : IDisposable
{
    private readonly TestFolder _folder = new("stored-start");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    /// <summary>Tables, shifts, an extended offset, tool lengths, inches, cutter compensation, a cycle and incremental moves.</summary>
    internal const string Busy =
        "G21 G90 G17\nG10 L2 P0 X1.5\nG10 L2 P2 X30. Y-20. Z5.\nG10 L10 P2 R55.\nG54.1 P3\nG52 X10. Y10.\n" +
        "G00 X0 Y0 Z10.\nG92 X5. Y10.\nG01 X5. F300.\nX10.\nG92.1\nG52 X0 Y0\nG55\nT2 M06\nG43 H2 Z20.\nS9000 M03\nM08\n" +
        "G00 X-5. Y-5.\nG41 D1 G01 X0 Y0 F500\nG01 X40.\nY30.\nX0\nY0\nG40 G00 X-10. Y-10.\nG49\nG20\nG00 X1. Y1. Z0.5\n" +
        "G01 Z-0.1 F10.\nX2. Y2.\nG21\nG00 Z30.\nG81 X10. Y10. Z-5. R2. F200\nX20.\nX30. Y20.\nG80\nG91 G01 X5. Y5.\nX-5.\n" +
        "G90 G00 Z50.\nG02 X20. Y10. I5. J0 F400\nG03 X10. Y10. R5.\nM09\nM05\nM30\n";

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_stored_start_is_the_start_re_interpretation_gives_for_the_corpus(string engine)
    {
        var location = Location(engine);
        var profile = MachineProfile.Default;
        var compared = 0;
        using var store = ProgramStores.Open(location);
        foreach (var corpus in Requires.Corpus())
        {
            if (ProgramExpansion.Applies(corpus, profile))
            {
                continue; // stored as its expansion: the source's lines are not the stored blocks' (the test below covers the rest)
            }

            if (new FileInfo(corpus).Length > 1_000_000)
            {
                continue; // a few seconds per re-interpreted start in a Debug build: the bench's start-from-line script takes the big ones
            }

            var file = Copy(corpus);
            var id = store.ImportRevision(file, profile).Id;
            var lines = File.ReadLines(file).Count();
            foreach (var line in Spread(lines, 8))
            {
                compared += Compare(store, id, file, line, profile) ? 1 : 0;
            }
        }

        compared.Should().BeGreaterThan(40, "most corpus programs have motion after most lines");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_stored_start_restores_tables_shifts_and_offsets_as_re_interpretation_does(string engine)
    {
        var location = Location(engine);
        using var store = ProgramStores.Open(location);
        foreach (var name in new[] { "fanuc-mill", "linuxcnc-mill" })
        {
            var profile = MachineProfile.Named(name)!;
            var file = Program($"busy-{name}.nc", Busy);
            var id = store.ImportRevision(file, profile).Id;
            var lines = File.ReadLines(file).Count();
            var compared = Enumerable.Range(1, lines).Count(line => Compare(store, id, file, line, profile));
            compared.Should().BeGreaterThan(30, $"every line up to the last motion block plans a start ({name})");
        }

        // The tables and shifts the skipped blocks set come from the store: line 10 of the (one line longer) program.
        var fanuc = MachineProfile.Named("fanuc-mill")!;
        var busy = Program("busy.nc", Busy);
        var plan = StartFromLine.Plan(store, store.ImportRevision(busy, fanuc).Id, 11, new StartPlanOptions { Profile = fanuc });
        plan.PmacLines.Take(6).Should().Equal("G99.9", "G10 L2 P0 X1.5 Y0 Z0", "G10 L2 P2 X30 Y-20 Z5", "G10 L1 P2 Z55", "G52 X10 Y10 Z0", "G92 X-5 Y-10 Z0");
    }

    [Fact]
    public void A_revision_stored_without_execution_states_says_so()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "old.db"));
        var file = Program("old.nc", "G0 X1 Y1 Z5\nG1 Z-1 F100\nG1 X5\nM30\n");
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(file, MachineProfile.Default).Id;
        }

        using (var raw = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={location.Target};Pooling=False"))
        {
            raw.Open();
            using var cmd = raw.CreateCommand();
            cmd.CommandText = "DELETE FROM exec_states"; // as a revision imported before schema 7 has none
            cmd.ExecuteNonQuery();
        }

        using var reopened = ProgramStores.Open(location);
        var act = () => StartFromLine.Plan(reopened, id, 3, new StartPlanOptions());
        act.Should().Throw<StoredStateMissingException>().Which.ProgramId.Should().Be(id);
        var beyond = () => StartFromLine.Plan(reopened, id, 5, new StartPlanOptions());
        beyond.Should().Throw<ArgumentOutOfRangeException>("no motion block follows line 5");
    }

    [Fact]
    public async Task The_job_service_plans_a_stored_revision_from_the_store_and_counts_what_it_re_interprets()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "service.db"));
        var file = Program("service.nc", Busy);
        var fanuc = MachineProfile.Named("fanuc-mill")!;
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(file, fanuc).Id;
        }

        var service = new PmacStream.Jobs.JobService(new PmacStream.Jobs.JobServiceOptions { Store = location });
        var settings = PmacStream.Jobs.RunSettings.Default;
        var prepared = await service.PrepareAsync(new PmacStream.Jobs.PrepareRequest(file, settings) { Profile = fanuc, Force = true, OutDir = _folder.NewFolder("split") });
        var stored = service.PlanStartFromStore(id, prepared.Program, 12, settings, fanuc);
        stored.GCode.Should().Equal(service.PlanStart(prepared.Program, 12, settings, fanuc).GCode);
        (service.StartsFromStore, service.StartFallbacks).Should().Be((1L, 0L), "the state came from the store");

        // Another profile than the one the revision was interpreted under: its tool table and offsets are not the stored positions'.
        var linux = MachineProfile.Named("linuxcnc-mill")!;
        var other = service.PlanStartFromStore(id, prepared.Program, 12, settings, linux);
        other.GCode.Should().Equal(service.PlanStart(prepared.Program, 12, settings, linux).GCode);
        (service.StartsFromStore, service.StartFallbacks).Should().Be((1L, 1L), "re-interpreted, and counted");

        var wrong = () => service.PlanStartFromStore(id + 1000, prepared.Program, 12, settings, fanuc);
        wrong.Should().Throw<PmacStream.Jobs.JobException>().WithMessage("no program*");
    }

    /// <summary>Plans the line both ways (fixed and highest-so-far safe Z); false when no motion block follows it.</summary>
    private static bool Compare(IProgramRevisions store, long id, string file, int line, MachineProfile profile)
    {
        var options = new StartPlanOptions { Profile = profile, SafeZMode = line % 2 == 0 ? SafeZMode.HighestSoFar : SafeZMode.Fixed, Clearance = 4 };
        StartPlan expected;
        try
        {
            expected = StartFromLine.Plan(file, line, options);
        }
        catch (ArgumentOutOfRangeException)
        {
            var none = () => StartFromLine.Plan(store, id, line, options);
            none.Should().Throw<ArgumentOutOfRangeException>($"{Path.GetFileName(file)}:{line}: no motion block after it either way");
            return false;
        }

        var stored = StartFromLine.Plan(store, id, line, options);
        var where = $"{Path.GetFileName(file)}:{line} ({profile.Name})";
        stored.Line.Should().Be(expected.Line, where);
        stored.Start.Should().Be(expected.Start, where);
        stored.SafeZ.Should().Be(expected.SafeZ, where);
        stored.GCode.Should().Equal(expected.GCode, where);
        stored.PmacLines.Should().Equal(expected.PmacLines, where);
        stored.State.Should().BeEquivalentTo(expected.State, where);
        return true;
    }

    private static IEnumerable<int> Spread(int lines, int count) =>
        Enumerable.Range(0, count).Select(i => 1 + (int)((long)i * Math.Max(0, lines - 1) / Math.Max(1, count - 1))).Distinct();

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

    /// <summary>A copy whose content is this test run's own (the PostgreSQL store is shared by every run): one comment line first.</summary>
    private string Copy(string corpus)
    {
        var path = Path.Combine(_folder.NewFolder("c"), Path.GetFileName(corpus));
        using var output = File.Create(path);
        output.Write(Encoding.ASCII.GetBytes($"({Guid.NewGuid():N})\n"));
        using var input = File.OpenRead(corpus);
        input.CopyTo(output);
        return path;
    }

    private string Program(string name, string text)
    {
        var path = Path.Combine(_folder.NewFolder("p"), name);
        File.WriteAllText(path, $"({Guid.NewGuid():N})\n" + text, new UTF8Encoding(false));
        return path;
    }
}
