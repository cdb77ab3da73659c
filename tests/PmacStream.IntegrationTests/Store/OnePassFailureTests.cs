using System.Data.Common;
using System.Text;
using Microsoft.Data.Sqlite;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// A split that stores the revision in the same pass leaves nothing half-written whatever stops it: a store that fails
/// in the middle (the storing thread's error is the one reported, the reading and splitting threads stop), or a
/// cancellation. No chunk folder is published, no working folder is left, and the store holds no row of the program.
/// </summary>
public sealed class OnePassFailureTests : IDisposable
{
    private readonly TestFolder _folder = new("one-pass-failure");

    public void Dispose() => _folder.Dispose();

    [Fact]
    public async Task A_store_failing_in_the_middle_stops_the_pass_and_keeps_nothing()
    {
        var (file, storePath) = Setup();
        using (var c = new SqliteConnection($"Data Source={storePath}"))
        {
            c.Open();
            using var cmd = c.CreateCommand();
            // The store fills up after 3,000 blocks (of 20,000), several batches into the pass.
            cmd.CommandText = "CREATE TRIGGER disk_full BEFORE INSERT ON blocks WHEN NEW.Lines > 3000 BEGIN SELECT RAISE(ABORT, 'database or disk is full'); END;";
            cmd.ExecuteNonQuery();
        }

        var outDir = Path.Combine(_folder.Path, "chunks");
        using (var store = ProgramStores.Open(StoreLocation.Sqlite(storePath)))
        {
            var pass = Task.Run(() =>
            {
                using var import = RevisionImport.Begin(store, file, new FileInfo(file).Length, MachineProfile.Default);
                Splitter.SplitAndImport(file, Options(outDir), import);
            });
            var failed = await FluentActions.Awaiting(() => pass.WaitAsync(TimeSpan.FromMinutes(2))).Should().ThrowAsync<DbException>();
            failed.Which.Message.Should().Contain("database or disk is full", "the store's own error, not the reader's cancellation");
        }

        NothingLeft(storePath, outDir);

        // Through the job service (what stream FILE and the HMI call): the store's failure is the request's, named.
        var service = new JobService(new JobServiceOptions { Store = StoreLocation.Sqlite(storePath) });
        var prepare = () => service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = true, OutDir = outDir });
        var refused = (await prepare.Should().ThrowAsync<JobException>()).Which;
        refused.Kind.Should().Be(JobErrorKind.BadRequest);
        refused.Message.Should().Contain("cannot import").And.Contain("database or disk is full");
        refused.InnerException.Should().BeAssignableTo<DbException>();
        NothingLeft(storePath, outDir);
    }

    [Fact]
    public async Task A_cancelled_pass_keeps_nothing()
    {
        var (file, storePath) = Setup();
        var outDir = Path.Combine(_folder.Path, "chunks");
        using var cts = new CancellationTokenSource();
        var progress = new CancelAfter(cts, new FileInfo(file).Length / 3);
        using (var store = ProgramStores.Open(StoreLocation.Sqlite(storePath)))
        {
            var pass = Task.Run(() =>
            {
                using var import = RevisionImport.Begin(store, file, new FileInfo(file).Length, MachineProfile.Default);
                Splitter.SplitAndImport(file, Options(outDir), import, progress, cts.Token);
            });
            await FluentActions.Awaiting(() => pass.WaitAsync(TimeSpan.FromMinutes(2))).Should().ThrowAsync<OperationCanceledException>();
        }

        progress.Cancelled.Should().BeTrue("the pass was a third through the file");
        NothingLeft(storePath, outDir);
    }

    private (string File, string Store) Setup()
    {
        var file = Path.Combine(_folder.Path, "long.nc");
        var text = new StringBuilder("G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F600\n");
        for (var i = 0; i < 20_000; i++)
        {
            text.Append("G1 X").Append(i % 100).Append(" Y").Append(i / 100).Append('\n');
        }

        text.Append("G0 Z5\nM30\n");
        File.WriteAllText(file, text.ToString(), new UTF8Encoding(false));
        var storePath = Path.Combine(_folder.Path, "store.db");
        using (ProgramStores.Open(StoreLocation.Sqlite(storePath)))
        {
        }

        return (file, storePath);
    }

    private static SplitOptions Options(string outDir) => RunSettings.Default.ToSplitOptions(MachineProfile.Default, outDir, false) with { BlocksPerChunk = 500 };

    private void NothingLeft(string storePath, string outDir)
    {
        Directory.Exists(outDir).Should().BeFalse("no chunk folder is published");
        Directory.GetDirectories(_folder.Path).Should().BeEmpty("no working folder is left");
        using var c = new SqliteConnection($"Data Source={storePath}");
        c.Open();
        foreach (var table in new[] { "programs", "blocks", "diagnostics", "exec_states", "program_source", "preparations" })
        {
            using var cmd = c.CreateCommand();
            cmd.CommandText = $"SELECT COUNT(*) FROM {table}";
            ((long)cmd.ExecuteScalar()!).Should().Be(0, $"no row of the program in {table}");
        }
    }

    /// <summary>Cancels once the split has read <paramref name="bytes"/> (called on the splitting thread, at once).</summary>
    private sealed class CancelAfter(CancellationTokenSource cts, long bytes) : IProgress<SplitProgress>
    {
        public bool Cancelled { get; private set; }

        public void Report(SplitProgress value)
        {
            if (!Cancelled && value.BytesRead >= bytes)
            {
                Cancelled = true;
                cts.Cancel();
            }
        }
    }
}
