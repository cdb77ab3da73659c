using System.Globalization;
using System.Security.Cryptography;
using Microsoft.Data.Sqlite;
using PmacStream.GCode;
using Serilog;

namespace PmacStream.Preparation.Store;

/// <summary>A program as stored: where it came from and how its check went.</summary>
/// <param name="Id">Row id.</param>
/// <param name="Path">Source file path as given.</param>
/// <param name="Size">File size in bytes.</param>
/// <param name="Sha256">SHA-256 of the file, lower-case hex.</param>
/// <param name="Lines">Source lines.</param>
/// <param name="Blocks">Stored blocks.</param>
/// <param name="Errors">Error diagnostics.</param>
/// <param name="Warnings">Warning diagnostics.</param>
/// <param name="EstimatedSeconds">Estimated run time at programmed feeds.</param>
/// <param name="Profile">Machine profile name used for the check.</param>
/// <param name="Created">When it was stored (UTC).</param>
public sealed record ProgramInfo(long Id, string Path, long Size, string Sha256, int Lines, long Blocks, int Errors, int Warnings,
    double EstimatedSeconds, string Profile, DateTimeOffset Created)
{
    /// <summary>The revision's name (the file name it was imported from); null for a program stored by <c>check --db</c>.</summary>
    public string? Name { get; init; }

    /// <summary>
    /// The identity of the profile the blocks were interpreted under (<see cref="MachineProfile.Identity"/>: its tool
    /// table and work offsets are in the stored positions); null for revisions stored before schema 7.
    /// </summary>
    public string? ProfileIdentity { get; init; }

    /// <summary>The check summary as <c>N errors, M warnings, B blocks</c>.</summary>
    public string CheckSummary => $"{Errors} errors, {Warnings} warnings, {Blocks} blocks";
}

/// <summary>
/// The relational program store (SQLite): a <c>programs</c> table, a <c>blocks</c> table with one row per
/// interpreted block (<c>Lines, GA..GI, MA..MC, X, Y, Z, I, J, K, R, F, S, T, H, P</c> plus D, the absolute start/end
/// positions, arc centre, motion kind, length, time and the modal T/H/D/S/F) and a <c>diagnostics</c> table. The first
/// nine G and three M modal groups of the profile fill GA..GI and MA..MC; a profile's further groups go to
/// <c>group_states</c> as JSON (<c>{"G":[94,null,98],"M":[6]}</c>), once per distinct state, which a block names in
/// <c>group_state</c>; the group names go to <c>programs.groups</c>, so a
/// state reads back equal to the interpreter's whatever the profile. Single
/// block, selected blocks and continuous execution (and the preview) read from here. Inserts go through one prepared
/// statement inside one transaction per program, so an interrupted import leaves nothing behind.
/// </summary>
public sealed partial class ProgramStore : IProgramRevisions
{
    private static readonly ILogger Logger = Log.ForContext<ProgramStore>();

    internal const string ProgramColumns = "id, path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, created, name, profile_identity";

    internal const string BlockColumns =
        "key, program_id, Lines, byte_offset, N, block_delete, GA, GB, GC, GD, GE, GF, GG, GH, GI, MA, MB, MC, " +
        "X, Y, Z, I, J, K, R, F, S, T, H, D, P, motion, start_x, start_y, start_z, end_x, end_y, end_z, " +
        "center_x, center_y, center_z, length, duration, modal_t, modal_h, modal_d, modal_s, modal_f, group_state";

