using System.Diagnostics;
using System.Globalization;
using Microsoft.Data.Sqlite;

namespace PmacStream.Streaming;

/// <summary>
/// Who has the job database open, recorded in the database file itself (copied out of the write-ahead log at once):
/// a process that stops without closing leaves its row, and its last writes in the write-ahead log. If that log is
/// then missing, those writes (jobs, checkpoints) are gone without a trace in SQLite; the row is the trace. A clean
/// close removes the process's own row and those of processes that are gone (their log was recovered by this one).
/// </summary>
internal static class JobStoreOpeners
{
    public const string Schema = "CREATE TABLE IF NOT EXISTS openers (pid INTEGER NOT NULL, host TEXT NOT NULL, started TEXT NOT NULL, opened TEXT NOT NULL);";

    private static readonly Lazy<(int Pid, string Started)> Self = new(() =>
    {
        using var p = Process.GetCurrentProcess();
        return (p.Id, p.StartTime.ToUniversalTime().ToString("O", CultureInfo.InvariantCulture));
    });

    /// <summary>The processes recorded as having the database open (at most a few), as text for a message.</summary>
    public static IReadOnlyList<string> Recorded(SqliteConnection db)
    {
        using var cmd = db.CreateCommand();
        cmd.CommandText = "SELECT pid, host, opened FROM openers ORDER BY rowid LIMIT 5";
        using var r = cmd.ExecuteReader();
        var list = new List<string>();
        while (r.Read())
        {
            list.Add($"process {r.GetValue(0)} on {r.GetValue(1)}, opened {r.GetValue(2)}");
        }

        return list;
    }

    /// <summary>Records this process as an opener and copies the record into the database file.</summary>
    public static long Register(SqliteConnection db)
    {
        long id;
        using (var cmd = db.CreateCommand())
        {
            cmd.CommandText = "INSERT INTO openers (pid, host, started, opened) VALUES ($p, $h, $s, $o); SELECT last_insert_rowid();";
            cmd.Parameters.AddWithValue("$p", Self.Value.Pid);
            cmd.Parameters.AddWithValue("$h", Environment.MachineName);
            cmd.Parameters.AddWithValue("$s", Self.Value.Started);
            cmd.Parameters.AddWithValue("$o", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            id = (long)cmd.ExecuteScalar()!;
        }

        // Best effort (PASSIVE never waits): with another process reading, the row may stay in the log a while.
        using (var cp = db.CreateCommand())
        {
            cp.CommandText = "PRAGMA wal_checkpoint(PASSIVE)";
            cp.ExecuteNonQuery();
        }

        return id;
    }

    /// <summary>Removes this opener's row and those of processes on this machine that no longer run.</summary>
    public static void Unregister(SqliteConnection db, long id)
    {
        var gone = new List<long> { id };
        using (var cmd = db.CreateCommand())
        {
            cmd.CommandText = "SELECT rowid, pid, started FROM openers WHERE host = $h AND rowid <> $id";
            cmd.Parameters.AddWithValue("$h", Environment.MachineName);
            cmd.Parameters.AddWithValue("$id", id);
            using var r = cmd.ExecuteReader();
            while (r.Read())
            {
                if (r.GetValue(1) is long pid && r.GetValue(2) is string started && !Running(pid, started))
                {
                    gone.Add(r.GetInt64(0));
                }
            }
        }

        using var delete = db.CreateCommand();
        delete.CommandText = $"DELETE FROM openers WHERE rowid IN ({string.Join(',', gone)})";
        delete.ExecuteNonQuery();
    }

    private static bool Running(long pid, string started)
    {
        if (pid is <= 0 or > int.MaxValue)
        {
            return false;
        }

        try
        {
            using var p = Process.GetProcessById((int)pid);
            return !DateTimeOffset.TryParse(started, CultureInfo.InvariantCulture, DateTimeStyles.RoundtripKind, out var t)
                || Math.Abs((p.StartTime.ToUniversalTime() - t.UtcDateTime).TotalSeconds) < 2;
        }
        catch (Exception e) when (e is ArgumentException or InvalidOperationException or System.ComponentModel.Win32Exception or NotSupportedException)
        {
            return false;
        }
    }
}
