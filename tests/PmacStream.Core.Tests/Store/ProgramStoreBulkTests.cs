using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

/// <summary>The new-file fast path of <c>check --db</c> (<see cref="ProgramStore.ImportToNewFile"/>).</summary>
public sealed class ProgramStoreBulkTests : IDisposable
{
    private readonly TestFolder _temp = new("store-bulk");

    private string Demo => RepoRoot.DemoProgram;

    public void Dispose()
    {
        Microsoft.Data.Sqlite.SqliteConnection.ClearAllPools();
        _temp.Dispose();
    }

    [Fact]
    public void New_file_import_stores_the_same_rows_as_the_ordinary_import_and_leaves_a_wal_store()
    {
        var fresh = Path.Combine(_temp.Path, "new.db");
        var (id, summary) = ProgramStore.ImportToNewFile(fresh, Demo, MachineProfile.Default);
        Directory.GetFiles(_temp.Path).Select(Path.GetFileName).Should().Equal("new.db");

        using var reference = ProgramStore.Open(Path.Combine(_temp.Path, "ref.db"));
        var (refId, refSummary) = reference.Import(Demo, MachineProfile.Default);
        summary.ToString().Should().Be(refSummary.ToString());

        using var store = ProgramStore.Open(fresh);
        store.ReadBlocks(id).Should().Equal(reference.ReadBlocks(refId));
        var info = store.GetProgram(id)!;
        info.Blocks.Should().Be(summary.Blocks);
        info.Sha256.Should().Be(reference.GetProgram(refId)!.Sha256);

        using var cmd = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={fresh}");
        cmd.Open();
        using var q = cmd.CreateCommand();
        q.CommandText = "PRAGMA journal_mode";
        q.ExecuteScalar().Should().Be("wal");

        // The new store takes further programs like any other.
        var (second, _) = store.Import(Demo, MachineProfile.Default);
        second.Should().NotBe(id);
        store.ListPrograms().Should().HaveCount(2);
    }

    [Fact]
    public void Diagnostics_of_a_bad_program_are_stored_and_reported_in_order()
    {
        var bad = Path.Combine(_temp.Path, "bad.nc");
        File.WriteAllText(bad, "O1\nG01 X1\nG05 Y-\n");
        var seen = new List<string>();
        var (id, summary) = ProgramStore.ImportToNewFile(Path.Combine(_temp.Path, "bad.db"), bad, MachineProfile.Default, d => seen.Add(d.Code));
        summary.Errors.Should().Be(3);
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "bad.db"));
        store.GetDiagnostics(id).Select(d => d.Code).Should().Equal(seen);
        store.ReadBlocks(id).Select(b => b.Line).Should().Equal(2, 3);
    }

    [Fact]
    public void A_cancelled_or_failed_import_leaves_no_file_at_all()
    {
        var target = Path.Combine(_temp.Path, "x.db");
        using var cts = new CancellationTokenSource();
        cts.Cancel();
        var cancelled = () => ProgramStore.ImportToNewFile(target, Demo, MachineProfile.Default, cancellationToken: cts.Token);
        cancelled.Should().Throw<OperationCanceledException>();

        var missing = () => ProgramStore.ImportToNewFile(target, Path.Combine(_temp.Path, "missing.nc"), MachineProfile.Default);
        missing.Should().Throw<FileNotFoundException>();

        // A failure in the middle (the diagnostic callback throws at the first diagnostic of a long program).
        var bad = Path.Combine(_temp.Path, "late-error.nc");
        File.WriteAllText(bad, "O1\n" + string.Concat(Enumerable.Range(1, 5000).Select(i => $"N{i} G01 X{i} F100\n")) + "G99\n");
        var thrown = () => ProgramStore.ImportToNewFile(target, bad, MachineProfile.Default, _ => throw new InvalidOperationException("boom"));
        thrown.Should().Throw<InvalidOperationException>();

        Directory.GetFiles(_temp.Path).Select(Path.GetFileName).Should().Equal("late-error.nc");
    }

    [Fact]
    public void An_existing_database_is_refused_and_kept()
    {
        var target = Path.Combine(_temp.Path, "old.db");
        File.WriteAllText(target, "not touched");
        var act = () => ProgramStore.ImportToNewFile(target, Demo, MachineProfile.Default);
        act.Should().Throw<IOException>().WithMessage("*already exists*");
        File.ReadAllText(target).Should().Be("not touched");
    }
}