    internal const string BaseSchema = """
        CREATE TABLE IF NOT EXISTS programs (
            id INTEGER PRIMARY KEY,
            path TEXT NOT NULL,
            size INTEGER NOT NULL,
            sha256 TEXT NOT NULL,
            lines INTEGER NOT NULL,
            blocks INTEGER NOT NULL,
            errors INTEGER NOT NULL,
            warnings INTEGER NOT NULL,
            estimated_seconds REAL NOT NULL,
            profile TEXT NOT NULL,
            check_summary TEXT NOT NULL,
            created TEXT NOT NULL,
            groups TEXT);
        CREATE INDEX IF NOT EXISTS programs_sha ON programs(sha256);
        CREATE TABLE IF NOT EXISTS blocks (
            key INTEGER PRIMARY KEY, program_id INTEGER NOT NULL, Lines INTEGER NOT NULL, byte_offset INTEGER NOT NULL,
            N REAL, block_delete INTEGER NOT NULL,
            GA REAL, GB REAL, GC REAL, GD REAL, GE REAL, GF REAL, GG REAL, GH REAL, GI REAL, MA REAL, MB REAL, MC REAL,
            X REAL, Y REAL, Z REAL, I REAL, J REAL, K REAL, R REAL, F REAL, S REAL, T REAL, H REAL, D REAL, P REAL,
            motion INTEGER NOT NULL, start_x REAL, start_y REAL, start_z REAL, end_x REAL, end_y REAL, end_z REAL,
            center_x REAL, center_y REAL, center_z REAL, length REAL, duration REAL,
            modal_t INTEGER, modal_h INTEGER, modal_d INTEGER, modal_s REAL, modal_f REAL, group_state INTEGER);
        CREATE TABLE IF NOT EXISTS group_states (
            program_id INTEGER NOT NULL, id INTEGER NOT NULL, more TEXT NOT NULL, PRIMARY KEY (program_id, id)) WITHOUT ROWID;
        CREATE TABLE IF NOT EXISTS diagnostics (
            program_id INTEGER NOT NULL, severity TEXT NOT NULL, code TEXT NOT NULL, line INTEGER NOT NULL,
            col INTEGER NOT NULL, message TEXT NOT NULL);
        CREATE INDEX IF NOT EXISTS diagnostics_program ON diagnostics(program_id, line);
        """;

    private readonly SqliteConnection _connection;

    private ProgramStore(SqliteConnection connection) => _connection = connection;

    /// <summary>The database file.</summary>
    public string Path { get; private init; } = string.Empty;

