using System.Globalization;
using Npgsql;
using NpgsqlTypes;
using PmacStream.GCode;
using Serilog;

namespace PmacStream.Preparation.Store;

/// <summary>
/// The program library on PostgreSQL: the same tables as <see cref="ProgramStore"/>. An import is one transaction;
/// blocks go in by binary <c>COPY</c>, one per batch of the check's pipeline, so the rows never wait in memory; the
/// source pieces and diagnostics between the batches. Every statement is parameterized.
/// </summary>
public sealed partial class PgProgramStore : IProgramRevisions
{
    private static readonly ILogger Logger = Log.ForContext<PgProgramStore>();

    internal const string PgBlockColumns =
        "program_id, line, byte_offset, n, block_delete, ga, gb, gc, gd, ge, gf, gg, gh, gi, ma, mb, mc, " +
        "x, y, z, i, j, k, r, f, s, t, h, d, p, motion, start_x, start_y, start_z, end_x, end_y, end_z, " +
        "center_x, center_y, center_z, length, duration, modal_t, modal_h, modal_d, modal_s, modal_f, group_state";

    private readonly NpgsqlConnection _connection;
    private readonly StoreLocation _location;

    private PgProgramStore(NpgsqlConnection connection, StoreLocation location)
    {
        _connection = connection;
        _location = location;
    }

    /// <summary>Opens the library at <paramref name="location"/> (migrating the schema when this role may).</summary>
    public static PgProgramStore Open(StoreLocation location) => new(PgSchema.OpenMigrated(location), location);

    /// <summary>
    /// How long each statement of an import may take (the block COPYs, the source pieces, the commit); null: in
    /// proportion to the file (<see cref="ImportTimeoutFor"/>). Npgsql's own default, 30 s, is what a 1M-block import
    /// hit on a loaded server; a longer <c>Command Timeout</c> in the connection string is kept.
    /// </summary>
    public TimeSpan? ImportTimeout { get; set; }

    /// <summary>
    /// The import's statement timeout for a file of <paramref name="bytes"/>: 5 minutes, plus a second for every 100 kB
    /// (a 1M-block CAM program, about 30 MB, gets 10 minutes), whatever one statement of it may have to wait for.
    /// </summary>
    public static TimeSpan ImportTimeoutFor(long bytes) => TimeSpan.FromSeconds(300 + (Math.Max(0, bytes) / 100_000));

    /// <summary>A connection of the import's own, its statements given <paramref name="timeout"/> (the commit's too).</summary>
    /// <remarks>A timeout set in <see cref="ImportTimeout"/> is taken as it is; a proportional one only lengthens the connection string's.</remarks>
    private NpgsqlConnection OpenImportConnection(TimeSpan timeout, bool exact)
    {
        var builder = new NpgsqlConnectionStringBuilder(_location.Target);
        var seconds = Seconds(timeout);
        if (exact || (builder.CommandTimeout != 0 && builder.CommandTimeout < seconds))
        {
            builder.CommandTimeout = seconds;
        }

        var connection = new NpgsqlConnection(builder.ConnectionString);
        try
        {
            connection.Open();
            return connection;
        }
        catch
        {
            connection.Dispose();
            throw;
        }
    }

    /// <inheritdoc />
    public ProgramImport ImportRevision(string file, MachineProfile profile, Action<Diagnostic>? onDiagnostic = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(profile);
        using var import = BeginRevision(file, new FileInfo(file).Length, profile);
        return import.Run(source => ImportPipeline.Run(source, file, profile, import.Blocks, onDiagnostic, cancellationToken, import.AfterBatch));
    }

