using System.Globalization;
using Microsoft.Data.Sqlite;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>A streaming job as recorded for crash-safe resume.</summary>
/// <param name="Id">Job id.</param>
/// <param name="ProgramPath">The G-code source.</param>
/// <param name="ProgramSha256">SHA-256 of the source when the job started (resume refuses a changed file).</param>
/// <param name="ManifestPath">The split's manifest.json.</param>
/// <param name="Strategy">Strategy used.</param>
/// <param name="Connection">Connection spec (<c>sim</c>, <c>tcp://host:port</c>, <c>serial:dev@baud</c>).</param>
/// <param name="FromLine">Start line when the job started from a block, else null.</param>
/// <param name="Message">Last notable message (fault text).</param>
/// <param name="Checkpoint">Last checkpoint, null before the first.</param>
/// <param name="Created">When the job was created.</param>
/// <param name="Preamble">The PMAC lines the (latest) start sent before its block, or null (none, or not recorded).</param>
/// <param name="LineProbeVariable">The line-probe variable the job's lines carry (null: none); records of older versions read as <c>P501</c>.</param>
/// <param name="Settings">The run settings the job started with, as JSON (<c>Jobs.RunSettingsFile</c>); null in records of older versions.</param>
/// <param name="Profile">The machine profile the job ran under, as <c>--profile</c> takes it (a built-in name or a file's full path); null in records of older versions.</param>
/// <param name="ProfileIdentity">That profile's name and digest (<c>MachineProfile.Identity</c>): a resume refuses a profile that changed since.</param>
public sealed record JobRecord(long Id, string ProgramPath, string ProgramSha256, string ManifestPath, StrategyKind Strategy, string Connection, int? FromLine, string Message, Checkpoint? Checkpoint, DateTimeOffset Created, IReadOnlyList<string>? Preamble = null, string? LineProbeVariable = "P501", string? Settings = null, string? Profile = null, string? ProfileIdentity = null)
{
    /// <summary>
    /// Where the job's current line came from when the program was expanded (subprograms, macros, loops: <c>O1002 line
    /// 7, call 3 of 4 from line 12</c>); null for a program whose lines are its source lines.
    /// </summary>
    public string? SourceLocation { get; init; }

    /// <summary>
    /// The last line of a selected-block job (lines <see cref="FromLine"/>..this): its program ends after this line's
    /// block; null when it runs to the program's end.
    /// </summary>
    public int? ToLine { get; init; }

    /// <summary>True when the job has not completed (it can be resumed).</summary>
    public bool Unfinished => Checkpoint?.State is not SessionState.Completed;

    /// <summary>What the history keeps of it (program revision, station, machine, user, end, outcome, counts).</summary>
    public JobHistory History { get; init; } = new(null, null, null, null, null, null, null, null, null, 0, 0, 0);

    /// <summary>
    /// The outcome the history shows: <c>completed</c>, <c>aborted</c>, <c>alarm</c> (faulted), <c>interrupted</c> (it
    /// stopped without an end: the process was ended, the link lost for good, the PC went down) or <c>running</c>.
    /// A record of an older version says it through its checkpoint.
    /// </summary>
    public string Outcome
    {
        get
        {
            switch (Checkpoint?.State)
            {
                case SessionState.Completed:
                    return "completed";
                case SessionState.Aborted:
                    return "aborted";
                case SessionState.Faulted:
                    return "alarm";
            }

            return History.Outcome switch
            {
                "running" when History.Ended is null && !JobHistory.RunnerGone(History.Runner) => "running",
                "aborted" or "alarm" or "completed" => History.Outcome,
                _ => "interrupted",
            };
        }
    }
}