    /// <summary>Opens (creating when needed) a store file.</summary>
    public static ProgramStore Open(string path) =>
        // WAL keeps readers (HMI, preview) going while a program is imported; NORMAL sync is safe with WAL.
        OpenWith(path, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; PRAGMA temp_store=MEMORY;");

    /// <summary>
    /// Checks a file and stores it as the first program of a database file that does not exist yet: the fast path of
    /// <c>check --db NEW.db</c>. The database is built beside <paramref name="dbPath"/> under a temporary name with
    /// no write-ahead log (every page is written once instead of to the WAL and again at the checkpoint) and renamed
    /// into place only when complete, so a failure or cancellation leaves no file behind. The result is an ordinary
    /// store in WAL mode. Throws <see cref="IOException"/> when <paramref name="dbPath"/> exists.
    /// </summary>
    public static (long ProgramId, CheckSummary Summary) ImportToNewFile(string dbPath, string file, MachineProfile profile,
        Action<Diagnostic>? onDiagnostic = null, CancellationToken cancellationToken = default)
    {
        if (File.Exists(dbPath))
        {
            throw new IOException($"{dbPath}: already exists");
        }

        var full = System.IO.Path.GetFullPath(dbPath);
        var temp = System.IO.Path.Combine(System.IO.Path.GetDirectoryName(full)!,
            $".{System.IO.Path.GetFileName(full)}.{Environment.ProcessId}.{Guid.NewGuid():N}.importing");
        try
        {
            (long, CheckSummary) result;
            // The rollback journal stays in memory: pages appended by the import are never journaled (a rollback
            // just forgets them), and nobody else can see the temporary file. One exclusive lock for the whole run.
            using (var store = OpenWith(temp, $"PRAGMA page_size={BulkPageSize}; PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF; " +
                                              $"PRAGMA locking_mode=EXCLUSIVE; PRAGMA temp_store=MEMORY; PRAGMA cache_size=-{BulkCacheKiB};"))
            {
                result = store.Import(file, profile, onDiagnostic, cancellationToken);
                using var cmd = store._connection.CreateCommand();
                // Back to the store's normal mode for the readers that open it later; nothing to checkpoint yet.
                cmd.CommandText = "PRAGMA locking_mode=NORMAL; PRAGMA journal_mode=WAL;";
                using var results = cmd.ExecuteReader();
                while (results.NextResult())
                {
                }
            }

            File.Move(temp, full, overwrite: false);
            return result;
        }
        finally
        {
            foreach (var f in new[] { temp, temp + "-journal", temp + "-wal", temp + "-shm" })
            {
                if (File.Exists(f))
                {
                    File.Delete(f);
                }
            }
        }
    }

    /// <summary>Page size of a database built by <see cref="ImportToNewFile"/> (fewer, fuller pages for long tables).</summary>
    internal const int BulkPageSize = 16384;

    /// <summary>Page cache of the bulk import, KiB (bounded: peak memory of check --db must stay small).</summary>
    internal const int BulkCacheKiB = 4096;

    private static ProgramStore OpenWith(string path, string pragmas)
    {
        var cs = new SqliteConnectionStringBuilder { DataSource = path, Mode = SqliteOpenMode.ReadWriteCreate, Pooling = false }.ToString();
        var connection = new SqliteConnection(cs);
        try
        {
            connection.Open();
            using var cmd = connection.CreateCommand();
            cmd.CommandText = pragmas;

            // Every statement's result is stepped: after a PRAGMA that returns a row, ExecuteNonQuery runs the rest
            // while disposing its reader and drops their errors, so a full disk surfaced later as "no such table".
            using var results = cmd.ExecuteReader();
            while (results.NextResult())
            {
            }

            SqliteMigrations.Apply(connection);
        }
        catch
        {
            connection.Dispose();
            throw;
        }

        return new ProgramStore(connection) { Path = path };
    }

    /// <summary>
    /// Starts storing a program. Add blocks and diagnostics to the writer, then <see cref="ProgramWriter.Complete"/>;
    /// disposing it without completing rolls everything back. Without the profile's groups the nine G and three M
    /// groups of paper-24g7m are assumed.
    /// </summary>
    public ProgramWriter BeginProgram(string sourcePath, long size, string profile) => new(_connection, sourcePath, size, profile, null);

    /// <summary>Starts storing a program checked against <paramref name="profile"/> (its modal groups are recorded).</summary>
    public ProgramWriter BeginProgram(string sourcePath, long size, MachineProfile profile) =>
        new(_connection, sourcePath, size, profile.Name, StoredGroups.Describe(profile), profile.Identity);

    /// <summary>
    /// Checks a file and stores every block and diagnostic in one pass (hashing as it reads). Returns the program id
    /// and the summary; <paramref name="onDiagnostic"/> sees each diagnostic as it is found, in line order, on a
    /// worker thread: reading and interpreting run on one thread while SQLite stores the blocks on the calling one.
    /// </summary>
    public (long ProgramId, CheckSummary Summary) Import(string file, MachineProfile profile, Action<Diagnostic>? onDiagnostic = null, CancellationToken cancellationToken = default)
    {
        using var fs = new FileStream(file, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        using var hashing = new HashingReadStream(fs);
        using var writer = BeginProgram(file, fs.Length, profile);
        var summary = ImportPipeline.Run(hashing, file, profile, writer, onDiagnostic, cancellationToken);
        writer.Complete(summary, hashing.HashHex());
        Logger.Information("Stored {File} as program {Id}: {Summary} in {Ms} ms", file, writer.ProgramId, summary.ToString(), (int)summary.Elapsed.TotalMilliseconds);
        return (writer.ProgramId, summary);
    }

    /// <summary>
    /// Checks a file and stores it as a program revision in the same pass: every block and diagnostic, and the exact
    /// source bytes (read once, hashed and stored as the check reads them). The same content under the same profile
    /// is the same revision: that import is rolled back and the stored revision's id returned.
    /// </summary>
    public ProgramImport ImportRevision(string file, MachineProfile profile, Action<Diagnostic>? onDiagnostic = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(profile);
        using var import = BeginRevision(file, new FileInfo(file).Length, profile);
        return import.Run(source => ImportPipeline.Run(source, file, profile, import.Blocks, onDiagnostic, cancellationToken, import.AfterBatch));
    }

    /// <summary>Opens the import of a revision (<see cref="RevisionImport.Begin"/>): one transaction on this store's connection.</summary>
    internal RevisionImport BeginRevision(string file, long size, MachineProfile profile) => new SqliteRevision(BeginProgram(System.IO.Path.GetFullPath(file), size, profile), file, profile);

    /// <summary>A revision imported into SQLite: one <see cref="ProgramWriter"/>, its transaction committed by completing.</summary>
    private sealed class SqliteRevision(ProgramWriter writer, string file, MachineProfile profile) : RevisionImport(file, profile)
    {
        internal override ImportPipeline.IBlockSink Blocks => writer;

        internal override void AfterBatch()
        {
            foreach (var piece in Pieces.Drain())
            {
                writer.AddSource(piece);
            }
        }

        private protected override ProgramImport CompleteCore(CheckSummary summary, string sha256)
        {
            if (writer.ExistingRevision(sha256, Profile.Name) is { } existing)
            {
                Logger.Information("{File} is program {Id} already (same content, profile {Profile})", File, existing, Profile.Name);
                return new ProgramImport(existing, summary, true);
            }

            writer.Complete(summary, sha256, System.IO.Path.GetFileName(File));
            Logger.Information("Stored {File} as program revision {Id}: {Summary} in {Ms} ms", File, writer.ProgramId, summary.ToString(), (int)summary.Elapsed.TotalMilliseconds);
            return new ProgramImport(writer.ProgramId, summary, false);
        }

        private protected override void DisposeCore() => writer.Dispose();
    }

    /// <summary>Program revisions (imported with their source), newest first.</summary>
    public IReadOnlyList<ProgramInfo> ListRevisions()
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {ProgramColumns} FROM programs WHERE revision = 1 ORDER BY id DESC";
        return ReadPrograms(cmd);
    }

    /// <summary>Writes a revision's exact source bytes to <paramref name="output"/>; false when the program has no stored source.</summary>
    public bool ExportSource(long programId, Stream output)
    {
        ArgumentNullException.ThrowIfNull(output);
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT revision FROM programs WHERE id = $p";
        cmd.Parameters.AddWithValue("$p", programId);
        if (cmd.ExecuteScalar() is not long rev || rev != 1)
        {
            return false;
        }

        cmd.CommandText = "SELECT data FROM program_source WHERE program_id = $p ORDER BY seq";
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            using var piece = r.GetStream(0);
            piece.CopyTo(output);
        }

        return true;
    }

