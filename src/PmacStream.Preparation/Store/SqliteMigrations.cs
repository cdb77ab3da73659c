using System.Globalization;
using Microsoft.Data.Sqlite;

namespace PmacStream.Preparation.Store;

/// <summary>
/// The store's schema on SQLite, as numbered migrations recorded in <c>schema_version</c> and applied once, in order,
/// each in its own transaction (the PostgreSQL ones in <c>PgSchema</c> keep the same numbers and tables). A file
/// written before the table existed (a <c>check --db</c> store, an old <c>jobs.db</c>) is brought up with every
/// migration: they create only what is missing, so its programs and jobs stay as they were (listed, and resumable).
/// An alarm history (or any other record) is one more migration at the end of the list.
/// </summary>
public static class SqliteMigrations
{
    /// <summary>The newest schema version this build writes.</summary>
    public static int Latest => Steps.Length;

    /// <summary>The jobs table as first written (jobs.db), and who has the file open.</summary>
    private const string JobsSchema = """
        CREATE TABLE IF NOT EXISTS jobs (
          id INTEGER PRIMARY KEY AUTOINCREMENT, created TEXT NOT NULL, program_path TEXT NOT NULL, program_sha256 TEXT NOT NULL,
          manifest_path TEXT NOT NULL, strategy TEXT NOT NULL, connection TEXT NOT NULL, from_line INTEGER,
          message TEXT NOT NULL DEFAULT '', cp_time TEXT, cp_state TEXT, cp_last_line INTEGER, cp_chunk INTEGER,
          cp_next_chunk INTEGER, cp_next_line INTEGER, cp_next_exact INTEGER, cp_chunks_downloaded INTEGER, cp_started INTEGER);
        CREATE TABLE IF NOT EXISTS openers (pid INTEGER NOT NULL, host TEXT NOT NULL, started TEXT NOT NULL, opened TEXT NOT NULL);
        """;

    /// <summary>Columns jobs.db gained over its versions (its records read with the defaults).</summary>
    private static readonly (string Name, string Definition)[] JobsAddedColumns =
    [
        ("line_probe", "TEXT NOT NULL DEFAULT 'P501'"),
        ("preamble", "TEXT"),
        ("cp_loaded", "INTEGER"),
        ("settings", "TEXT"),
        ("profile", "TEXT"),
        ("profile_identity", "TEXT"),
    ];

    /// <summary>What the history shows of a job; records of older versions read with nulls (outcome from the checkpoint).</summary>
    internal static readonly (string Name, string Definition)[] JobHistoryColumns =
    [
        ("program_id", "INTEGER"),
        ("station", "TEXT"),
        ("machine", "TEXT"),
        ("os_user", "TEXT"),
        ("runner", "TEXT"),
        ("ended", "TEXT"),
        ("outcome", "TEXT"),
        ("blocks_executed", "INTEGER"),
        ("blocks_total", "INTEGER"),
        ("stops", "INTEGER NOT NULL DEFAULT 0"),
        ("alarms", "INTEGER NOT NULL DEFAULT 0"),
        ("resumes", "INTEGER NOT NULL DEFAULT 0"),
    ];

    private static readonly (string Name, Action<SqliteConnection, SqliteTransaction> Apply)[] Steps =
    [
        ("programs and decoded blocks (check --db)", (c, t) => Run(c, t, ProgramStore.BaseSchema)),
        ("program revisions: name, source bytes", (c, t) =>
        {
            AddColumn(c, t, "programs", "groups", "TEXT");
            AddColumn(c, t, "blocks", "group_state", "INTEGER");
            AddColumn(c, t, "programs", "name", "TEXT");
            AddColumn(c, t, "programs", "revision", "INTEGER NOT NULL DEFAULT 0");
            Run(c, t, """
                CREATE TABLE IF NOT EXISTS program_source (program_id INTEGER NOT NULL, seq INTEGER NOT NULL, data BLOB NOT NULL, PRIMARY KEY (program_id, seq)) WITHOUT ROWID;
                CREATE INDEX IF NOT EXISTS programs_revision ON programs(sha256, profile, revision);
                """);
        }),
        ("jobs and checkpoints", (c, t) =>
        {
            Run(c, t, JobsSchema);
            foreach (var (name, definition) in JobsAddedColumns)
            {
                AddColumn(c, t, "jobs", name, definition);
            }
        }),
        ("job history", (c, t) =>
        {
            foreach (var (name, definition) in JobHistoryColumns)
            {
                AddColumn(c, t, "jobs", name, definition);
            }
        }),
        ("alarm history", (c, t) => Run(c, t, AlarmStores.SqliteSchema)), // 5: a table of its own, created only when missing
        ("machine leases", (c, t) => Run(c, t, LeaseSchema)),
        ("execution states and stored preparations", (c, t) =>
        {
            AddColumn(c, t, "programs", "profile_identity", "TEXT");
            Run(c, t, ExecutionSchema);
        }),
        ("jobs: where an expanded program's line came from", (c, t) =>
        {
            // Whether or not steps 5-7 ran: the column is added only when missing.
            AddColumn(c, t, "jobs", "source_location", "TEXT");
        }),
        ("cycle holes of stored blocks", (c, t) => Run(c, t, CycleHolesSchema)), // 9: a table of its own, whether or not 10 exists
        ("selected blocks: a job's last line; an expanded revision's source map", (c, t) =>
        {
            // 10: a column added only when missing and a table of its own, whether or not step 11 ran before it.
            AddColumn(c, t, "jobs", "to_line", "INTEGER");
            Run(c, t, ExpansionMapSchema);
        }),
    ];

