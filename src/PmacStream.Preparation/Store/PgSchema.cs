using System.Globalization;
using Npgsql;

namespace PmacStream.Preparation.Store;

/// <summary>
/// The store's schema on PostgreSQL: the same tables and migration numbers as <see cref="SqliteMigrations"/>, recorded
/// in <c>schema_version</c>. Migrations need the rights to create tables (the database's owner: <c>pmacstream store
/// migrate</c> or the first open by the owner); a station's role only reads and writes rows, so a station finding
/// the schema behind says who must migrate it rather than trying.
/// </summary>
public static class PgSchema
{
    private static readonly (string Name, string Sql)[] Steps =
    [
        ("programs and decoded blocks (check --db)", """
            CREATE TABLE IF NOT EXISTS programs (
              id BIGSERIAL PRIMARY KEY, path TEXT NOT NULL, size BIGINT NOT NULL, sha256 TEXT NOT NULL, lines INTEGER NOT NULL,
              blocks BIGINT NOT NULL, errors INTEGER NOT NULL, warnings INTEGER NOT NULL, estimated_seconds DOUBLE PRECISION NOT NULL,
              profile TEXT NOT NULL, check_summary TEXT NOT NULL, created TEXT NOT NULL, groups TEXT);
            CREATE INDEX IF NOT EXISTS programs_sha ON programs(sha256);
            CREATE TABLE IF NOT EXISTS blocks (
              program_id BIGINT NOT NULL, line INTEGER NOT NULL, byte_offset BIGINT NOT NULL, n DOUBLE PRECISION, block_delete INTEGER NOT NULL,
              ga DOUBLE PRECISION, gb DOUBLE PRECISION, gc DOUBLE PRECISION, gd DOUBLE PRECISION, ge DOUBLE PRECISION, gf DOUBLE PRECISION,
              gg DOUBLE PRECISION, gh DOUBLE PRECISION, gi DOUBLE PRECISION, ma DOUBLE PRECISION, mb DOUBLE PRECISION, mc DOUBLE PRECISION,
              x DOUBLE PRECISION, y DOUBLE PRECISION, z DOUBLE PRECISION, i DOUBLE PRECISION, j DOUBLE PRECISION, k DOUBLE PRECISION,
              r DOUBLE PRECISION, f DOUBLE PRECISION, s DOUBLE PRECISION, t DOUBLE PRECISION, h DOUBLE PRECISION, d DOUBLE PRECISION, p DOUBLE PRECISION,
              motion INTEGER NOT NULL, start_x DOUBLE PRECISION, start_y DOUBLE PRECISION, start_z DOUBLE PRECISION,
              end_x DOUBLE PRECISION, end_y DOUBLE PRECISION, end_z DOUBLE PRECISION,
              center_x DOUBLE PRECISION, center_y DOUBLE PRECISION, center_z DOUBLE PRECISION, length DOUBLE PRECISION, duration DOUBLE PRECISION,
              modal_t INTEGER, modal_h INTEGER, modal_d INTEGER, modal_s DOUBLE PRECISION, modal_f DOUBLE PRECISION, group_state BIGINT,
              PRIMARY KEY (program_id, line));
            CREATE TABLE IF NOT EXISTS group_states (program_id BIGINT NOT NULL, id BIGINT NOT NULL, more TEXT NOT NULL, PRIMARY KEY (program_id, id));
            CREATE TABLE IF NOT EXISTS diagnostics (
              program_id BIGINT NOT NULL, severity TEXT NOT NULL, code TEXT NOT NULL, line INTEGER NOT NULL, col INTEGER NOT NULL, message TEXT NOT NULL);
            CREATE INDEX IF NOT EXISTS diagnostics_program ON diagnostics(program_id, line);
            """),
        ("program revisions: name, source bytes", """
            ALTER TABLE programs ADD COLUMN IF NOT EXISTS name TEXT;
            ALTER TABLE programs ADD COLUMN IF NOT EXISTS revision BIGINT NOT NULL DEFAULT 0;
            CREATE TABLE IF NOT EXISTS program_source (program_id BIGINT NOT NULL, seq BIGINT NOT NULL, data BYTEA NOT NULL, PRIMARY KEY (program_id, seq));
            CREATE INDEX IF NOT EXISTS programs_revision ON programs(sha256, profile, revision);
            """),
        ("jobs and checkpoints", """
            CREATE TABLE IF NOT EXISTS jobs (
              id BIGSERIAL PRIMARY KEY, created TEXT NOT NULL, program_path TEXT NOT NULL, program_sha256 TEXT NOT NULL,
              manifest_path TEXT NOT NULL, strategy TEXT NOT NULL, connection TEXT NOT NULL, from_line BIGINT,
              message TEXT NOT NULL DEFAULT '', cp_time TEXT, cp_state TEXT, cp_last_line BIGINT, cp_chunk BIGINT,
              cp_next_chunk BIGINT, cp_next_line BIGINT, cp_next_exact BIGINT, cp_chunks_downloaded BIGINT, cp_started BIGINT,
              line_probe TEXT NOT NULL DEFAULT 'P501', preamble TEXT, cp_loaded BIGINT, settings TEXT, profile TEXT, profile_identity TEXT);
            """),
        ("job history", """
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS program_id BIGINT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS station TEXT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS machine TEXT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS os_user TEXT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS runner TEXT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS ended TEXT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS outcome TEXT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS blocks_executed BIGINT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS blocks_total BIGINT;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS stops BIGINT NOT NULL DEFAULT 0;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS alarms BIGINT NOT NULL DEFAULT 0;
            ALTER TABLE jobs ADD COLUMN IF NOT EXISTS resumes BIGINT NOT NULL DEFAULT 0;
            """),
        ("alarm history", AlarmStores.PgSchemaSql), // 5: a table of its own, created only when missing
        ("machine leases", SqliteMigrations.LeaseSchema), // the same text runs on both engines
        ("execution states and stored preparations", """
            ALTER TABLE programs ADD COLUMN IF NOT EXISTS profile_identity TEXT;
            CREATE TABLE IF NOT EXISTS exec_states (
              program_id BIGINT NOT NULL, line INTEGER NOT NULL, offset_x DOUBLE PRECISION NOT NULL, offset_y DOUBLE PRECISION NOT NULL,
              offset_z DOUBLE PRECISION NOT NULL, highest_z DOUBLE PRECISION, controller TEXT NOT NULL, selection TEXT,
              PRIMARY KEY (program_id, line));
            CREATE TABLE IF NOT EXISTS preparations (
              id BIGSERIAL PRIMARY KEY, program_id BIGINT NOT NULL, inputs_key TEXT NOT NULL, inputs TEXT NOT NULL,
              manifest TEXT NOT NULL, created TEXT NOT NULL, UNIQUE (program_id, inputs_key));
            CREATE TABLE IF NOT EXISTS preparation_files (
              preparation_id BIGINT NOT NULL, seq INTEGER NOT NULL, name TEXT NOT NULL, data BYTEA NOT NULL,
              PRIMARY KEY (preparation_id, seq));
            """),
        ("jobs: where an expanded program's line came from", "ALTER TABLE jobs ADD COLUMN IF NOT EXISTS source_location TEXT;"),
        ("cycle holes of stored blocks", SqliteMigrations.CycleHolesSchema), // 9: the same text runs on both engines
        ("selected blocks: a job's last line; an expanded revision's source map",
            "ALTER TABLE jobs ADD COLUMN IF NOT EXISTS to_line BIGINT;\n" + SqliteMigrations.ExpansionMapSchema), // 10: whether or not 11 ran
    ];