    /// <summary>
    /// Opens the import of a revision (<see cref="RevisionImport.Begin"/>): a connection and transaction of its own,
    /// every statement given the import's timeout (<see cref="ImportTimeout"/>, else in proportion to <paramref name="size"/>).
    /// </summary>
    internal RevisionImport BeginRevision(string file, long size, MachineProfile profile)
    {
        var timeout = ImportTimeout ?? ImportTimeoutFor(size);
        var connection = OpenImportConnection(timeout, exact: ImportTimeout is not null);
        NpgsqlTransaction? tx = null;
        try
        {
            tx = connection.BeginTransaction();
            using var cmd = new NpgsqlCommand(
                "INSERT INTO programs (path, size, sha256, lines, blocks, errors, warnings, estimated_seconds, profile, check_summary, created, groups, profile_identity) " +
                "VALUES (@path, @size, '', 0, 0, 0, 0, 0, @profile, 'incomplete', @created, @groups, @identity) RETURNING id", connection, tx);
            cmd.Parameters.AddWithValue("path", Path.GetFullPath(file));
            cmd.Parameters.AddWithValue("size", size);
            cmd.Parameters.AddWithValue("profile", profile.Name);
            cmd.Parameters.AddWithValue("created", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            cmd.Parameters.AddWithValue("groups", StoredGroups.Describe(profile));
            cmd.Parameters.AddWithValue("identity", profile.Identity);
            cmd.CommandTimeout = Seconds(timeout);
            var id = (long)cmd.ExecuteScalar()!;
            return new PgRevision(this, connection, tx, id, timeout, file, profile);
        }
        catch
        {
            tx?.Dispose();
            connection.Dispose();
            throw;
        }
    }

    /// <summary>A revision imported into PostgreSQL: its own connection and transaction, blocks by binary COPY.</summary>
    private sealed class PgRevision(PgProgramStore store, NpgsqlConnection connection, NpgsqlTransaction tx, long id, TimeSpan timeout, string file, MachineProfile profile)
        : RevisionImport(file, profile)
    {
        private readonly Writer _writer = new(connection, tx, id, timeout);

        internal override ImportPipeline.IBlockSink Blocks => _writer;

        internal override void AfterBatch()
        {
            _writer.EndCopy();
            foreach (var piece in Pieces.Drain())
            {
                _writer.AddSource(piece);
            }
        }

        private protected override ProgramImport CompleteCore(CheckSummary summary, string sha256)
        {
            using (var find = new NpgsqlCommand("SELECT id FROM programs WHERE sha256 = @s AND profile = @p AND revision = 1 ORDER BY id LIMIT 1", connection, tx))
            {
                find.CommandTimeout = Seconds(timeout);
                find.Parameters.AddWithValue("s", sha256);
                find.Parameters.AddWithValue("p", Profile.Name);
                if (find.ExecuteScalar() is long existing)
                {
                    tx.Rollback();
                    return new ProgramImport(existing, summary, true);
                }
            }

            using (var cmd = new NpgsqlCommand(
                       "UPDATE programs SET sha256 = @sha, lines = @lines, blocks = @blocks, errors = @e, warnings = @w, estimated_seconds = @t, " +
                       "check_summary = @sum, name = @name, revision = 1 WHERE id = @id", connection, tx))
            {
                cmd.CommandTimeout = Seconds(timeout);
                cmd.Parameters.AddWithValue("sha", sha256);
                cmd.Parameters.AddWithValue("lines", summary.Lines);
                cmd.Parameters.AddWithValue("blocks", _writer.Blocks);
                cmd.Parameters.AddWithValue("e", summary.Errors);
                cmd.Parameters.AddWithValue("w", summary.Warnings);
                cmd.Parameters.AddWithValue("t", summary.EstimatedSeconds);
                cmd.Parameters.AddWithValue("sum", summary.ToString());
                cmd.Parameters.AddWithValue("name", Path.GetFileName(File));
                cmd.Parameters.AddWithValue("id", id);
                cmd.ExecuteNonQuery();
            }

            tx.Commit();
            Logger.Information("Stored {File} as program revision {Id} in {Store}: {Summary}", File, id, store._location.Display, summary.ToString());
            return new ProgramImport(id, summary, false);
        }

        private protected override void DisposeCore()
        {
            _writer.Dispose();
            tx.Dispose();
            connection.Dispose();
        }
    }

    /// <inheritdoc />
    public IReadOnlyList<ProgramInfo> ListRevisions()
    {
        using var cmd = new NpgsqlCommand($"SELECT {ProgramStore.ProgramColumns} FROM programs WHERE revision = 1 ORDER BY id DESC", _connection);
        return ProgramStore.ReadPrograms(cmd);
    }

    /// <inheritdoc />
    public ProgramInfo? GetProgram(long id)
    {
        using var cmd = new NpgsqlCommand($"SELECT {ProgramStore.ProgramColumns} FROM programs WHERE id = @id", _connection);
        cmd.Parameters.AddWithValue("id", id);
        return ProgramStore.ReadPrograms(cmd).FirstOrDefault();
    }

    /// <inheritdoc />
    public IReadOnlyList<Diagnostic> GetDiagnostics(long programId)
    {
        using var cmd = new NpgsqlCommand("SELECT severity, code, line, col, message FROM diagnostics WHERE program_id = @p ORDER BY line, ctid", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        using var r = cmd.ExecuteReader();
        var list = new List<Diagnostic>();
        while (r.Read())
        {
            list.Add(new Diagnostic(r.GetString(0) == "error" ? Severity.Error : Severity.Warning, r.GetString(1), r.GetInt32(2), r.GetInt32(3), r.GetString(4)));
        }

        return list;
    }

    /// <inheritdoc />
    public bool ExportSource(long programId, Stream output)
    {
        ArgumentNullException.ThrowIfNull(output);
        using (var rev = new NpgsqlCommand("SELECT revision FROM programs WHERE id = @p", _connection))
        {
            rev.Parameters.AddWithValue("p", programId);
            if (rev.ExecuteScalar() is not long r || r != 1)
            {
                return false;
            }
        }

        using var cmd = new NpgsqlCommand("SELECT data FROM program_source WHERE program_id = @p ORDER BY seq", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        using var reader = cmd.ExecuteReader(System.Data.CommandBehavior.SequentialAccess);
        while (reader.Read())
        {
            using var piece = reader.GetStream(0);
            piece.CopyTo(output);
        }

        return true;
    }

    /// <inheritdoc />
    public void DeleteProgram(long programId)
    {
        // Deleting a revision's rows takes time in proportion to it, as its import did (10M blocks: well over Npgsql's
        // default 30 s), so each statement gets the import's timeout for the revision's source size.
        var timeout = Seconds(ImportTimeout ?? ImportTimeoutFor(SourceBytesOf(programId)));
        using var tx = _connection.BeginTransaction();
        using (var prepared = new NpgsqlCommand("DELETE FROM preparation_files WHERE preparation_id IN (SELECT id FROM preparations WHERE program_id = @p)", _connection, tx) { CommandTimeout = timeout })
        {
            prepared.Parameters.AddWithValue("p", programId);
            prepared.ExecuteNonQuery();
        }

        foreach (var table in new[] { "blocks", "diagnostics", "group_states", "program_source", "exec_states", "cycle_holes", "expansion_maps", "preparations" })
        {
            using var cmd = new NpgsqlCommand($"DELETE FROM {table} WHERE program_id = @p", _connection, tx) { CommandTimeout = timeout }; // table names from the list above
            cmd.Parameters.AddWithValue("p", programId);
            cmd.ExecuteNonQuery();
        }

        using (var cmd = new NpgsqlCommand("DELETE FROM programs WHERE id = @p", _connection, tx))
        {
            cmd.Parameters.AddWithValue("p", programId);
            cmd.ExecuteNonQuery();
        }

        tx.Commit();
    }

    private long SourceBytesOf(long programId)
    {
        using var cmd = new NpgsqlCommand("SELECT size FROM programs WHERE id = @p", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        return cmd.ExecuteScalar() is long bytes ? bytes : 0;
    }

    /// <inheritdoc />
    public GCode.Expansion.ExpansionMap? ReadExpansionMap(long programId)
    {
        using var cmd = new NpgsqlCommand("SELECT data FROM expansion_maps WHERE program_id = @p ORDER BY seq", _connection);
        cmd.Parameters.AddWithValue("p", programId);
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

    /// <inheritdoc />
    public DecodedBlock? GetBlockAtOrAfterLine(long programId, int line)
    {
        var groups = GroupsOf(programId);
        // A leading 0 stands for SQLite's row key, so both engines' rows read with one reader.
        using var cmd = new NpgsqlCommand($"SELECT 0::bigint, {PgBlockColumns} FROM blocks WHERE program_id = @p AND line >= @l ORDER BY line LIMIT 1", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        cmd.Parameters.AddWithValue("l", Math.Max(0, line));
        using var r = cmd.ExecuteReader();
        return r.Read() ? ProgramStore.ReadBlock(r, groups) : null;
    }

    /// <inheritdoc />
    public bool HasBlockDeleteBlock(long programId, int line)
    {
        using var cmd = new NpgsqlCommand("SELECT 1 FROM blocks WHERE program_id = @p AND line <= @l AND block_delete <> 0 LIMIT 1", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        cmd.Parameters.AddWithValue("l", Math.Max(0, line));
        return cmd.ExecuteScalar() is not null;
    }

    /// <inheritdoc />
    public StoredStart? GetStart(long programId, int line)
    {
        var groups = GroupsOf(programId);
        DecodedBlock block;
        using (var cmd = new NpgsqlCommand($"SELECT 0::bigint, {PgBlockColumns} FROM blocks WHERE program_id = @p AND line >= @l AND motion <> 0 ORDER BY line LIMIT 1", _connection))
        {
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("l", Math.Max(0, line));
            using var r = cmd.ExecuteReader();
            if (!r.Read())
            {
                return null;
            }

            block = ProgramStore.ReadBlock(r, groups);
        }

        DecodedBlock? previous = null;
        using (var cmd = new NpgsqlCommand($"SELECT 0::bigint, {PgBlockColumns} FROM blocks WHERE program_id = @p AND line < @l ORDER BY line DESC LIMIT 1", _connection))
        {
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("l", block.Line);
            using var r = cmd.ExecuteReader();
            if (r.Read())
            {
                previous = ProgramStore.ReadBlock(r, groups);
            }
        }

        using var state = new NpgsqlCommand($"SELECT {ProgramWriter.ExecStateColumns} FROM exec_states WHERE program_id = @p AND line < @l ORDER BY line DESC LIMIT 1", _connection);
        state.Parameters.AddWithValue("p", programId);
        state.Parameters.AddWithValue("l", block.Line);
        using var s = state.ExecuteReader();
        return new StoredStart(block, previous, s.Read() ? ProgramStore.ReadExecState(s) : null);
    }

    /// <inheritdoc />
    public IEnumerable<StoredBlock> ReadStoredBlocks(long programId, int fromLine = 0, int toLine = int.MaxValue)
    {
        var groups = GroupsOf(programId);
        Dictionary<int, CycleHoles> holes;
        using (var cmd = new NpgsqlCommand("SELECT line, holes, r_level, bottom FROM cycle_holes WHERE program_id = @p AND line BETWEEN @a AND @b", _connection))
        {
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("a", fromLine);
            cmd.Parameters.AddWithValue("b", toLine);
            holes = ProgramStore.ReadHoles(cmd);
        }

        using var blocks = new NpgsqlCommand($"SELECT 0::bigint, {PgBlockColumns} FROM blocks WHERE program_id = @p AND line BETWEEN @a AND @b ORDER BY line", _connection);
        blocks.Parameters.AddWithValue("p", programId);
        blocks.Parameters.AddWithValue("a", fromLine);
        blocks.Parameters.AddWithValue("b", toLine);
        using var r = blocks.ExecuteReader();
        while (r.Read())
        {
            var block = ProgramStore.ReadBlock(r, groups);
            yield return new StoredBlock(block, holes.TryGetValue(block.Line, out var h) ? h : null);
        }
    }

    /// <inheritdoc />
    public IEnumerable<StoredMoveTime> ReadMoveTimes(long programId, int fromLine = 0, int toLine = int.MaxValue)
    {
        using var cmd = new NpgsqlCommand("SELECT line, motion, duration, modal_f FROM blocks WHERE program_id = @p AND line BETWEEN @a AND @b AND motion <> 0 ORDER BY line", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        cmd.Parameters.AddWithValue("a", fromLine);
        cmd.Parameters.AddWithValue("b", toLine);
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            yield return new StoredMoveTime(r.GetInt32(0), (MotionKind)r.GetInt32(1), r.IsDBNull(2) ? 0 : r.GetDouble(2), r.IsDBNull(3) ? null : r.GetDouble(3));
        }
    }

    private StoredGroups GroupsOf(long programId)
    {
        using var cmd = new NpgsqlCommand("SELECT groups FROM programs WHERE id = @id", _connection);
        cmd.Parameters.AddWithValue("id", programId);
        var names = cmd.ExecuteScalar() as string;
        using var states = new NpgsqlCommand("SELECT id, more FROM group_states WHERE program_id = @id", _connection);
        states.Parameters.AddWithValue("id", programId);
        var map = new Dictionary<long, string>();
        using (var r = states.ExecuteReader())
        {
            while (r.Read())
            {
                map[r.GetInt64(0)] = r.GetString(1);
            }
        }

        return StoredGroups.Parse(names, map);
    }

    /// <inheritdoc />
    public void Dispose() => _connection.Dispose();

    private static int Seconds(TimeSpan timeout) => Math.Max(1, (int)Math.Ceiling(timeout.TotalSeconds));

    /// <summary>One import's rows: blocks by binary COPY (opened on the first block of a batch, closed before any other statement).</summary>
    private sealed class Writer(NpgsqlConnection connection, NpgsqlTransaction tx, long programId, TimeSpan timeout) : ImportPipeline.IBlockSink, IDisposable
    {
        private readonly Dictionary<string, long> _states = new(StringComparer.Ordinal);
        private readonly List<StoredExecState> _execStates = [];
        private readonly List<(int Line, CycleHoles Holes)> _holes = [];
        private NpgsqlBinaryImporter? _copy;
        private long _sourceSeq;

        public long Blocks { get; private set; }

        public void Add(in Interpreter.LastBlock b, ModalState m)
        {
            var more = StoredGroups.MoreText(m);
            long? state = null;
            if (more is not null)
            {
                if (!_states.TryGetValue(more, out var sid))
                {
                    EndCopy();
                    sid = _states.Count + 1;
                    _states.Add(more, sid);
                    using var cmd = new NpgsqlCommand("INSERT INTO group_states (program_id, id, more) VALUES (@p, @i, @m)", connection, tx) { CommandTimeout = Seconds(timeout) };
                    cmd.Parameters.AddWithValue("p", programId);
                    cmd.Parameters.AddWithValue("i", sid);
                    cmd.Parameters.AddWithValue("m", more);
                    cmd.ExecuteNonQuery();
                }

                state = sid;
            }

            var c = _copy ??= Copy($"COPY blocks ({PgBlockColumns}) FROM STDIN (FORMAT BINARY)");
            c.StartRow();
            c.Write(programId, NpgsqlDbType.Bigint);
            c.Write(b.Line, NpgsqlDbType.Integer);
            c.Write(b.ByteOffset, NpgsqlDbType.Bigint);
            D(c, b.N);
            c.Write(b.BlockDelete ? 1 : 0, NpgsqlDbType.Integer);
            D(c, m.GA); D(c, m.GB); D(c, m.GC); D(c, m.GD); D(c, m.GE); D(c, m.GF); D(c, m.GG); D(c, m.GH); D(c, m.GI);
            D(c, m.MA); D(c, m.MB); D(c, m.MC);
            D(c, b.X); D(c, b.Y); D(c, b.Z); D(c, b.I); D(c, b.J); D(c, b.K); D(c, b.R); D(c, b.F); D(c, b.S); D(c, b.T); D(c, b.H); D(c, b.D); D(c, b.P);
            c.Write((int)b.Motion, NpgsqlDbType.Integer);
            D(c, b.Start.X); D(c, b.Start.Y); D(c, b.Start.Z);
            D(c, b.End.X); D(c, b.End.Y); D(c, b.End.Z);
            D(c, b.Center?.X); D(c, b.Center?.Y); D(c, b.Center?.Z);
            D(c, b.Length);
            D(c, b.DurationSeconds);
            c.Write(m.Tool, NpgsqlDbType.Integer);
            c.Write(m.LengthOffset, NpgsqlDbType.Integer);
            c.Write(m.CutterComp, NpgsqlDbType.Integer);
            D(c, m.SpindleSpeed);
            D(c, m.Feed);
            if (state is { } st)
            {
                c.Write(st, NpgsqlDbType.Bigint);
            }
            else
            {
                c.WriteNull();
            }

            Blocks++;
        }

        public void Add(Diagnostic d)
        {
            EndCopy();
            using var cmd = new NpgsqlCommand("INSERT INTO diagnostics (program_id, severity, code, line, col, message) VALUES (@p, @s, @c, @l, @k, @m)", connection, tx) { CommandTimeout = Seconds(timeout) };
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("s", d.Severity == Severity.Error ? "error" : "warning");
            cmd.Parameters.AddWithValue("c", d.Code);
            cmd.Parameters.AddWithValue("l", d.Line);
            cmd.Parameters.AddWithValue("k", d.Column);
            cmd.Parameters.AddWithValue("m", d.Message);
            cmd.ExecuteNonQuery();
        }

        public void AddSource(byte[] piece)
        {
            EndCopy();
            using var cmd = new NpgsqlCommand("INSERT INTO program_source (program_id, seq, data) VALUES (@p, @s, @d)", connection, tx) { CommandTimeout = Seconds(timeout) };
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("s", _sourceSeq++);
            cmd.Parameters.AddWithValue("d", piece);
            cmd.ExecuteNonQuery();
        }

        /// <summary>Stores piece <paramref name="seq"/> of an expanded program's source map (<c>expansion_maps</c>, migration 10).</summary>
        public void AddExpansionMap(int seq, string text)
        {
            EndCopy();
            using var cmd = new NpgsqlCommand("INSERT INTO expansion_maps (program_id, seq, data) VALUES (@p, @s, @d)", connection, tx) { CommandTimeout = Seconds(timeout) };
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("s", seq);
            cmd.Parameters.AddWithValue("d", text);
            cmd.ExecuteNonQuery();
        }

        /// <summary>Keeps an execution state for the COPY that follows the batch's blocks.</summary>
        public void Add(StoredExecState state) => _execStates.Add(state);

        /// <summary>Keeps a cycle block's holes for the COPY that follows the batch's blocks.</summary>
        public void Add(int line, CycleHoles holes) => _holes.Add((line, holes));

        /// <summary>Ends the open COPY (its rows go in with the transaction), then copies the execution states waiting.</summary>
        public void EndCopy()
        {
            if (_copy is { } c)
            {
                _copy = null;
                c.Complete();
                c.Dispose();
            }

            CopyHoles();
            if (_execStates.Count == 0)
            {
                return;
            }

            using (var states = Copy($"COPY exec_states ({ProgramWriter.ExecStateColumns}) FROM STDIN (FORMAT BINARY)"))
            {
                foreach (var e in _execStates)
                {
                    states.StartRow();
                    states.Write(programId, NpgsqlDbType.Bigint);
                    states.Write(e.Line, NpgsqlDbType.Integer);
                    states.Write(e.Offset.X, NpgsqlDbType.Double);
                    states.Write(e.Offset.Y, NpgsqlDbType.Double);
                    states.Write(e.Offset.Z, NpgsqlDbType.Double);
                    D(states, e.HighestZ);
                    states.Write(e.ControllerText, NpgsqlDbType.Text);
                    if (e.Selection is { } sel)
                    {
                        states.Write(sel, NpgsqlDbType.Text);
                    }
                    else
                    {
                        states.WriteNull();
                    }
                }

                states.Complete();
            }

            _execStates.Clear();
        }

        private void CopyHoles()
        {
            if (_holes.Count == 0)
            {
                return;
            }

            using (var copy = Copy($"COPY cycle_holes ({ProgramWriter.CycleHoleColumns}) FROM STDIN (FORMAT BINARY)"))
            {
                foreach (var (line, holes) in _holes)
                {
                    copy.StartRow();
                    copy.Write(programId, NpgsqlDbType.Bigint);
                    copy.Write(line, NpgsqlDbType.Integer);
                    copy.Write(holes.Count, NpgsqlDbType.Integer);
                    copy.Write(holes.RLevel, NpgsqlDbType.Double);
                    copy.Write(holes.Bottom, NpgsqlDbType.Double);
                }

                copy.Complete();
            }

            _holes.Clear();
        }

        /// <summary>A binary COPY given the import's timeout (its <c>Complete</c> waits for the server to take every row).</summary>
        private NpgsqlBinaryImporter Copy(string sql)
        {
            var copy = connection.BeginBinaryImport(sql);
            copy.Timeout = timeout;
            return copy;
        }

        public void Dispose()
        {
            // Not completed: disposing cancels the COPY; the transaction rolls back with it.
            _copy?.Dispose();
            _copy = null;
        }

        private static void D(NpgsqlBinaryImporter c, double? v)
        {
            if (v is { } x)
            {
                c.Write(x, NpgsqlDbType.Double);
            }
            else
            {
                c.WriteNull();
            }
        }
    }
}
