using System.Globalization;
using Npgsql;
using PmacStream.Preparation.Store;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// Jobs, checkpoints and history in a shop's PostgreSQL: the same table and record reader as <see cref="JobStore"/>.
/// Each write is its own committed statement (durable on the server: <c>synchronous_commit</c> on). A station keeps
/// running its job when the server is unreachable: the writes it could not make wait here, in order (a job's newer
/// checkpoint replaces its older waiting one), and go in before the next write once the server answers again; the
/// close waits a while for the server before giving up on them (and says so). Every statement is parameterized; the
/// password never appears in a message.
/// </summary>
public sealed class PgJobStore : IJobStore
{
    /// <summary>How long the close waits for an unreachable server to take the writes still waiting.</summary>
    public static TimeSpan CloseWait { get; set; } = TimeSpan.FromSeconds(60);

    private static readonly ILogger Logger = Log.ForContext<PgJobStore>();
    private readonly NpgsqlDataSource _source;
    private readonly object _lock = new();
    private readonly List<(string Kind, long Job, Action<NpgsqlConnection> Write)> _waiting = [];
    private bool _outage;

    private PgJobStore(NpgsqlDataSource source, string display)
    {
        _source = source;
        Path = display;
    }

    /// <inheritdoc />
    public string Path { get; }

    /// <summary>Writes waiting for the server (0 unless it was unreachable).</summary>
    public int Waiting
    {
        get
        {
            lock (_lock)
            {
                return _waiting.Count;
            }
        }
    }

    /// <summary>Opens the store's jobs (migrating the schema when this role may).</summary>
    /// <exception cref="JobStoreException">The server cannot be reached, or the schema is behind and this role may not migrate it.</exception>
    public static PgJobStore Open(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        try
        {
            using (PgSchema.OpenMigrated(location))
            {
            }

            return new PgJobStore(new NpgsqlSlimDataSourceBuilder(location.Target).Build(), location.Display);
        }
        catch (Exception e) when (e is NpgsqlException or InvalidOperationException or ArgumentException)
        {
            throw new JobStoreException(location.Display, JobStoreProblem.Unavailable, $"{location.Display}: the store cannot be used: {StoreLocation.Redact(e.Message)}", e);
        }
    }

