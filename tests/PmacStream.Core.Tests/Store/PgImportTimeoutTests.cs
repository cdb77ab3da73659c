using System.Diagnostics;
using Npgsql;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

/// <summary>
/// An import into PostgreSQL gives its statements a timeout of their own, in proportion to the program (Npgsql's
/// default 30 s is what a 1M-block import hit on a loaded server); a timeout forced short shows that every statement,
/// commit included, is held to it, and that a timed-out import leaves nothing behind.
/// </summary>
public sealed class PgImportTimeoutTests : IDisposable
{
    private readonly TestFolder _folder = new("pg-import-timeout");

    public void Dispose() => _folder.Dispose();

    [Fact]
    public void The_import_timeout_grows_with_the_program_beyond_npgsqls_default()
    {
        PgProgramStore.ImportTimeoutFor(1_000).Should().Be(TimeSpan.FromMinutes(5));
        PgProgramStore.ImportTimeoutFor(30_000_000).Should().BeGreaterThanOrEqualTo(TimeSpan.FromMinutes(10), "a 1M-block CAM program is about 30 MB");
        PgProgramStore.ImportTimeoutFor(300_000_000).Should().BeGreaterThan(PgProgramStore.ImportTimeoutFor(30_000_000));
    }

    [SkippableFact]
    public void A_blocked_import_fails_after_its_own_timeout_and_stores_nothing()
    {
        var (station, admin) = Requires.Postgres();
        Skip.If(admin is null, "PMACSTREAM_TEST_PG_ADMIN is not set: no role that may lock the programs table");
        using (PgSchema.OpenMigrated(StoreLocation.Parse(admin!)))
        {
        }

        var file = Path.Combine(_folder.Path, $"blocked-{Guid.NewGuid():N}.nc");
        File.WriteAllText(file, $"({Guid.NewGuid():N})\nG21 G90\nG00 X0 Y0\nG01 X10 F300\nM30\n");
        using var store = PgProgramStore.Open(StoreLocation.Parse(station));
        store.ImportTimeout = TimeSpan.FromSeconds(2);
        var clock = new Stopwatch();
        using (var locker = new NpgsqlConnection(admin))
        {
            locker.Open();
            using var tx = locker.BeginTransaction();
            using (var lockCmd = new NpgsqlCommand("LOCK TABLE programs IN ACCESS EXCLUSIVE MODE", locker, tx))
            {
                lockCmd.ExecuteNonQuery();
            }

            clock.Start();
            var act = () => store.ImportRevision(file, MachineProfile.Default);
            act.Should().Throw<NpgsqlException>().Where(e => e.InnerException is TimeoutException || e.Message.Contains("timeout", StringComparison.OrdinalIgnoreCase),
                "the import's first statement waits for the lock longer than the import's timeout");
            clock.Stop();
            tx.Rollback();
        }

        clock.Elapsed.Should().BeLessThan(TimeSpan.FromSeconds(25), "the import's own 2 s timeout, not Npgsql's 30 s default");
        store.ListRevisions().Should().NotContain(p => p.Path == Path.GetFullPath(file), "a timed-out import is rolled back");

        store.ImportTimeout = null; // in proportion again: the same import goes through once nothing blocks it
        store.ImportRevision(file, MachineProfile.Default).Existing.Should().BeFalse();
    }

    [SkippableFact]
    public void Removing_a_revision_is_held_to_the_import_timeout_not_npgsqls_default()
    {
        var (station, admin) = Requires.Postgres();
        Skip.If(admin is null, "PMACSTREAM_TEST_PG_ADMIN is not set: no role that may lock the blocks table");
        using (PgSchema.OpenMigrated(StoreLocation.Parse(admin!)))
        {
        }

        var file = Path.Combine(_folder.Path, $"rm-{Guid.NewGuid():N}.nc");
        File.WriteAllText(file, $"({Guid.NewGuid():N})\nG21 G90\nG00 X0 Y0\nG01 X10 F300\nM30\n");
        using var store = PgProgramStore.Open(StoreLocation.Parse(station));
        var id = store.ImportRevision(file, MachineProfile.Default).Id;
        store.ImportTimeout = TimeSpan.FromSeconds(2);
        var clock = Stopwatch.StartNew();
        using (var locker = new NpgsqlConnection(admin))
        {
            locker.Open();
            using var tx = locker.BeginTransaction();
            using (var lockCmd = new NpgsqlCommand("LOCK TABLE blocks IN ACCESS EXCLUSIVE MODE", locker, tx))
            {
                lockCmd.ExecuteNonQuery();
            }

            var act = () => store.DeleteProgram(id);
            act.Should().Throw<NpgsqlException>().Where(e => e.InnerException is TimeoutException || e.Message.Contains("timeout", StringComparison.OrdinalIgnoreCase));
            clock.Stop();
            tx.Rollback();
        }

        clock.Elapsed.Should().BeLessThan(TimeSpan.FromSeconds(25), "the store's own 2 s timeout, not Npgsql's 30 s default");
        store.ListRevisions().Should().Contain(p => p.Id == id, "a timed-out removal is rolled back");
        store.DeleteProgram(id);
        store.ListRevisions().Should().NotContain(p => p.Id == id);
    }
}
