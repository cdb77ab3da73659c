using System.Globalization;
using Microsoft.Data.Sqlite;
using Npgsql;

namespace PmacStream.Preparation.Store;

/// <summary>One alarm in the store's history: raised on a machine (during a job or not), cleared later.</summary>
/// <param name="Id">The row's id.</param>
/// <param name="Machine">The controller it was seen on (its connection, or the machine's name).</param>
/// <param name="Code">Stable code (<c>limit+</c>, <c>fatal-following-error</c>, ...).</param>
/// <param name="Motor">Motor number.</param>
/// <param name="Axis">Axis letter.</param>
/// <param name="Text">Clear text when it was raised.</param>
/// <param name="Raised">When it was first seen.</param>
/// <param name="Cleared">When it was seen gone, or null while active.</param>
/// <param name="JobId">The job on the machine when it was raised, or null.</param>
public sealed record StoredAlarm(long Id, string Machine, string Code, int Motor, string Axis, string Text, DateTimeOffset Raised, DateTimeOffset? Cleared, long? JobId);

/// <summary>
/// The alarm history of a store (migration 5, table <c>alarms</c>), on SQLite or PostgreSQL: what the console records as
/// alarms come and go, and what <c>alarms --history</c> and the HMI list.
/// </summary>
public interface IAlarmStore : IDisposable
{
    /// <summary>Records an alarm raised; returns its id.</summary>
    long Raise(string machine, string code, int motor, string axis, string text, DateTimeOffset raised, long? jobId);

    /// <summary>Marks an alarm cleared.</summary>
    void Clear(long id, DateTimeOffset cleared);

    /// <summary>The alarms of <paramref name="machine"/> (null: every machine), newest first.</summary>
    IReadOnlyList<StoredAlarm> List(string? machine = null);

    /// <summary>True when nothing has been recorded yet (an old alarms.jsonl may be imported).</summary>
    bool IsEmpty { get; }
}

/// <summary>Opens a store's alarm history by its location.</summary>
public static class AlarmStores
{
    /// <summary>The table, as both engines create it (migration 5).</summary>
    internal const string SqliteSchema = """
        CREATE TABLE IF NOT EXISTS alarms (
          id INTEGER PRIMARY KEY AUTOINCREMENT, machine TEXT NOT NULL, code TEXT NOT NULL, motor INTEGER NOT NULL, axis TEXT NOT NULL,
          text TEXT NOT NULL, raised TEXT NOT NULL, cleared TEXT, job_id INTEGER);
        CREATE INDEX IF NOT EXISTS alarms_machine ON alarms(machine, cleared);
        """;

    /// <summary>The same table on PostgreSQL.</summary>
    internal const string PgSchemaSql = """
        CREATE TABLE IF NOT EXISTS alarms (
          id BIGSERIAL PRIMARY KEY, machine TEXT NOT NULL, code TEXT NOT NULL, motor INTEGER NOT NULL, axis TEXT NOT NULL,
          text TEXT NOT NULL, raised TEXT NOT NULL, cleared TEXT, job_id BIGINT);
        CREATE INDEX IF NOT EXISTS alarms_machine ON alarms(machine, cleared);
        """;

    /// <summary>Opens (creating and migrating when needed) the alarm history at <paramref name="location"/>.</summary>
    public static IAlarmStore Open(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        if (location.Engine == StoreEngine.Postgres)
        {
            return new PgAlarms(PgSchema.OpenMigrated(location));
        }

        StoreFiles.PrepareSqlite(location.Target);
        var connection = new SqliteConnection(new SqliteConnectionStringBuilder { DataSource = location.Target, Mode = SqliteOpenMode.ReadWriteCreate, Pooling = false, DefaultTimeout = 30 }.ToString());
        try
        {
            connection.Open();
            using (var cmd = connection.CreateCommand())
            {
                cmd.CommandText = "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;";
                using var results = cmd.ExecuteReader();
                while (results.NextResult())
                {
                }
            }

            SqliteMigrations.Apply(connection);
            return new SqliteAlarms(connection);
        }
        catch
        {
            connection.Dispose();
            throw;
        }
    }

    private static string Iso(DateTimeOffset t) => t.ToUniversalTime().ToString("O", CultureInfo.InvariantCulture);

    private static DateTimeOffset Time(string s) => DateTimeOffset.Parse(s, CultureInfo.InvariantCulture, DateTimeStyles.RoundtripKind);

    private static StoredAlarm Read(System.Data.Common.DbDataReader r) => new(
        r.GetInt64(0), r.GetString(1), r.GetString(2), r.GetInt32(3), r.GetString(4), r.GetString(5), Time(r.GetString(6)),
        r.IsDBNull(7) ? null : Time(r.GetString(7)), r.IsDBNull(8) ? null : r.GetInt64(8));