/// <summary>What the history records when a job starts.</summary>
/// <param name="ProgramId">The program revision (the store's id), or null.</param>
/// <param name="Station">The station; null: the host name.</param>
/// <param name="Machine">The machine's name or its connection.</param>
/// <param name="BlocksTotal">Motion blocks of the program.</param>
public sealed record JobHistoryStart(long? ProgramId, string? Station, string Machine, long BlocksTotal)
{
    /// <summary>The last line of a selected-block job (<see cref="JobRecord.ToLine"/>), else null.</summary>
    public int? ToLine { get; init; }
}

/// <summary>
/// Jobs and their checkpoints in SQLite (WAL). A checkpoint is written every tick it changed with <c>synchronous=NORMAL</c>
/// (survives a host process crash) and with <c>synchronous=FULL</c> at chunk boundaries, faults and the end
/// (survives a power loss). Opening checks the files (header, write-ahead log frames, <c>PRAGMA quick_check</c>, a
/// write-ahead log lost after a crash) and moves a damaged set aside instead of using or replacing it; every field
/// read is checked (<see cref="JobRecordReader"/>). Failures are <see cref="JobStoreException"/>s naming the file.
/// </summary>
public sealed class JobStore : IJobStore
{
    private static readonly ILogger Logger = Log.ForContext<JobStore>();
    private readonly SqliteConnection _db;
    private readonly object _lock = new();
    private SqliteCommand? _update;
    private bool _full;
    private long _opener;

    private JobStore(SqliteConnection db, string path, long opener)
    {
        _db = db;
        Path = path;
        _opener = opener;
    }

    /// <summary>The database file.</summary>
    public string Path { get; }

    /// <summary>Checkpoints written (for tests and benchmarks).</summary>
    public long CheckpointWrites { get; private set; }

    /// <summary>The default store file: <c>$PMACSTREAM_JOB_DB</c>, else <c>~/.pmacstream/store.db</c> (jobs.db's records are copied into it once).</summary>
    public static string DefaultPath =>
        Environment.GetEnvironmentVariable("PMACSTREAM_JOB_DB") is { Length: > 0 } env
            ? env
            : Preparation.Store.StoreLocation.DefaultSqlitePath;

    /// <summary>Opens (creating when needed) a job database in WAL mode, after checking it is sound.</summary>
    /// <exception cref="JobStoreException">
    /// Damaged (moved aside, <see cref="JobStoreException.KeptAs"/>), or it cannot be opened, read or written.
    /// </exception>
    public static JobStore Open(string path)
    {
        var full = System.IO.Path.GetFullPath(path);
        try
        {
            Directory.CreateDirectory(System.IO.Path.GetDirectoryName(full)!);
            if (!Directory.Exists(full))
            {
                Preparation.Store.StoreFiles.PrepareSqlite(full);
            }

            if (Directory.Exists(full))
            {
                throw new JobStoreException(full, JobStoreProblem.Unavailable, $"{full}: is a folder, not a job database");
            }

            var walExisted = File.Exists(JobStoreFiles.Wal(full));
            if ((JobStoreFiles.HeaderProblem(full) ?? JobStoreFiles.WalProblem(JobStoreFiles.Wal(full))) is { } problem)
            {
                throw Damaged(full, problem);
            }

            return OpenChecked(full, walExisted);
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException)
        {
            throw new JobStoreException(full, JobStoreProblem.Unavailable, $"{full}: the job database cannot be used: {e.Message}", e);
        }
    }

    private static JobStore OpenChecked(string full, bool walExisted)
    {
        var db = new SqliteConnection(new SqliteConnectionStringBuilder { DataSource = full, Pooling = false }.ToString());
        try
        {
            db.Open();
            using (var cmd = db.CreateCommand())
            {
                cmd.CommandText = "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;";
                cmd.ExecuteNonQuery();
            }

            if (QuickCheck(db) is { } problem)
            {
                db.Dispose();
                throw Damaged(full, problem);
            }

            Preparation.Store.SqliteMigrations.Apply(db);
            if (!walExisted && JobStoreOpeners.Recorded(db) is { Count: > 0 } openers)
            {
                db.Dispose();
                throw Damaged(full, $"its write-ahead log {JobStoreFiles.Wal(full)} is missing although {string.Join("; ", openers)} did not close it: the jobs and checkpoints written last are lost");
            }

            return new JobStore(db, full, JobStoreOpeners.Register(db));
        }
        catch (SqliteException e)
        {
            db.Dispose();
            throw IsDamage(e) ? Damaged(full, e.Message) : Unavailable(full, "open", e);
        }
        catch
        {
            db.Dispose();
            throw;
        }
    }