    /// <summary>The newest schema version this build writes (the same number as on SQLite).</summary>
    public static int Latest => Steps.Length;

    /// <summary>
    /// Brings the database to <see cref="Latest"/>: each missing migration in its own transaction, under an advisory
    /// lock so two stations starting at once do not both migrate. A role without the rights gets a message naming
    /// what to run.
    /// </summary>
    public static void Apply(NpgsqlConnection connection)
    {
        ArgumentNullException.ThrowIfNull(connection);
        if (Version(connection) == Latest)
        {
            return;
        }

        try
        {
            Exec(connection, null, "SELECT pg_advisory_lock(7007026)");
            Exec(connection, null, "CREATE TABLE IF NOT EXISTS schema_version (version BIGINT PRIMARY KEY, name TEXT NOT NULL, applied TEXT NOT NULL)");
            for (var v = Version(connection) + 1; v <= Latest; v++)
            {
                using var t = connection.BeginTransaction();
                Exec(connection, t, Steps[v - 1].Sql);
                using var cmd = new NpgsqlCommand("INSERT INTO schema_version (version, name, applied) VALUES (@v, @n, @a)", connection, t);
                cmd.Parameters.AddWithValue("v", (long)v);
                cmd.Parameters.AddWithValue("n", Steps[v - 1].Name);
                cmd.Parameters.AddWithValue("a", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
                cmd.ExecuteNonQuery();
                t.Commit();
            }
        }
        catch (PostgresException e) when (e.SqlState is PostgresErrorCodes.InsufficientPrivilege)
        {
            throw new InvalidOperationException(
                $"the store's schema is at version {SafeVersion(connection)} and this pmacstream needs {Latest}, but this role may not create tables ({e.MessageText}): run `pmacstream store migrate --store URI` as the database's owner", e);
        }
        finally
        {
            Exec(connection, null, "SELECT pg_advisory_unlock_all()");
        }
    }

    /// <summary>The schema version recorded (0: none yet).</summary>
    public static int Version(NpgsqlConnection connection)
    {
        ArgumentNullException.ThrowIfNull(connection);
        using var exists = new NpgsqlCommand("SELECT to_regclass('schema_version') IS NOT NULL", connection);
        if (exists.ExecuteScalar() is not true)
        {
            return 0;
        }

        using var cmd = new NpgsqlCommand("SELECT COALESCE(MAX(version), 0) FROM schema_version", connection);
        return Convert.ToInt32(cmd.ExecuteScalar(), CultureInfo.InvariantCulture);
    }

    /// <summary>Opens a connection to <paramref name="location"/> and migrates it when needed.</summary>
    public static NpgsqlConnection OpenMigrated(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        var connection = new NpgsqlConnection(location.Target);
        try
        {
            connection.Open();
            Apply(connection);
            return connection;
        }
        catch
        {
            connection.Dispose();
            throw;
        }
    }

    private static int SafeVersion(NpgsqlConnection connection)
    {
        try
        {
            return Version(connection);
        }
        catch (NpgsqlException)
        {
            return 0;
        }
    }

    private static void Exec(NpgsqlConnection c, NpgsqlTransaction? t, string sql)
    {
        using var cmd = new NpgsqlCommand(sql, c, t);
        cmd.ExecuteNonQuery();
    }
}