    private const string Columns = "id, machine, code, motor, axis, text, raised, cleared, job_id";

    private sealed class SqliteAlarms(SqliteConnection db) : IAlarmStore
    {
        public bool IsEmpty
        {
            get
            {
                using var cmd = db.CreateCommand();
                cmd.CommandText = "SELECT COUNT(*) FROM alarms";
                return (long)cmd.ExecuteScalar()! == 0;
            }
        }

        public long Raise(string machine, string code, int motor, string axis, string text, DateTimeOffset raised, long? jobId)
        {
            using var cmd = db.CreateCommand();
            cmd.CommandText = "INSERT INTO alarms (machine, code, motor, axis, text, raised, job_id) VALUES ($m, $c, $mo, $a, $t, $r, $j) RETURNING id";
            cmd.Parameters.AddWithValue("$m", machine);
            cmd.Parameters.AddWithValue("$c", code);
            cmd.Parameters.AddWithValue("$mo", motor);
            cmd.Parameters.AddWithValue("$a", axis);
            cmd.Parameters.AddWithValue("$t", text);
            cmd.Parameters.AddWithValue("$r", Iso(raised));
            cmd.Parameters.AddWithValue("$j", (object?)jobId ?? DBNull.Value);
            return (long)cmd.ExecuteScalar()!;
        }

        public void Clear(long id, DateTimeOffset cleared)
        {
            using var cmd = db.CreateCommand();
            cmd.CommandText = "UPDATE alarms SET cleared=$c WHERE id=$id AND cleared IS NULL";
            cmd.Parameters.AddWithValue("$c", Iso(cleared));
            cmd.Parameters.AddWithValue("$id", id);
            cmd.ExecuteNonQuery();
        }

        public IReadOnlyList<StoredAlarm> List(string? machine = null)
        {
            using var cmd = db.CreateCommand();
            cmd.CommandText = $"SELECT {Columns} FROM alarms WHERE $m IS NULL OR machine=$m ORDER BY id DESC";
            cmd.Parameters.AddWithValue("$m", (object?)machine ?? DBNull.Value);
            using var r = cmd.ExecuteReader();
            var list = new List<StoredAlarm>();
            while (r.Read())
            {
                list.Add(Read(r));
            }

            return list;
        }

        public void Dispose() => db.Dispose();
    }

    private sealed class PgAlarms(NpgsqlConnection db) : IAlarmStore
    {
        public bool IsEmpty
        {
            get
            {
                using var cmd = new NpgsqlCommand("SELECT COUNT(*) FROM alarms", db);
                return Convert.ToInt64(cmd.ExecuteScalar(), CultureInfo.InvariantCulture) == 0;
            }
        }

        public long Raise(string machine, string code, int motor, string axis, string text, DateTimeOffset raised, long? jobId)
        {
            using var cmd = new NpgsqlCommand("INSERT INTO alarms (machine, code, motor, axis, text, raised, job_id) VALUES (@m, @c, @mo, @a, @t, @r, @j) RETURNING id", db);
            cmd.Parameters.AddWithValue("m", machine);
            cmd.Parameters.AddWithValue("c", code);
            cmd.Parameters.AddWithValue("mo", motor);
            cmd.Parameters.AddWithValue("a", axis);
            cmd.Parameters.AddWithValue("t", text);
            cmd.Parameters.AddWithValue("r", Iso(raised));
            cmd.Parameters.Add(new NpgsqlParameter("j", NpgsqlTypes.NpgsqlDbType.Bigint) { Value = (object?)jobId ?? DBNull.Value });
            return Convert.ToInt64(cmd.ExecuteScalar(), CultureInfo.InvariantCulture);
        }

        public void Clear(long id, DateTimeOffset cleared)
        {
            using var cmd = new NpgsqlCommand("UPDATE alarms SET cleared=@c WHERE id=@id AND cleared IS NULL", db);
            cmd.Parameters.AddWithValue("c", Iso(cleared));
            cmd.Parameters.AddWithValue("id", id);
            cmd.ExecuteNonQuery();
        }

        public IReadOnlyList<StoredAlarm> List(string? machine = null)
        {
            using var cmd = new NpgsqlCommand($"SELECT {Columns} FROM alarms WHERE @m::text IS NULL OR machine=@m ORDER BY id DESC", db);
            cmd.Parameters.Add(new NpgsqlParameter("m", NpgsqlTypes.NpgsqlDbType.Text) { Value = (object?)machine ?? DBNull.Value });
            using var r = cmd.ExecuteReader();
            var list = new List<StoredAlarm>();
            while (r.Read())
            {
                list.Add(Read(r));
            }

            return list;
        }

        public void Dispose() => db.Dispose();
    }
}