    /// <summary><c>PRAGMA quick_check</c>: null when it says ok, else its first findings.</summary>
    private static string? QuickCheck(SqliteConnection db)
    {
        using var cmd = db.CreateCommand();
        cmd.CommandText = "PRAGMA quick_check(5)";
        using var r = cmd.ExecuteReader();
        var findings = new List<string>();
        while (r.Read())
        {
            findings.Add(r.GetValue(0)?.ToString() ?? string.Empty);
        }

        return findings is ["ok"] ? null : $"the integrity check found: {string.Join("; ", findings)}";
    }

    private static bool IsDamage(SqliteException e) => e.SqliteErrorCode is 11 or 26; // SQLITE_CORRUPT, SQLITE_NOTADB

    private static JobStoreException Damaged(string full, string problem)
    {
        SqliteConnection.ClearAllPools();
        string kept;
        try
        {
            kept = JobStoreFiles.KeepAside(full);
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException)
        {
            Logger.Error("job database {Path} is damaged ({Problem}) and could not be moved aside: {Error}", full, problem, e.Message);
            return new JobStoreException(full, JobStoreProblem.Damaged, $"{full}: the job database is damaged: {problem}. It could not be moved aside ({e.Message}); move it away yourself, then check where the machine is before starting again", e);
        }

        Logger.Error("job database {Path} is damaged ({Problem}); moved aside to {Kept}", full, problem, kept);
        return new JobStoreException(
            full,
            JobStoreProblem.Damaged,
            $"{full}: the job database is damaged: {problem}. It was moved aside to {kept} (kept, nothing deleted); the next job starts a new database. The jobs recorded in it cannot be resumed from here: check where the machine is, then start the program again from a line")
        {
            KeptAs = kept,
        };
    }

    private static JobStoreException Unavailable(string full, string doing, SqliteException e) =>
        new(full, IsDamage(e) ? JobStoreProblem.Damaged : JobStoreProblem.Unavailable, $"{full}: cannot {doing} the job database: {e.Message}", e);