    /// <inheritdoc />
    public long CreateJob(string programPath, string programSha256, string manifestPath, StrategyKind strategy, string connection, int? fromLine, string? lineProbe = "P501", string? settings = null,
        (string Source, string Identity)? profile = null, JobHistoryStart? history = null)
    {
        var h = history ?? new JobHistoryStart(null, null, connection, 0);
        try
        {
            lock (_lock)
            {
                using var c = _source.OpenConnection();
                Flush(c);
                using var cmd = new NpgsqlCommand("""
                    INSERT INTO jobs (created, program_path, program_sha256, manifest_path, strategy, connection, from_line, line_probe, settings, profile, profile_identity,
                                      program_id, station, machine, os_user, runner, outcome, blocks_total, blocks_executed, to_line)
                    VALUES (@c, @p, @h, @m, @s, @conn, @f, @lp, @set, @pr, @pi, @pid, @st, @mach, @u, @r, 'running', @bt, 0, @tl) RETURNING id
                    """, c);
                cmd.Parameters.AddWithValue("c", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
                cmd.Parameters.AddWithValue("p", System.IO.Path.GetFullPath(programPath));
                cmd.Parameters.AddWithValue("h", programSha256);
                cmd.Parameters.AddWithValue("m", System.IO.Path.GetFullPath(manifestPath));
                cmd.Parameters.AddWithValue("s", strategy.ToString().ToLowerInvariant());
                cmd.Parameters.AddWithValue("conn", connection);
                cmd.Parameters.AddWithValue("f", fromLine is { } f ? (long)f : DBNull.Value);
                cmd.Parameters.AddWithValue("lp", lineProbe ?? string.Empty);
                cmd.Parameters.AddWithValue("set", (object?)settings ?? DBNull.Value);
                cmd.Parameters.AddWithValue("pr", (object?)profile?.Source ?? DBNull.Value);
                cmd.Parameters.AddWithValue("pi", (object?)profile?.Identity ?? DBNull.Value);
                cmd.Parameters.AddWithValue("pid", h.ProgramId is { } pid ? pid : DBNull.Value);
                cmd.Parameters.AddWithValue("st", h.Station ?? Environment.MachineName);
                cmd.Parameters.AddWithValue("mach", h.Machine);
                cmd.Parameters.AddWithValue("u", Environment.UserName);
                cmd.Parameters.AddWithValue("r", JobHistory.ThisProcess);
                cmd.Parameters.AddWithValue("bt", h.BlocksTotal);
                cmd.Parameters.AddWithValue("tl", h.ToLine is { } tl ? (long)tl : DBNull.Value);
                var id = (long)cmd.ExecuteScalar()!;
                Logger.Information("job {Job} created in {Store} for {Program} ({Strategy}, {Connection})", id, Path, programPath, strategy, connection);
                return id;
            }
        }
        catch (NpgsqlException e)
        {
            throw Unavailable("record the job in", e);
        }
    }

    /// <inheritdoc />
    public void SaveCheckpoint(long jobId, Checkpoint cp, bool durable, long? executed) => Write("checkpoint", jobId, c =>
    {
        using var cmd = new NpgsqlCommand("""
            UPDATE jobs SET cp_time=@t, cp_state=@st, cp_last_line=@l, cp_chunk=@c, cp_next_chunk=@nc, cp_next_line=@nl, cp_next_exact=@ne,
              cp_chunks_downloaded=@cd, cp_started=@sd, cp_loaded=@ld, blocks_executed=COALESCE(@be, blocks_executed) WHERE id=@id
            """, c);
        cmd.Parameters.AddWithValue("t", cp.TimeUtc.ToString("O", CultureInfo.InvariantCulture));
        cmd.Parameters.AddWithValue("st", cp.State.ToString());
        cmd.Parameters.AddWithValue("l", (long)cp.LastExecutedLine);
        cmd.Parameters.AddWithValue("c", (long)cp.CurrentChunk);
        cmd.Parameters.AddWithValue("nc", (long)cp.Next.Chunk);
        cmd.Parameters.AddWithValue("nl", (long)cp.Next.Line);
        cmd.Parameters.AddWithValue("ne", cp.NextExact ? 1L : 0L);
        cmd.Parameters.AddWithValue("cd", (long)cp.ChunksDownloaded);
        cmd.Parameters.AddWithValue("sd", cp.Started ? 1L : 0L);
        cmd.Parameters.AddWithValue("ld", cp.Loaded ? 1L : 0L);
        cmd.Parameters.Add(new NpgsqlParameter<long?>("be", NpgsqlTypes.NpgsqlDbType.Bigint) { TypedValue = executed });
        cmd.Parameters.AddWithValue("id", jobId);
        cmd.ExecuteNonQuery();
    });

    /// <inheritdoc />
    public void RecordStart(long jobId, JobStart start)
    {
        ArgumentNullException.ThrowIfNull(start);
        Write("start", jobId, c =>
        {
            using var cmd = new NpgsqlCommand("UPDATE jobs SET from_line=@f, preamble=@pre, line_probe=@lp WHERE id=@id", c);
            cmd.Parameters.AddWithValue("f", start.FromLine is { } f ? (long)f : DBNull.Value);
            cmd.Parameters.AddWithValue("pre", start.Preamble is { } pre ? string.Join('\n', pre) : DBNull.Value);
            cmd.Parameters.AddWithValue("lp", start.LineProbeVariable ?? string.Empty);
            cmd.Parameters.AddWithValue("id", jobId);
            cmd.ExecuteNonQuery();
        });
    }

    /// <inheritdoc />
    public void SetMessage(long jobId, string message) => Write("message", jobId, c =>
    {
        using var cmd = new NpgsqlCommand("UPDATE jobs SET message=@m WHERE id=@id", c);
        cmd.Parameters.AddWithValue("m", message);
        cmd.Parameters.AddWithValue("id", jobId);
        cmd.ExecuteNonQuery();
    });

    /// <inheritdoc />
    public void SetSourceLocation(long jobId, string? location) => Write("source location", jobId, c =>
    {
        using var cmd = new NpgsqlCommand("UPDATE jobs SET source_location=@s WHERE id=@id", c);
        cmd.Parameters.Add(new NpgsqlParameter<string?>("s", NpgsqlTypes.NpgsqlDbType.Text) { TypedValue = location });
        cmd.Parameters.AddWithValue("id", jobId);
        cmd.ExecuteNonQuery();
    });

    /// <inheritdoc />
    public void RecordEnd(long jobId, string outcome, long executed, long total, int stops, int alarms)
    {
        var ended = DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture);
        Write("end", jobId, c =>
        {
            using var cmd = new NpgsqlCommand("UPDATE jobs SET ended=@e, outcome=@o, blocks_executed=@x, blocks_total=@t, stops=stops+@s, alarms=alarms+@a WHERE id=@id", c);
            cmd.Parameters.AddWithValue("e", ended);
            cmd.Parameters.AddWithValue("o", outcome);
            cmd.Parameters.AddWithValue("x", executed);
            cmd.Parameters.AddWithValue("t", total);
            cmd.Parameters.AddWithValue("s", (long)stops);
            cmd.Parameters.AddWithValue("a", (long)alarms);
            cmd.Parameters.AddWithValue("id", jobId);
            cmd.ExecuteNonQuery();
        });
    }

