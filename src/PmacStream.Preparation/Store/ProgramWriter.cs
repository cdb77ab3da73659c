using System.Globalization;
using Microsoft.Data.Sqlite;
using PmacStream.GCode;
using SQLitePCL;

namespace PmacStream.Preparation.Store;

/// <summary>
/// Stores one program's blocks and diagnostics inside one transaction through prepared statements bound directly
/// with SQLite's C API (ADO.NET parameter objects would box every double and cap the rate well below 300,000 rows/s).
/// </summary>
public sealed class ProgramWriter : IDisposable, ImportPipeline.IBlockSink
{
    private readonly SqliteConnection _connection;
    private readonly SqliteTransaction _tx;
    private readonly sqlite3_stmt _block;
    private readonly sqlite3_stmt _diag;
    private readonly (BindState State, double Value)[] _bound = new (BindState, double)[64];
    private readonly sqlite3_stmt _state;
    private readonly sqlite3_stmt _exec;
    private readonly sqlite3_stmt _holes;
    private readonly Dictionary<string, long> _states = new(StringComparer.Ordinal); // distinct further-group states, by text
    private ModalState? _modal;
    private long _seq;
    private long _sourceSeq;
    private bool _completed;
    private bool _disposed;

    internal ProgramWriter(SqliteConnection connection, string sourcePath, long size, string profile, string? groups, string? profileIdentity = null)
    {
        _connection = connection;
        _tx = connection.BeginTransaction();
        using (var cmd = connection.CreateCommand())
        {
            cmd.Transaction = _tx;
            cmd.CommandText = "INSERT INTO programs (path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, check_summary, created, groups, profile_identity) " +
                              "VALUES ($path, $size, '', 0, 0, 0, 0, 0, $profile, 'incomplete', $created, $groups, $identity); SELECT last_insert_rowid();";
            cmd.Parameters.AddWithValue("$identity", (object?)profileIdentity ?? DBNull.Value);
            cmd.Parameters.AddWithValue("$path", sourcePath);
            cmd.Parameters.AddWithValue("$size", size);
            cmd.Parameters.AddWithValue("$profile", profile);
            cmd.Parameters.AddWithValue("$groups", (object?)groups ?? DBNull.Value);
            cmd.Parameters.AddWithValue("$created", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            ProgramId = (long)cmd.ExecuteScalar()!;
        }

        var db = connection.Handle!;
        var placeholders = string.Join(", ", Enumerable.Repeat("?", ProgramStore.BlockColumns.Split(',').Length));
        Check(raw.sqlite3_prepare_v2(db, $"INSERT INTO blocks ({ProgramStore.BlockColumns}) VALUES ({placeholders})", out _block), db);
        Check(raw.sqlite3_prepare_v2(db, "INSERT INTO diagnostics (program_id, severity, code, line, col, message) VALUES (?, ?, ?, ?, ?, ?)", out _diag), db);
        Check(raw.sqlite3_prepare_v2(db, "INSERT INTO group_states (program_id, id, more) VALUES (?, ?, ?)", out _state), db);
        Check(raw.sqlite3_prepare_v2(db, $"INSERT INTO exec_states ({ExecStateColumns}) VALUES (?, ?, ?, ?, ?, ?, ?, ?)", out _exec), db);
        Check(raw.sqlite3_prepare_v2(db, $"INSERT INTO cycle_holes ({CycleHoleColumns}) VALUES (?, ?, ?, ?, ?)", out _holes), db);
    }

    /// <summary>The columns of <c>exec_states</c> (both engines).</summary>
    internal const string ExecStateColumns = "program_id, line, offset_x, offset_y, offset_z, highest_z, controller, selection";

    /// <summary>The columns of <c>cycle_holes</c> (both engines).</summary>
    internal const string CycleHoleColumns = "program_id, line, holes, r_level, bottom";

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
        if (!ReferenceEquals(m, _modal))
        {
            // Consecutive blocks share one state instance until something changes: bound once per change.
            _modal = m;
            BindD(7, m.GA); BindD(8, m.GB); BindD(9, m.GC); BindD(10, m.GD); BindD(11, m.GE); BindD(12, m.GF);
            BindD(13, m.GG); BindD(14, m.GH); BindD(15, m.GI); BindD(16, m.MA); BindD(17, m.MB); BindD(18, m.MC);
            BindGroupState(StoredGroups.MoreText(m));
        }

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

    /// <inheritdoc />
    void ImportPipeline.IBlockSink.Add(in Interpreter.LastBlock block, ModalState modal) => Add(in block, modal);

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

    /// <summary>Adds the execution state a start needs after a block (<see cref="StoredExecState"/>).</summary>
    internal void Add(StoredExecState e)
    {
        var s = _exec;
        raw.sqlite3_bind_int64(s, 1, ProgramId);
        raw.sqlite3_bind_int(s, 2, e.Line);
        raw.sqlite3_bind_double(s, 3, e.Offset.X);
        raw.sqlite3_bind_double(s, 4, e.Offset.Y);
        raw.sqlite3_bind_double(s, 5, e.Offset.Z);
        if (e.HighestZ is { } z)
        {
            raw.sqlite3_bind_double(s, 6, z);
        }
        else
        {
            raw.sqlite3_bind_null(s, 6);
        }

        raw.sqlite3_bind_text(s, 7, e.ControllerText);
        if (e.Selection is { } sel)
        {
            raw.sqlite3_bind_text(s, 8, sel);
        }
        else
        {
            raw.sqlite3_bind_null(s, 8);
        }

        Step(s);
    }

    /// <inheritdoc />
    void ImportPipeline.IBlockSink.Add(StoredExecState state) => Add(state);

    /// <summary>Adds the holes of the cycle block at <paramref name="line"/>.</summary>
    public void Add(int line, CycleHoles holes)
    {
        var s = _holes;
        raw.sqlite3_bind_int64(s, 1, ProgramId);
        raw.sqlite3_bind_int(s, 2, line);
        raw.sqlite3_bind_int(s, 3, holes.Count);
        raw.sqlite3_bind_double(s, 4, holes.RLevel);
        raw.sqlite3_bind_double(s, 5, holes.Bottom);
        Step(s);
    }

    /// <summary>Stores the next piece of the program's exact source (a revision's, for export and execution).</summary>
    public void AddSource(byte[] piece)
    {
        ArgumentNullException.ThrowIfNull(piece);
        using var cmd = _connection.CreateCommand();
        cmd.Transaction = _tx;
        cmd.CommandText = "INSERT INTO program_source (program_id, seq, data) VALUES ($p, $s, $d)";
        cmd.Parameters.AddWithValue("$p", ProgramId);
        cmd.Parameters.AddWithValue("$s", _sourceSeq++);
        cmd.Parameters.AddWithValue("$d", piece);
        cmd.ExecuteNonQuery();
    }

    /// <summary>Stores piece <paramref name="seq"/> of an expanded program's source map (<c>expansion_maps</c>, migration 10).</summary>
    public void AddExpansionMap(int seq, string text)
    {
        using var cmd = _connection.CreateCommand();
        cmd.Transaction = _tx;
        cmd.CommandText = "INSERT INTO expansion_maps (program_id, seq, data) VALUES ($p, $s, $d)";
        cmd.Parameters.AddWithValue("$p", ProgramId);
        cmd.Parameters.AddWithValue("$s", seq);
        cmd.Parameters.AddWithValue("$d", text);
        cmd.ExecuteNonQuery();
    }

    /// <summary>The id of a stored revision with this content under this profile, other than this one, or null.</summary>
    public long? ExistingRevision(string sha256, string profile)
    {
        using var cmd = _connection.CreateCommand();
        cmd.Transaction = _tx;
        cmd.CommandText = "SELECT id FROM programs WHERE sha256 = $s AND profile = $p AND revision = 1 AND id <> $id ORDER BY id LIMIT 1";
        cmd.Parameters.AddWithValue("$s", sha256.ToLowerInvariant());
        cmd.Parameters.AddWithValue("$p", profile);
        cmd.Parameters.AddWithValue("$id", ProgramId);
        return cmd.ExecuteScalar() is long id ? id : null;
    }

    /// <summary>Writes the totals and commits everything; a <paramref name="revisionName"/> marks it a program revision (its source stored).</summary>
    public void Complete(CheckSummary summary, string sha256, string? revisionName = null)
    {
        using (var cmd = _connection.CreateCommand())
        {
            cmd.Transaction = _tx;
            cmd.CommandText = "UPDATE programs SET sha256 = $sha, lines = $lines, blocks = $blocks, errors = $e, warnings = $w, " +
                              "estimated_seconds = $t, check_summary = $sum, name = $name, revision = $rev WHERE id = $id";
            cmd.Parameters.AddWithValue("$name", (object?)revisionName ?? DBNull.Value);
            cmd.Parameters.AddWithValue("$rev", revisionName is null ? 0 : 1);
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
        _state.Dispose();
        _exec.Dispose();
        _holes.Dispose();
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

    /// <summary>Binds the id of the block's further-group state, storing the state the first time it is seen (null: none).</summary>
    private void BindGroupState(string? more)
    {
        if (more == null)
        {
            BindD(49, null);
            return;
        }

        if (!_states.TryGetValue(more, out var id))
        {
            id = _states.Count + 1;
            _states.Add(more, id);
            raw.sqlite3_bind_int64(_state, 1, ProgramId);
            raw.sqlite3_bind_int64(_state, 2, id);
            raw.sqlite3_bind_text(_state, 3, more);
            Step(_state);
        }

        BindI(49, id);
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