    /// <summary>
    /// Version 10: the source map of a revision whose program was expanded (subprograms, macros, o-words): the split's
    /// <c>expansion.map</c> text in pieces (the blocks of such a revision are numbered by expanded line, as <c>M0==</c> counts them).
    /// </summary>
    public const string ExpansionMapSchema = """
        CREATE TABLE IF NOT EXISTS expansion_maps (
            program_id BIGINT NOT NULL, seq INTEGER NOT NULL, data TEXT NOT NULL, PRIMARY KEY (program_id, seq));
        """;

    /// <summary>
    /// Version 9: the holes of each stored cycle block (how many, the R level and the bottom, machine Z), as the
    /// interpreter decided them, so the preview draws a cycle from the store as it draws it from the file.
    /// </summary>
    public const string CycleHolesSchema = """
        CREATE TABLE IF NOT EXISTS cycle_holes (
            program_id BIGINT NOT NULL, line INTEGER NOT NULL, holes INTEGER NOT NULL, r_level DOUBLE PRECISION NOT NULL,
            bottom DOUBLE PRECISION NOT NULL, PRIMARY KEY (program_id, line));
        """;

    /// <summary>
    /// One row per leased machine (migration 6): which station's process holds it, since when, its last heartbeat
    /// and the expiry it was taken with (milliseconds since 1970, the database's clock: every station judges expiry
    /// by the same clock).
    /// </summary>
    public const string LeaseSchema = """
        CREATE TABLE IF NOT EXISTS leases (
          machine TEXT PRIMARY KEY, station TEXT NOT NULL, pid BIGINT NOT NULL, runner TEXT NOT NULL, job_id BIGINT,
          since_ms BIGINT NOT NULL, heartbeat_ms BIGINT NOT NULL, expiry_ms BIGINT NOT NULL);
        """;

    /// <summary>
    /// Version 7: what a start from a block needs beyond the blocks' modal state (<see cref="StoredExecState"/>, once per
    /// change), and the preparations of a revision (chunk files and manifest, keyed by every input the split read).
    /// </summary>
    private const string ExecutionSchema = """
        CREATE TABLE IF NOT EXISTS exec_states (
            program_id INTEGER NOT NULL, line INTEGER NOT NULL, offset_x REAL NOT NULL, offset_y REAL NOT NULL, offset_z REAL NOT NULL,
            highest_z REAL, controller TEXT NOT NULL, selection TEXT, PRIMARY KEY (program_id, line)) WITHOUT ROWID;
        CREATE TABLE IF NOT EXISTS preparations (
            id INTEGER PRIMARY KEY, program_id INTEGER NOT NULL, inputs_key TEXT NOT NULL, inputs TEXT NOT NULL,
            manifest TEXT NOT NULL, created TEXT NOT NULL, UNIQUE (program_id, inputs_key));
        CREATE TABLE IF NOT EXISTS preparation_files (
            preparation_id INTEGER NOT NULL, seq INTEGER NOT NULL, name TEXT NOT NULL, data BLOB NOT NULL,
            PRIMARY KEY (preparation_id, seq)) WITHOUT ROWID;
        """;

    /// <summary>Applies the migrations the file has not had; returns how many ran.</summary>
    public static int Apply(SqliteConnection connection)
    {
        ArgumentNullException.ThrowIfNull(connection);
        Run(connection, null, "CREATE TABLE IF NOT EXISTS schema_version (version INTEGER PRIMARY KEY, name TEXT NOT NULL, applied TEXT NOT NULL)");
        var have = Version(connection);
        if (have > Latest)
        {
            throw new InvalidOperationException($"the store's schema is version {have}, newer than this pmacstream knows ({Latest}): update pmacstream");
        }

        for (var v = have + 1; v <= Latest; v++)
        {
            using var t = connection.BeginTransaction();
            Steps[v - 1].Apply(connection, t);
            using var cmd = connection.CreateCommand();
            cmd.Transaction = t;
            cmd.CommandText = "INSERT INTO schema_version (version, name, applied) VALUES ($v, $n, $a)";
            cmd.Parameters.AddWithValue("$v", v);
            cmd.Parameters.AddWithValue("$n", Steps[v - 1].Name);
            cmd.Parameters.AddWithValue("$a", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            cmd.ExecuteNonQuery();
            t.Commit();
        }

        return Latest - have;
    }

    /// <summary>The schema version recorded in the file (0: none yet).</summary>
    public static int Version(SqliteConnection connection)
    {
        ArgumentNullException.ThrowIfNull(connection);
        using var cmd = connection.CreateCommand();
        cmd.CommandText = "SELECT COALESCE(MAX(version), 0) FROM schema_version";
        return Convert.ToInt32(cmd.ExecuteScalar(), CultureInfo.InvariantCulture);
    }

    private static void Run(SqliteConnection c, SqliteTransaction? t, string sql)
    {
        using var cmd = c.CreateCommand();
        cmd.Transaction = t;
        cmd.CommandText = sql;
        using var results = cmd.ExecuteReader();
        while (results.NextResult())
        {
        }
    }

    private static void AddColumn(SqliteConnection c, SqliteTransaction t, string table, string column, string definition)
    {
        using var cmd = c.CreateCommand();
        cmd.Transaction = t;
        cmd.CommandText = "SELECT COUNT(*) FROM pragma_table_info($t) WHERE name = $c";
        cmd.Parameters.AddWithValue("$t", table);
        cmd.Parameters.AddWithValue("$c", column);
        if ((long)cmd.ExecuteScalar()! == 0)
        {
            using var alter = c.CreateCommand();
            alter.Transaction = t;
            alter.CommandText = $"ALTER TABLE {table} ADD COLUMN {column} {definition}"; // names from the list above, never input
            alter.ExecuteNonQuery();
        }
    }
}
