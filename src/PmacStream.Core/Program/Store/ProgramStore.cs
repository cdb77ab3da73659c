using System.Globalization;
using System.Security.Cryptography;
using Microsoft.Data.Sqlite;
using PmacStream.GCode;
using Serilog;
using SQLitePCL;

namespace PmacStream.Program.Store;

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
    /// <summary>The check summary as <c>N errors, M warnings, B blocks</c>.</summary>
    public string CheckSummary => $"{Errors} errors, {Warnings} warnings, {Blocks} blocks";
}

/// <summary>
/// The relational program store (SQLite): a <c>programs</c> table, a <c>blocks</c> table with one row per
/// interpreted block (<c>Lines, GA..GI, MA..MC, X, Y, Z, I, J, K, R, F, S, T, H, P</c> plus D, the absolute start/end
/// positions, arc centre, motion kind, length, time and the modal T/H/D/S/F) and a <c>diagnostics</c> table. Single
/// block, selected blocks and continuous execution (and the preview) read from here. Inserts go through one prepared
/// statement inside one transaction per program, so an interrupted import leaves nothing behind.
/// </summary>
public sealed class ProgramStore : IDisposable
{
    private static readonly ILogger Logger = Log.ForContext<ProgramStore>();

    internal const string BlockColumns =
        "key, program_id, Lines, byte_offset, N, block_delete, GA, GB, GC, GD, GE, GF, GG, GH, GI, MA, MB, MC, " +
        "X, Y, Z, I, J, K, R, F, S, T, H, D, P, motion, start_x, start_y, start_z, end_x, end_y, end_z, " +
        "center_x, center_y, center_z, length, duration, modal_t, modal_h, modal_d, modal_s, modal_f";