    /// <inheritdoc />
    public void RecordResume(long jobId, string? station)
    {
        var runner = JobHistory.ThisProcess;
        Write("resume", jobId, c =>
        {
            using var cmd = new NpgsqlCommand("UPDATE jobs SET resumes=resumes+1, outcome='running', ended=NULL, runner=@r, station=COALESCE(@st, station) WHERE id=@id", c);
            cmd.Parameters.AddWithValue("r", runner);
            cmd.Parameters.Add(new NpgsqlParameter<string?>("st", NpgsqlTypes.NpgsqlDbType.Text) { TypedValue = station });
            cmd.Parameters.AddWithValue("id", jobId);
            cmd.ExecuteNonQuery();
        });
    }

    /// <inheritdoc />
    public JobRecord? Get(long id) => Query("WHERE id=@id", ("id", id)).FirstOrDefault();

    /// <inheritdoc />
    public JobRecord? LatestUnfinished() => Query("WHERE cp_state IS NULL OR cp_state <> 'Completed' ORDER BY id DESC LIMIT 1").FirstOrDefault();

    /// <inheritdoc />
    public JobRecord? Latest(string connection) => Query("WHERE connection=@conn ORDER BY id DESC LIMIT 1", ("conn", connection)).FirstOrDefault();

    /// <inheritdoc />
    public IReadOnlyList<JobRecord> List() => Query("ORDER BY id DESC");

    /// <summary>Closes the store; writes still waiting for an unreachable server get <see cref="CloseWait"/> to go in.</summary>
    public void Dispose()
    {
        var until = DateTime.UtcNow + CloseWait;
        while (Waiting > 0 && DateTime.UtcNow < until)
        {
            if (TryFlush())
            {
                break;
            }

            Thread.Sleep(1000);
        }

        if (Waiting > 0)
        {
            Logger.Error("{Store}: {Count} job record writes could not reach the server and are lost (the last checkpoint stays where it was)", Path, Waiting);
        }

        _source.Dispose();
    }

    private bool TryFlush()
    {
        lock (_lock)
        {
            try
            {
                using var c = _source.OpenConnection();
                Flush(c);
                return true;
            }
            catch (NpgsqlException)
            {
                return false;
            }
        }
    }

    /// <summary>Makes a write, after the ones waiting; an unreachable server keeps it waiting instead of stopping the job.</summary>
    private void Write(string kind, long jobId, Action<NpgsqlConnection> write)
    {
        lock (_lock)
        {
            if (kind == "checkpoint")
            {
                _waiting.RemoveAll(w => w.Kind == "checkpoint" && w.Job == jobId); // only the newest checkpoint matters
            }

            _waiting.Add((kind, jobId, write));
            try
            {
                using var c = _source.OpenConnection();
                Flush(c);
            }
            catch (NpgsqlException e) when (e is not PostgresException || e.IsTransient)
            {
                if (!_outage)
                {
                    _outage = true;
                    Logger.Warning("{Store}: the server cannot be reached ({Error}); the job runs on and its records wait here", Path, StoreLocation.Redact(e.Message));
                }
            }
            catch (PostgresException e)
            {
                _waiting.RemoveAt(_waiting.Count - 1);
                throw new JobStoreException(Path, JobStoreProblem.Unavailable, $"{Path}: cannot write the job's {kind}: {StoreLocation.Redact(e.MessageText)}", e);
            }
        }
    }

    private void Flush(NpgsqlConnection c)
    {
        while (_waiting.Count > 0)
        {
            _waiting[0].Write(c);
            _waiting.RemoveAt(0);
        }

        if (_outage)
        {
            _outage = false;
            Logger.Information("{Store}: reachable again; the waiting job records are written", Path);
        }
    }

    private List<JobRecord> Query(string where, params (string Name, object Value)[] args)
    {
        var list = new List<JobRecord>();
        try
        {
            using var c = _source.OpenConnection();
            using var cmd = new NpgsqlCommand($"SELECT {JobRecordReader.Columns} FROM jobs {where}", c); // where: fixed text of this class
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
        catch (NpgsqlException e)
        {
            throw Unavailable("read", e);
        }

        return list;
    }

    private JobStoreException Unavailable(string doing, NpgsqlException e) =>
        new(Path, JobStoreProblem.Unavailable, $"{Path}: cannot {doing} the store: {StoreLocation.Redact(e.Message)}", e);
}