    /// <summary>
    /// Records a new job and returns its id; <paramref name="lineProbe"/> is the line-probe variable its lines carry
    /// (null: none), <paramref name="settings"/> the run settings it starts with (JSON), <paramref name="profile"/> the
    /// machine profile it runs under (name or file, and its identity).
    /// </summary>
    public long CreateJob(string programPath, string programSha256, string manifestPath, StrategyKind strategy, string connection, int? fromLine, string? lineProbe = "P501", string? settings = null,
        (string Source, string Identity)? profile = null, JobHistoryStart? history = null)
    {
        lock (_lock)
        {
            try
            {
                var id = Insert(programPath, programSha256, manifestPath, strategy, connection, fromLine, lineProbe, settings, profile);
                WriteHistoryStart(id, history ?? new JobHistoryStart(null, null, connection, 0));
                return id;
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "record the job in", e);
            }
        }
    }

    private long Insert(string programPath, string programSha256, string manifestPath, StrategyKind strategy, string connection, int? fromLine, string? lineProbe, string? settings,
        (string Source, string Identity)? profile)
    {
        using var cmd = _db.CreateCommand();
        cmd.CommandText = """
            INSERT INTO jobs (created, program_path, program_sha256, manifest_path, strategy, connection, from_line, line_probe, settings, profile, profile_identity)
            VALUES ($c, $p, $h, $m, $s, $conn, $f, $lp, $set, $pr, $pi); SELECT last_insert_rowid();
            """;
        cmd.Parameters.AddWithValue("$pr", (object?)profile?.Source ?? DBNull.Value);
        cmd.Parameters.AddWithValue("$pi", (object?)profile?.Identity ?? DBNull.Value);
        cmd.Parameters.AddWithValue("$set", (object?)settings ?? DBNull.Value);
        cmd.Parameters.AddWithValue("$lp", lineProbe ?? string.Empty);
        cmd.Parameters.AddWithValue("$c", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
        cmd.Parameters.AddWithValue("$p", System.IO.Path.GetFullPath(programPath));
        cmd.Parameters.AddWithValue("$h", programSha256);
        cmd.Parameters.AddWithValue("$m", System.IO.Path.GetFullPath(manifestPath));
        cmd.Parameters.AddWithValue("$s", strategy.ToString().ToLowerInvariant());
        cmd.Parameters.AddWithValue("$conn", connection);
        cmd.Parameters.AddWithValue("$f", fromLine is { } f ? f : DBNull.Value);
        var id = (long)cmd.ExecuteScalar()!;
        Logger.Information("job {Job} created for {Program} ({Strategy}, {Connection})", id, programPath, strategy, connection);
        return id;
    }

    /// <summary>Writes a job's checkpoint; durable ones are committed with <c>synchronous=FULL</c>.</summary>
    public void SaveCheckpoint(long jobId, Checkpoint cp, bool durable) => SaveCheckpoint(jobId, cp, durable, null);

    /// <summary>Writes a job's checkpoint with the blocks executed so far (for the history).</summary>
    public void SaveCheckpoint(long jobId, Checkpoint cp, bool durable, long? executed)
    {
        lock (_lock)
        {
            try
            {
                Update(jobId, cp, durable, executed);
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "write a checkpoint to", e);
            }
        }
    }

    private void Update(long jobId, Checkpoint cp, bool durable, long? executed)
    {
        SetSynchronous(durable);
        _update ??= Prepare();
        var p = _update.Parameters;
        p["$id"].Value = jobId;
        p["$t"].Value = cp.TimeUtc.ToString("O", CultureInfo.InvariantCulture);
        p["$st"].Value = cp.State.ToString();
        p["$l"].Value = cp.LastExecutedLine;
        p["$c"].Value = cp.CurrentChunk;
        p["$nc"].Value = cp.Next.Chunk;
        p["$nl"].Value = cp.Next.Line;
        p["$ne"].Value = cp.NextExact ? 1 : 0;
        p["$cd"].Value = cp.ChunksDownloaded;
        p["$sd"].Value = cp.Started ? 1 : 0;
        p["$ld"].Value = cp.Loaded ? 1 : 0;
        p["$be"].Value = executed is { } x ? x : DBNull.Value;
        _update.ExecuteNonQuery();
        CheckpointWrites++;
        if (durable)
        {
            SetSynchronous(false);
        }
    }

    /// <summary>Records how the job (re)starts: start line, preamble and line probe, committed with <c>synchronous=FULL</c>.</summary>
    public void RecordStart(long jobId, JobStart start)
    {
        lock (_lock)
        {
            try
            {
                WriteStart(jobId, start);
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "record the job's start in", e);
            }
        }
    }

    private void WriteStart(long jobId, JobStart start)
    {
        SetSynchronous(true);
        using var cmd = _db.CreateCommand();
        cmd.CommandText = "UPDATE jobs SET from_line=$f, preamble=$pre, line_probe=$lp WHERE id=$id";
        cmd.Parameters.AddWithValue("$f", start.FromLine is { } f ? f : DBNull.Value);
        cmd.Parameters.AddWithValue("$pre", start.Preamble is { } pre ? string.Join('\n', pre) : DBNull.Value);
        cmd.Parameters.AddWithValue("$lp", start.LineProbeVariable ?? string.Empty);
        cmd.Parameters.AddWithValue("$id", jobId);
        cmd.ExecuteNonQuery();
        SetSynchronous(false);
    }

    private void WriteHistoryStart(long id, JobHistoryStart h)
    {
        using var cmd = _db.CreateCommand();
        cmd.CommandText = "UPDATE jobs SET program_id=$pid, station=$st, machine=$m, os_user=$u, runner=$r, outcome='running', blocks_total=$bt, blocks_executed=0, to_line=$tl WHERE id=$id";
        cmd.Parameters.AddWithValue("$tl", h.ToLine is { } tl ? tl : DBNull.Value);
        cmd.Parameters.AddWithValue("$pid", (object?)h.ProgramId ?? DBNull.Value);
        cmd.Parameters.AddWithValue("$st", h.Station ?? Environment.MachineName);
        cmd.Parameters.AddWithValue("$m", h.Machine);
        cmd.Parameters.AddWithValue("$u", Environment.UserName);
        cmd.Parameters.AddWithValue("$r", JobHistory.ThisProcess);
        cmd.Parameters.AddWithValue("$bt", h.BlocksTotal);
        cmd.Parameters.AddWithValue("$id", id);
        cmd.ExecuteNonQuery();
    }

    /// <summary>Records how a job ended (durably): its outcome, blocks executed, stops and alarms.</summary>
    public void RecordEnd(long jobId, string outcome, long executed, long total, int stops, int alarms)
    {
        lock (_lock)
        {
            try
            {
                SetSynchronous(true);
                using var cmd = _db.CreateCommand();
                cmd.CommandText = "UPDATE jobs SET ended=$e, outcome=$o, blocks_executed=$x, blocks_total=$t, stops=stops+$s, alarms=alarms+$a WHERE id=$id";
                cmd.Parameters.AddWithValue("$e", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
                cmd.Parameters.AddWithValue("$o", outcome);
                cmd.Parameters.AddWithValue("$x", executed);
                cmd.Parameters.AddWithValue("$t", total);
                cmd.Parameters.AddWithValue("$s", stops);
                cmd.Parameters.AddWithValue("$a", alarms);
                cmd.Parameters.AddWithValue("$id", jobId);
                cmd.ExecuteNonQuery();
                SetSynchronous(false);
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "record the job's end in", e);
            }
        }
    }

    /// <summary>Records that a job is resumed by this process (at <paramref name="station"/>): running again, one more resume.</summary>
    public void RecordResume(long jobId, string? station)
    {
        lock (_lock)
        {
            try
            {
                using var cmd = _db.CreateCommand();
                cmd.CommandText = "UPDATE jobs SET resumes=resumes+1, outcome='running', ended=NULL, runner=$r, station=COALESCE($st, station) WHERE id=$id";
                cmd.Parameters.AddWithValue("$r", JobHistory.ThisProcess);
                cmd.Parameters.AddWithValue("$st", (object?)station ?? DBNull.Value);
                cmd.Parameters.AddWithValue("$id", jobId);
                cmd.ExecuteNonQuery();
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "record the resume in", e);
            }
        }
    }

    /// <summary>Sets the job's message (fault text, completion).</summary>
    public void SetMessage(long jobId, string message)
    {
        lock (_lock)
        {
            try
            {
                using var cmd = _db.CreateCommand();
                cmd.CommandText = "UPDATE jobs SET message=$m WHERE id=$id";
                cmd.Parameters.AddWithValue("$m", message);
                cmd.Parameters.AddWithValue("$id", jobId);
                cmd.ExecuteNonQuery();
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "write to", e);
            }
        }
    }

    /// <inheritdoc />
    public void SetSourceLocation(long jobId, string? location)
    {
        lock (_lock)
        {
            try
            {
                using var cmd = _db.CreateCommand();
                cmd.CommandText = "UPDATE jobs SET source_location=$s WHERE id=$id";
                cmd.Parameters.AddWithValue("$s", (object?)location ?? DBNull.Value);
                cmd.Parameters.AddWithValue("$id", jobId);
                cmd.ExecuteNonQuery();
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "write to", e);
            }
        }
    }

    /// <summary>A sink that writes one job's checkpoints.</summary>
    public ICheckpointSink SinkFor(long jobId, Func<long?>? executed = null) => new Sink(this, jobId, executed);

    /// <summary>A job by id, or null.</summary>
    public JobRecord? Get(long id) => Query("WHERE id=$id", ("$id", id)).FirstOrDefault();

    /// <summary>The most recent job that has not completed, or null.</summary>
    public JobRecord? LatestUnfinished() =>
        Query("WHERE cp_state IS NULL OR cp_state <> 'Completed' ORDER BY id DESC LIMIT 1").FirstOrDefault();

    /// <summary>The newest job recorded for a connection (as <see cref="CreateJob"/> took it), whatever its state; null when none.</summary>
    public JobRecord? Latest(string connection) =>
        Query("WHERE connection=$conn ORDER BY id DESC LIMIT 1", ("$conn", connection)).FirstOrDefault();

    /// <summary>All jobs, newest first.</summary>
    public IReadOnlyList<JobRecord> List() => Query("ORDER BY id DESC");

    /// <inheritdoc />
    public void Dispose()
    {
        lock (_lock)
        {
            _update?.Dispose();
            _update = null;
            if (_opener != 0)
            {
                try
                {
                    JobStoreOpeners.Unregister(_db, _opener);
                }
                catch (SqliteException e)
                {
                    // The row stays: the next open still sees the write-ahead log, so nothing is reported wrongly.
                    Logger.Warning("job database {Path}: could not record a clean close: {Error}", Path, e.Message);
                }

                _opener = 0;
            }

            _db.Dispose();
        }
    }

    private void SetSynchronous(bool full)
    {
        if (full == _full)
        {
            return;
        }

        using var cmd = _db.CreateCommand();
        cmd.CommandText = full ? "PRAGMA synchronous=FULL" : "PRAGMA synchronous=NORMAL";
        cmd.ExecuteNonQuery();
        _full = full;
    }

    private SqliteCommand Prepare()
    {
        var cmd = _db.CreateCommand();
        cmd.CommandText = """
            UPDATE jobs SET cp_time=$t, cp_state=$st, cp_last_line=$l, cp_chunk=$c, cp_next_chunk=$nc, cp_next_line=$nl,
              cp_next_exact=$ne, cp_chunks_downloaded=$cd, cp_started=$sd, cp_loaded=$ld,
              blocks_executed=COALESCE($be, blocks_executed) WHERE id=$id
            """;
        foreach (var n in new[] { "$id", "$t", "$st", "$l", "$c", "$nc", "$nl", "$ne", "$cd", "$sd", "$ld", "$be" })
        {
            cmd.Parameters.Add(new SqliteParameter(n, null));
        }

        cmd.Prepare();
        return cmd;
    }

    private List<JobRecord> Query(string where, params (string Name, object Value)[] args)
    {
        var list = new List<JobRecord>();
        lock (_lock)
        {
            try
            {
                using var cmd = _db.CreateCommand();
                cmd.CommandText = $"SELECT {JobRecordReader.Columns} FROM jobs {where}";
                foreach (var (n, v) in args)
                {
                    cmd.Parameters.AddWithValue(n, v);
                }

                using var r = cmd.ExecuteReader();
                while (r.Read())
                {
                    list.Add(JobRecordReader.Read(r, Path));
                }
            }
            catch (SqliteException e)
            {
                throw Unavailable(Path, "read", e);
            }
        }

        return list;
    }

    private sealed class Sink(JobStore store, long jobId, Func<long?>? executed) : ICheckpointSink
    {
        public void Save(Checkpoint checkpoint, bool durable) => store.SaveCheckpoint(jobId, checkpoint, durable, executed?.Invoke());

        public void RecordStart(JobStart start) => store.RecordStart(jobId, start);
    }
}