    private const string Schema = """
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
            created TEXT NOT NULL);
        CREATE INDEX IF NOT EXISTS programs_sha ON programs(sha256);
        CREATE TABLE IF NOT EXISTS blocks (
            key INTEGER PRIMARY KEY, program_id INTEGER NOT NULL, Lines INTEGER NOT NULL, byte_offset INTEGER NOT NULL,
            N REAL, block_delete INTEGER NOT NULL,
            GA REAL, GB REAL, GC REAL, GD REAL, GE REAL, GF REAL, GG REAL, GH REAL, GI REAL, MA REAL, MB REAL, MC REAL,
            X REAL, Y REAL, Z REAL, I REAL, J REAL, K REAL, R REAL, F REAL, S REAL, T REAL, H REAL, D REAL, P REAL,
            motion INTEGER NOT NULL, start_x REAL, start_y REAL, start_z REAL, end_x REAL, end_y REAL, end_z REAL,
            center_x REAL, center_y REAL, center_z REAL, length REAL, duration REAL,
            modal_t INTEGER, modal_h INTEGER, modal_d INTEGER, modal_s REAL, modal_f REAL);
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
            cmd.CommandText = pragmas + Schema;

            // Every statement's result is stepped: after a PRAGMA that returns a row, ExecuteNonQuery runs the rest
            // while disposing its reader and drops their errors, so a full disk surfaced later as "no such table".
            using var results = cmd.ExecuteReader();
            while (results.NextResult())
            {
            }
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
    /// disposing it without completing rolls everything back.
    /// </summary>
    public ProgramWriter BeginProgram(string sourcePath, long size, string profile) => new(_connection, sourcePath, size, profile);

    /// <summary>
    /// Checks a file and stores every block and diagnostic in one pass (hashing as it reads). Returns the program id
    /// and the summary; <paramref name="onDiagnostic"/> sees each diagnostic as it is found, in line order, on a
    /// worker thread: reading and interpreting run on one thread while SQLite stores the blocks on the calling one.
    /// </summary>
    public (long ProgramId, CheckSummary Summary) Import(string file, MachineProfile profile, Action<Diagnostic>? onDiagnostic = null, CancellationToken cancellationToken = default)
    {
        using var fs = new FileStream(file, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        using var hashing = new HashingReadStream(fs);
        using var writer = BeginProgram(file, fs.Length, profile.Name);
        var summary = ImportPipeline.Run(hashing, file, profile, writer, onDiagnostic, cancellationToken);
        writer.Complete(summary, hashing.HashHex());
        Logger.Information("Stored {File} as program {Id}: {Summary} in {Ms} ms", file, writer.ProgramId, summary.ToString(), (int)summary.Elapsed.TotalMilliseconds);
        return (writer.ProgramId, summary);
    }

    /// <summary>All stored programs, newest first.</summary>
    public IReadOnlyList<ProgramInfo> ListPrograms()
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT id, path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, created FROM programs ORDER BY id DESC";
        return ReadPrograms(cmd);
    }

    /// <summary>A stored program by id, or null.</summary>
    public ProgramInfo? GetProgram(long id)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT id, path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, created FROM programs WHERE id = $id";
        cmd.Parameters.AddWithValue("$id", id);
        return ReadPrograms(cmd).FirstOrDefault();
    }

    /// <summary>The newest stored program with this SHA-256 (so an unchanged file need not be imported again), or null.</summary>
    public ProgramInfo? FindBySha256(string sha256)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = "SELECT id, path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, created FROM programs WHERE sha256 = $s ORDER BY id DESC LIMIT 1";
        cmd.Parameters.AddWithValue("$s", sha256.ToLowerInvariant());
        return ReadPrograms(cmd).FirstOrDefault();
    }

    /// <summary>The block at a source line (single-block execution, start from line), or null when that line holds no block.</summary>
    public DecodedBlock? GetBlockAtLine(long programId, int line)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key = $k";
        cmd.Parameters.AddWithValue("$k", Key(programId, line));
        using var r = cmd.ExecuteReader();
        return r.Read() ? ReadBlock(r) : null;
    }

    /// <summary>The first block at or after a source line (where execution starts when a chosen line is empty), or null.</summary>
    public DecodedBlock? GetBlockAtOrAfterLine(long programId, int line)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key >= $a AND key <= $b ORDER BY key LIMIT 1";
        cmd.Parameters.AddWithValue("$a", Key(programId, Math.Max(0, line)));
        cmd.Parameters.AddWithValue("$b", Key(programId, int.MaxValue));
        using var r = cmd.ExecuteReader();
        return r.Read() ? ReadBlock(r) : null;
    }

    /// <summary>The blocks whose source lines lie in [<paramref name="fromLine"/>, <paramref name="toLine"/>] (selected-block execution).</summary>
    public IReadOnlyList<DecodedBlock> GetRange(long programId, int fromLine, int toLine) => ReadBlocks(programId, fromLine, toLine).ToList();

    /// <summary>
    /// An ordered cursor over the blocks from a source line on (continuous execution, preview). Streams rows; keep
    /// the enumeration short-lived or on its own store instance, since it holds a read statement open.
    /// </summary>
    public IEnumerable<DecodedBlock> ReadBlocks(long programId, int fromLine = 1, int toLine = int.MaxValue)
    {
        using var cmd = _connection.CreateCommand();
        // The row key is (program, line), so a range of lines is a range of keys: no index, no sort.
        cmd.CommandText = $"SELECT {BlockColumns} FROM blocks WHERE key BETWEEN $a AND $b ORDER BY key";
        cmd.Parameters.AddWithValue("$a", Key(programId, Math.Max(0, fromLine)));
        cmd.Parameters.AddWithValue("$b", Key(programId, Math.Max(0, toLine)));
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            yield return ReadBlock(r);
        }
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
        cmd.CommandText = "DELETE FROM blocks WHERE key BETWEEN $a AND $b; DELETE FROM diagnostics WHERE program_id = $p; DELETE FROM programs WHERE id = $p;";
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

    private static List<ProgramInfo> ReadPrograms(SqliteCommand cmd)
    {
        using var r = cmd.ExecuteReader();
        var list = new List<ProgramInfo>();
        while (r.Read())
        {
            list.Add(new ProgramInfo(r.GetInt64(0), r.GetString(1), r.GetInt64(2), r.GetString(3), r.GetInt32(4), r.GetInt64(5),
                r.GetInt32(6), r.GetInt32(7), r.GetDouble(8), r.GetString(9),
                DateTimeOffset.Parse(r.GetString(10), CultureInfo.InvariantCulture, DateTimeStyles.AssumeUniversal)));
        }

        return list;
    }

    private static DecodedBlock ReadBlock(SqliteDataReader r)
    {
        double? D(int i) => r.IsDBNull(i) ? null : r.GetDouble(i);
        var ga = D(6);
        var modal = new ModalState
        {
            GA = ga, GB = D(7), GC = D(8), GD = D(9), GE = D(10), GF = D(11), GG = D(12), GH = D(13), GI = D(14),
            MA = D(15), MB = D(16), MC = D(17),
            Units = D(7) == 20 ? LengthUnits.Inches : LengthUnits.Millimetres,
            Plane = D(10) is { } ge ? (int)ge : 17,
            Absolute = D(8) != 91,
            WorkOffset = D(9) is { } gd ? (int)gd : 54,
            Spindle = D(16) is { } mb ? (int)mb : 5,
            Coolant = D(17) is { } mc ? (int)mc : 9,
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

/// <summary>
/// Stores one program's blocks and diagnostics inside one transaction through prepared statements bound directly
/// with SQLite's C API (ADO.NET parameter objects would box every double and cap the rate well below 300,000 rows/s).
/// </summary>
public sealed class ProgramWriter : IDisposable
{
    private readonly SqliteConnection _connection;
    private readonly SqliteTransaction _tx;
    private readonly sqlite3_stmt _block;
    private readonly sqlite3_stmt _diag;
    private readonly (BindState State, double Value)[] _bound = new (BindState, double)[64];
    private long _seq;
    private bool _completed;
    private bool _disposed;

    internal ProgramWriter(SqliteConnection connection, string sourcePath, long size, string profile)
    {
        _connection = connection;
        _tx = connection.BeginTransaction();
        using (var cmd = connection.CreateCommand())
        {
            cmd.Transaction = _tx;
            cmd.CommandText = "INSERT INTO programs (path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, check_summary, created) " +
                              "VALUES ($path, $size, '', 0, 0, 0, 0, 0, $profile, 'incomplete', $created); SELECT last_insert_rowid();";
            cmd.Parameters.AddWithValue("$path", sourcePath);
            cmd.Parameters.AddWithValue("$size", size);
            cmd.Parameters.AddWithValue("$profile", profile);
            cmd.Parameters.AddWithValue("$created", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            ProgramId = (long)cmd.ExecuteScalar()!;
        }

        var db = connection.Handle!;
        var placeholders = string.Join(", ", Enumerable.Repeat("?", ProgramStore.BlockColumns.Split(',').Length));
        Check(raw.sqlite3_prepare_v2(db, $"INSERT INTO blocks ({ProgramStore.BlockColumns}) VALUES ({placeholders})", out _block), db);
        Check(raw.sqlite3_prepare_v2(db, "INSERT INTO diagnostics (program_id, severity, code, line, col, message) VALUES (?, ?, ?, ?, ?, ?)", out _diag), db);
    }

    /// <summary>The new program's id.</summary>
    public long ProgramId { get; }

    /// <summary>Blocks added so far.</summary>
    public long Blocks => _seq;

    /// <summary>Adds a block (in program order).</summary>
    public void Add(DecodedBlock b)
    {
        var fields = new Interpreter.LastBlock
        {
            Line = b.Line, ByteOffset = b.ByteOffset, N = b.N, BlockDelete = b.BlockDelete,
            X = b.X, Y = b.Y, Z = b.Z, I = b.I, J = b.J, K = b.K, R = b.R, F = b.F, S = b.S, T = b.T, H = b.H, D = b.D, P = b.P,
            Motion = b.Motion, Start = b.Start, End = b.End, Center = b.Center, Length = b.Length, DurationSeconds = b.DurationSeconds,
        };
        Add(in fields, b.Modal);
    }

    /// <summary>Adds a block from the interpreter's fields and modal state (no record allocated).</summary>
    internal void Add(in Interpreter.LastBlock b, ModalState m)
    {
        BindI(1, ProgramStore.Key(ProgramId, b.Line));
        BindI(2, ProgramId);
        BindI(3, b.Line);
        BindI(4, b.ByteOffset);
        BindD(5, b.N);
        BindI(6, b.BlockDelete ? 1 : 0);
        BindD(7, m.GA); BindD(8, m.GB); BindD(9, m.GC); BindD(10, m.GD); BindD(11, m.GE); BindD(12, m.GF);
        BindD(13, m.GG); BindD(14, m.GH); BindD(15, m.GI); BindD(16, m.MA); BindD(17, m.MB); BindD(18, m.MC);
        BindD(19, b.X); BindD(20, b.Y); BindD(21, b.Z); BindD(22, b.I); BindD(23, b.J); BindD(24, b.K);
        BindD(25, b.R); BindD(26, b.F); BindD(27, b.S); BindD(28, b.T); BindD(29, b.H); BindD(30, b.D); BindD(31, b.P);
        BindI(32, (int)b.Motion);
        BindD(33, b.Start.X); BindD(34, b.Start.Y); BindD(35, b.Start.Z);
        BindD(36, b.End.X); BindD(37, b.End.Y); BindD(38, b.End.Z);
        BindD(39, b.Center?.X); BindD(40, b.Center?.Y); BindD(41, b.Center?.Z);
        BindD(42, b.Length);
        BindD(43, b.DurationSeconds);
        BindI(44, m.Tool);
        BindI(45, m.LengthOffset);
        BindI(46, m.CutterComp);
        BindD(47, m.SpindleSpeed);
        BindD(48, m.Feed);
        Step(_block);
        _seq++;
    }

    /// <summary>Adds a diagnostic.</summary>
    public void Add(Diagnostic d)
    {
        var s = _diag;
        raw.sqlite3_bind_int64(s, 1, ProgramId);
        raw.sqlite3_bind_text(s, 2, d.Severity == Severity.Error ? "error" : "warning");
        raw.sqlite3_bind_text(s, 3, d.Code);
        raw.sqlite3_bind_int(s, 4, d.Line);
        raw.sqlite3_bind_int(s, 5, d.Column);
        raw.sqlite3_bind_text(s, 6, d.Message);
        Step(s);
    }

    /// <summary>Writes the totals and commits everything.</summary>
    public void Complete(CheckSummary summary, string sha256)
    {
        using (var cmd = _connection.CreateCommand())
        {
            cmd.Transaction = _tx;
            cmd.CommandText = "UPDATE programs SET sha256 = $sha, lines = $lines, blocks = $blocks, errors = $e, warnings = $w, " +
                              "estimated_seconds = $t, check_summary = $sum WHERE id = $id";
            cmd.Parameters.AddWithValue("$sha", sha256.ToLowerInvariant());
            cmd.Parameters.AddWithValue("$lines", summary.Lines);
            cmd.Parameters.AddWithValue("$blocks", _seq);
            cmd.Parameters.AddWithValue("$e", summary.Errors);
            cmd.Parameters.AddWithValue("$w", summary.Warnings);
            cmd.Parameters.AddWithValue("$t", summary.EstimatedSeconds);
            cmd.Parameters.AddWithValue("$sum", summary.ToString());
            cmd.Parameters.AddWithValue("$id", ProgramId);
            cmd.ExecuteNonQuery();
        }

        ReleaseStatements();
        _tx.Commit();
        _completed = true;
    }

    /// <summary>Rolls back unless <see cref="Complete"/> ran.</summary>
    public void Dispose()
    {
        if (_disposed)
        {
            return;
        }

        _disposed = true;
        ReleaseStatements();
        if (!_completed)
        {
            _tx.Rollback();
        }

        _tx.Dispose();
    }

    private void ReleaseStatements()
    {
        _block.Dispose();
        _diag.Dispose();
    }

    private void Step(sqlite3_stmt s)
    {
        var rc = raw.sqlite3_step(s);
        raw.sqlite3_reset(s);
        if (rc != raw.SQLITE_DONE)
        {
            throw new SqliteException($"SQLite error {rc}: {raw.sqlite3_errmsg(_connection.Handle!).utf8_to_string()}", rc);
        }
    }

    // Bindings survive sqlite3_reset, and consecutive blocks share most values (modal codes, Z, feed), so only
    // changed values are re-bound: this halves the native calls per row on CAM programs.
    private void BindD(int index, double? v)
    {
        ref var slot = ref _bound[index];
        if (v is { } value)
        {
            if (slot.State == BindState.Double && slot.Value.Equals(value))
            {
                return;
            }

            raw.sqlite3_bind_double(_block, index, value);
            slot = (BindState.Double, value);
        }
        else if (slot.State != BindState.Null)
        {
            raw.sqlite3_bind_null(_block, index);
            slot = (BindState.Null, 0);
        }
    }

    private void BindI(int index, long v)
    {
        ref var slot = ref _bound[index];
        if (slot.State == BindState.Integer && slot.Value == v)
        {
            return;
        }

        raw.sqlite3_bind_int64(_block, index, v);
        slot = (BindState.Integer, v);
    }

    private enum BindState : byte
    {
        Unbound,
        Null,
        Double,
        Integer,
    }

    private static void Check(int rc, sqlite3 db)
    {
        if (rc != raw.SQLITE_OK)
        {
            throw new SqliteException($"SQLite error {rc}: {raw.sqlite3_errmsg(db).utf8_to_string()}", rc);
        }
    }
}

/// <summary>Read-through stream that hashes what passes (SHA-256 of the file while checking it, without a second read).</summary>
internal sealed class HashingReadStream(Stream inner) : Stream
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
