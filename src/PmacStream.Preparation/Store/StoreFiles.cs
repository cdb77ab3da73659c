using Microsoft.Data.Sqlite;
using Serilog;

namespace PmacStream.Preparation.Store;

/// <summary>The SQLite store file's set-up: its folder, and the records of the per-PC <c>jobs.db</c> of earlier versions.</summary>
public static class StoreFiles
{
    private static readonly ILogger Logger = Log.ForContext(typeof(StoreFiles));

    /// <summary>The job database of earlier versions beside the default store (<c>~/.pmacstream/jobs.db</c>).</summary>
    public static string LegacyJobDatabase => Path.Combine(Path.GetDirectoryName(StoreLocation.DefaultSqlitePath)!, "jobs.db");

    /// <summary>
    /// Makes the store file's folder; when the default store does not exist yet and an earlier version's
    /// <c>jobs.db</c> lies beside it, the store starts as a copy of it (<c>VACUUM INTO</c>: its jobs and checkpoints,
    /// listed and resumable as they were; the old file stays untouched).
    /// </summary>
    public static void PrepareSqlite(string path)
    {
        var full = Path.GetFullPath(path);
        Directory.CreateDirectory(Path.GetDirectoryName(full)!);
        if (File.Exists(full) || !string.Equals(full, Path.GetFullPath(StoreLocation.DefaultSqlitePath), StringComparison.Ordinal) || !File.Exists(LegacyJobDatabase))
        {
            return;
        }

        var temp = full + ".adopting";
        File.Delete(temp);
        using (var db = new SqliteConnection(new SqliteConnectionStringBuilder { DataSource = LegacyJobDatabase, Mode = SqliteOpenMode.ReadOnly, Pooling = false }.ToString()))
        {
            db.Open();
            using var cmd = db.CreateCommand();
            cmd.CommandText = "VACUUM INTO $to";
            cmd.Parameters.AddWithValue("$to", temp);
            cmd.ExecuteNonQuery();
        }

        File.Move(temp, full);
        Logger.Information("store {Store}: started from the jobs of {Legacy} (kept as it was)", full, LegacyJobDatabase);
    }
}
