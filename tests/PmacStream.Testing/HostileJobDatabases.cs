using Microsoft.Data.Sqlite;
using PmacStream.Streaming;

namespace PmacStream.Testing;

/// <summary>
/// Job databases damaged the ways the field damages them (docs/hostile-inputs.md names each one and the message it
/// must give): garbage in a field, a file that is not a database, a damaged page, and the files a crash leaves with
/// their write-ahead log damaged or missing. Each is made fresh in its own folder and returned as its path.
/// </summary>
public static class HostileJobDatabases
{
    /// <summary>The checkpoint the healthy database's job holds.</summary>
    public static readonly Checkpoint Checkpoint = new(4002, 5, new StreamPosition(6, 5001), true, 5, SessionState.Faulted, new DateTimeOffset(2026, 5, 1, 8, 0, 0, TimeSpan.Zero));

    /// <summary>A new folder under the temp folder.</summary>
    public static string Folder(string tag)
    {
        var d = Path.Combine(Path.GetTempPath(), "pmacstream-hostile", $"{tag}-{Guid.NewGuid():N}");
        Directory.CreateDirectory(d);
        return d;
    }

    /// <summary>A database with one unfinished job (id 1, a checkpoint), closed cleanly.</summary>
    public static string Healthy(string folder)
    {
        var db = Path.Combine(folder, "jobs.db");
        using var store = JobStore.Open(db);
        Fill(store);
        return db;
    }

    /// <summary>The healthy database with one column of job 1 set to a raw SQL value (<c>'garbage'</c>, <c>NULL</c>, <c>-3</c>...).</summary>
    public static string WithField(string folder, string column, string sqlValue)
    {
        var db = Healthy(folder);
        using var raw = new SqliteConnection(new SqliteConnectionStringBuilder { DataSource = db, Pooling = false }.ToString());
        raw.Open();
        using var cmd = raw.CreateCommand();
        cmd.CommandText = $"UPDATE jobs SET {column} = {sqlValue} WHERE id = 1";
        cmd.ExecuteNonQuery().Should1();
        return db;
    }

    /// <summary>A file of random bytes where the database should be.</summary>
    public static string NotADatabase(string folder)
    {
        var db = Path.Combine(folder, "jobs.db");
        var bytes = new byte[8192];
        new Random(20).NextBytes(bytes);
        File.WriteAllBytes(db, bytes);
        return db;
    }

    /// <summary>The healthy database (with many jobs, so the table spans pages) with one page overwritten.</summary>
    public static string PageDamaged(string folder)
    {
        var db = Path.Combine(folder, "jobs.db");
        using (var store = JobStore.Open(db))
        {
            for (var i = 0; i < 200; i++)
            {
                Fill(store);
            }
        }

        using (var f = new FileStream(db, FileMode.Open, FileAccess.ReadWrite))
        {
            var page = new byte[4096];
            new Random(21).NextBytes(page);
            f.Position = 4096 * 2; // page 3: inside the jobs table's b-tree
            f.Write(page);
        }

        return db;
    }

    /// <summary>
    /// The files as a killed process leaves them: copied while the store is open, after the job and its checkpoints
    /// were written (they are still in the write-ahead log).
    /// </summary>
    public static string CrashImage(string folder)
    {
        var live = Folder("live");
        var source = Path.Combine(live, "jobs.db");
        var db = Path.Combine(folder, "jobs.db");
        using (var store = JobStore.Open(source))
        {
            Fill(store);
            foreach (var suffix in new[] { string.Empty, "-wal", "-shm" })
            {
                if (File.Exists(source + suffix))
                {
                    File.Copy(source + suffix, db + suffix);
                }
            }
        }

        return db;
    }

    /// <summary>A crash image whose write-ahead log was deleted.</summary>
    public static string WalMissing(string folder)
    {
        var db = CrashImage(folder);
        File.Delete(db + "-wal");
        return db;
    }

    /// <summary>A crash image with bytes of the write-ahead log's first frame changed (committed frames follow it).</summary>
    public static string WalDamaged(string folder)
    {
        var db = CrashImage(folder);
        using var f = new FileStream(db + "-wal", FileMode.Open, FileAccess.ReadWrite);
        f.Position = 32 + 24 + 100; // header, frame header, then into the first page
        f.Write([0xDE, 0xAD, 0xBE, 0xEF]);
        return db;
    }

    private static void Fill(JobStore store)
    {
        var id = store.CreateJob("/tmp/part.nc", new string('a', 64), "/tmp/part_chunks/manifest.json", StrategyKind.Chunk, "tcp://127.0.0.1:1025", null);
        store.SaveCheckpoint(id, Checkpoint with { State = SessionState.Running, LastExecutedLine = 3000 }, durable: true);
        store.SaveCheckpoint(id, Checkpoint, durable: true);
    }

    private static void Should1(this int rows)
    {
        if (rows != 1)
        {
            throw new InvalidOperationException($"expected to change job 1, changed {rows} rows");
        }
    }
}