    /// <summary>All stored programs, newest first.</summary>
    public IReadOnlyList<ProgramInfo> ListPrograms()
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {ProgramColumns} FROM programs ORDER BY id DESC";
        return ReadPrograms(cmd);
    }

    /// <summary>A stored program by id, or null.</summary>
    public ProgramInfo? GetProgram(long id)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {ProgramColumns} FROM programs WHERE id = $id";
        cmd.Parameters.AddWithValue("$id", id);
        return ReadPrograms(cmd).FirstOrDefault();
    }

    /// <summary>The newest stored program with this SHA-256 (so an unchanged file need not be imported again), or null.</summary>
    public ProgramInfo? FindBySha256(string sha256)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {ProgramColumns} FROM programs WHERE sha256 = $s ORDER BY id DESC LIMIT 1";
        cmd.Parameters.AddWithValue("$s", sha256.ToLowerInvariant());
        return ReadPrograms(cmd).FirstOrDefault();
    }

    /// <summary>The block at a source line (single-block execution, start from line), or null when that line holds no block.</summary>
    public DecodedBlock? GetBlockAtLine(long programId, int line)
    {
        var groups = GroupsOf(programId);
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key = $k";
        cmd.Parameters.AddWithValue("$k", Key(programId, line));
        using var r = cmd.ExecuteReader();
        return r.Read() ? ReadBlock(r, groups) : null;
    }

    /// <inheritdoc />
    public GCode.Expansion.ExpansionMap? ReadExpansionMap(long programId)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT data FROM expansion_maps WHERE program_id = $p ORDER BY seq";
        cmd.Parameters.AddWithValue("$p", programId);
        var text = new System.Text.StringBuilder();
        using (var r = cmd.ExecuteReader())
        {
            while (r.Read())
            {
                text.Append(r.GetString(0));
            }
        }

        return text.Length == 0 ? null : GCode.Expansion.ExpansionMap.Read(new StringReader(text.ToString()), $"program {programId}'s source map");
    }

    /// <summary>The first block at or after a source line (where execution starts when a chosen line is empty), or null.</summary>
    public DecodedBlock? GetBlockAtOrAfterLine(long programId, int line)
    {
        var groups = GroupsOf(programId);
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key >= $a AND key <= $b ORDER BY key LIMIT 1";
        cmd.Parameters.AddWithValue("$a", Key(programId, Math.Max(0, line)));
        cmd.Parameters.AddWithValue("$b", Key(programId, int.MaxValue));
        using var r = cmd.ExecuteReader();
        return r.Read() ? ReadBlock(r, groups) : null;
    }

    /// <inheritdoc />
    public bool HasBlockDeleteBlock(long programId, int line)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT 1 FROM blocks WHERE key >= $a AND key <= $b AND block_delete <> 0 LIMIT 1";
        cmd.Parameters.AddWithValue("$a", Key(programId, 0));
        cmd.Parameters.AddWithValue("$b", Key(programId, Math.Max(0, line)));
        return cmd.ExecuteScalar() is not null;
    }

    /// <inheritdoc />
    public StoredStart? GetStart(long programId, int line)
    {
        var groups = GroupsOf(programId);
        using var cmd = _connection.CreateCommand();
        // Motion blocks are most blocks: the scan from the line's key stops at the first one.
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key >= $a AND key <= $b AND motion <> 0 ORDER BY key LIMIT 1";
        cmd.Parameters.AddWithValue("$a", Key(programId, Math.Max(0, line)));
        cmd.Parameters.AddWithValue("$b", Key(programId, int.MaxValue));
        DecodedBlock block;
        using (var r = cmd.ExecuteReader())
        {
            if (!r.Read())
            {
                return null;
            }

            block = ReadBlock(r, groups);
        }

        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key >= $a AND key < $b ORDER BY key DESC LIMIT 1";
        cmd.Parameters["$a"].Value = Key(programId, 0);
        cmd.Parameters["$b"].Value = Key(programId, block.Line);
        DecodedBlock? previous = null;
        using (var r = cmd.ExecuteReader())
        {
            if (r.Read())
            {
                previous = ReadBlock(r, groups);
            }
        }

        cmd.CommandText = $"SELECT {ProgramWriter.ExecStateColumns} FROM exec_states WHERE program_id = $p AND line < $l ORDER BY line DESC LIMIT 1";
        cmd.Parameters.Clear();
        cmd.Parameters.AddWithValue("$p", programId);
        cmd.Parameters.AddWithValue("$l", block.Line);
        using var s = cmd.ExecuteReader();
        return new StoredStart(block, previous, s.Read() ? ReadExecState(s) : null);
    }

    /// <summary>An <c>exec_states</c> row (its columns in <see cref="ProgramWriter.ExecStateColumns"/> order), either engine.</summary>
    internal static StoredExecState ReadExecState(System.Data.Common.DbDataReader r) =>
        new(r.GetInt32(1), new Point3(r.GetDouble(2), r.GetDouble(3), r.GetDouble(4)), r.IsDBNull(5) ? null : r.GetDouble(5),
            r.GetString(6).Split('\n'), r.IsDBNull(7) ? null : r.GetString(7));

    /// <summary>The blocks whose source lines lie in [<paramref name="fromLine"/>, <paramref name="toLine"/>] (selected-block execution).</summary>
    public IReadOnlyList<DecodedBlock> GetRange(long programId, int fromLine, int toLine) => ReadBlocks(programId, fromLine, toLine).ToList();

    /// <summary>
    /// An ordered cursor over the blocks from a source line on (continuous execution, preview). Streams rows; keep
    /// the enumeration short-lived or on its own store instance, since it holds a read statement open.
    /// </summary>
    public IEnumerable<DecodedBlock> ReadBlocks(long programId, int fromLine = 1, int toLine = int.MaxValue)
    {
        var groups = GroupsOf(programId);
        using var cmd = _connection.CreateCommand();
        // The row key is (program, line), so a range of lines is a range of keys: no index, no sort.
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key BETWEEN $a AND $b ORDER BY key";
        cmd.Parameters.AddWithValue("$a", Key(programId, Math.Max(0, fromLine)));
        cmd.Parameters.AddWithValue("$b", Key(programId, Math.Max(0, toLine)));
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            yield return ReadBlock(r, groups);
        }
    }

    /// <inheritdoc />
    public IEnumerable<StoredBlock> ReadStoredBlocks(long programId, int fromLine = 0, int toLine = int.MaxValue)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT line, holes, r_level, bottom FROM cycle_holes WHERE program_id = $p AND line BETWEEN $a AND $b";
        cmd.Parameters.AddWithValue("$p", programId);
        cmd.Parameters.AddWithValue("$a", fromLine);
        cmd.Parameters.AddWithValue("$b", toLine);
        var holes = ReadHoles(cmd);
        foreach (var block in ReadBlocks(programId, fromLine, toLine))
        {
            yield return new StoredBlock(block, holes.TryGetValue(block.Line, out var h) ? h : null);
        }
    }

    /// <inheritdoc />
    public IEnumerable<StoredMoveTime> ReadMoveTimes(long programId, int fromLine = 0, int toLine = int.MaxValue)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT Lines, motion, duration, modal_f FROM blocks WHERE key BETWEEN $a AND $b AND motion <> 0 ORDER BY key";
        cmd.Parameters.AddWithValue("$a", Key(programId, Math.Max(0, fromLine)));
        cmd.Parameters.AddWithValue("$b", Key(programId, Math.Max(0, toLine)));
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            yield return new StoredMoveTime(r.GetInt32(0), (MotionKind)r.GetInt32(1), r.IsDBNull(2) ? 0 : r.GetDouble(2), r.IsDBNull(3) ? null : r.GetDouble(3));
        }
    }

    /// <summary>
    /// The cycle holes of a range, by line: cycle blocks are few beside the others, so they are read first (PostgreSQL
    /// keeps one reader open per connection) rather than joined to every block.
    /// </summary>
    internal static Dictionary<int, CycleHoles> ReadHoles(System.Data.Common.DbCommand cmd)
    {
        var holes = new Dictionary<int, CycleHoles>();
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            holes[r.GetInt32(0)] = new CycleHoles(r.GetInt32(1), r.GetDouble(2), r.GetDouble(3));
        }

        return holes;
    }

    /// <summary>The modal groups a program was stored with (paper-24g7m's nine and three for a program stored without them).</summary>
    public StoredGroups GroupsOf(long programId)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT groups FROM programs WHERE id = $id";
        cmd.Parameters.AddWithValue("$id", programId);
        var names = cmd.ExecuteScalar() as string;
        cmd.CommandText = "SELECT id, more FROM group_states WHERE program_id = $id";
        var states = new Dictionary<long, string>();
        using (var r = cmd.ExecuteReader())
        {
            while (r.Read())
            {
                states[r.GetInt64(0)] = r.GetString(1);
            }
        }

        return StoredGroups.Parse(names, states);
    }

    /// <summary>The stored diagnostics of a program in line order.</summary>
    public IReadOnlyList<Diagnostic> GetDiagnostics(long programId)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT severity, code, line, col, message FROM diagnostics WHERE program_id = $p ORDER BY line, rowid";
        cmd.Parameters.AddWithValue("$p", programId);
        using var r = cmd.ExecuteReader();
        var list = new List<Diagnostic>();
        while (r.Read())
        {
            list.Add(new Diagnostic(r.GetString(0) == "error" ? Severity.Error : Severity.Warning, r.GetString(1), r.GetInt32(2), r.GetInt32(3), r.GetString(4)));
        }

        return list;
    }

    /// <summary>Deletes a program with its blocks and diagnostics.</summary>
    public void DeleteProgram(long programId)
    {
        using var tx = _connection.BeginTransaction();
        using var cmd = _connection.CreateCommand();
        cmd.Transaction = tx;
        cmd.CommandText = "DELETE FROM blocks WHERE key BETWEEN $a AND $b; DELETE FROM diagnostics WHERE program_id = $p; " +
                          "DELETE FROM group_states WHERE program_id = $p; DELETE FROM program_source WHERE program_id = $p; DELETE FROM exec_states WHERE program_id = $p; DELETE FROM cycle_holes WHERE program_id = $p; DELETE FROM expansion_maps WHERE program_id = $p; " +
                          "DELETE FROM preparation_files WHERE preparation_id IN (SELECT id FROM preparations WHERE program_id = $p); " +
                          "DELETE FROM preparations WHERE program_id = $p; DELETE FROM programs WHERE id = $p;";
        cmd.Parameters.AddWithValue("$p", programId);
        cmd.Parameters.AddWithValue("$a", Key(programId, 0));
        cmd.Parameters.AddWithValue("$b", Key(programId, int.MaxValue));
        cmd.ExecuteNonQuery();
        tx.Commit();
    }

    /// <inheritdoc />
    public void Dispose() => _connection.Dispose();

    /// <summary>Row key of a block: program id in the high 32 bits, source line in the low ones (one block per line).</summary>
    internal static long Key(long programId, int line) => (programId << 32) | (uint)line;

    internal static List<ProgramInfo> ReadPrograms(System.Data.Common.DbCommand cmd)
    {
        using var r = cmd.ExecuteReader();
        var list = new List<ProgramInfo>();
        while (r.Read())
        {
            list.Add(new ProgramInfo(r.GetInt64(0), r.GetString(1), r.GetInt64(2), r.GetString(3), r.GetInt32(4), r.GetInt64(5),
                r.GetInt32(6), r.GetInt32(7), r.GetDouble(8), r.GetString(9),
                DateTimeOffset.Parse(r.GetString(10), CultureInfo.InvariantCulture, DateTimeStyles.AssumeUniversal)) { Name = r.IsDBNull(11) ? null : r.GetString(11), ProfileIdentity = r.IsDBNull(12) ? null : r.GetString(12) });
        }

        return list;
    }

    internal static DecodedBlock ReadBlock(System.Data.Common.DbDataReader r, StoredGroups groups)
    {
        double? D(int i) => r.IsDBNull(i) ? null : r.GetDouble(i);
        var (g, m) = groups.Values(i => D(6 + i), i => D(15 + i), r.IsDBNull(48) ? null : r.GetInt64(48));
        var modal = new ModalState
        {
            G = g,
            M = m,
            Tool = r.GetInt32(43), LengthOffset = r.GetInt32(44), CutterComp = r.GetInt32(45), SpindleSpeed = r.GetDouble(46), Feed = D(47),
        };
        return new DecodedBlock
        {
            Line = r.GetInt32(2),
            ByteOffset = r.GetInt64(3),
            N = D(4),
            BlockDelete = r.GetInt32(5) != 0,
            Modal = modal,
            X = D(18), Y = D(19), Z = D(20), I = D(21), J = D(22), K = D(23), R = D(24), F = D(25), S = D(26), T = D(27), H = D(28), D = D(29), P = D(30),
            Motion = (MotionKind)r.GetInt32(31),
            Start = new Point3(r.GetDouble(32), r.GetDouble(33), r.GetDouble(34)),
            End = new Point3(r.GetDouble(35), r.GetDouble(36), r.GetDouble(37)),
            Center = r.IsDBNull(38) ? null : new Point3(r.GetDouble(38), r.GetDouble(39), r.GetDouble(40)),
            Length = r.GetDouble(41),
            DurationSeconds = r.GetDouble(42),
        };
    }
}

/// <summary>What an import stored: the revision's id, the check's summary, and whether that revision was stored before.</summary>
/// <param name="Id">The revision's id.</param>
/// <param name="Summary">The check of this import.</param>
/// <param name="Existing">True when the same content under the same profile was stored already (nothing new written).</param>
public sealed record ProgramImport(long Id, CheckSummary Summary, bool Existing);

/// <summary>Read-through stream that hashes what passes (SHA-256 of the file while checking it, without a second read).</summary>
internal sealed class HashingReadStream(Stream inner, SourcePieces? pieces = null) : Stream
{
    private readonly IncrementalHash _hash = IncrementalHash.CreateHash(HashAlgorithmName.SHA256);

    public override bool CanRead => true;

    public override bool CanSeek => false;

    public override bool CanWrite => false;

    public override long Length => inner.Length;

    public override long Position { get => inner.Position; set => throw new NotSupportedException(); }

    public string HashHex() => Convert.ToHexStringLower(_hash.GetHashAndReset());

    public override int Read(byte[] buffer, int offset, int count)
    {
        var n = inner.Read(buffer, offset, count);
        _hash.AppendData(buffer, offset, n);
        pieces?.Append(buffer.AsSpan(offset, n));
        return n;
    }

    public override void Flush()
    {
    }

    public override long Seek(long offset, SeekOrigin origin) => throw new NotSupportedException();

    public override void SetLength(long value) => throw new NotSupportedException();

    public override void Write(byte[] buffer, int offset, int count) => throw new NotSupportedException();

    protected override void Dispose(bool disposing)
    {
        if (disposing)
        {
            _hash.Dispose();
        }

        base.Dispose(disposing);
    }
}
