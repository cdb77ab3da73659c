using System.Data;
using System.Data.Common;
using System.Globalization;
using Microsoft.Data.Sqlite;
using Npgsql;
using PmacStream.Preparation.Store;

namespace PmacStream.Streaming;

/// <summary>Who holds a machine's lease, as the store records it.</summary>
/// <param name="Machine">The machine (<c>--machine</c>, else its connection).</param>
/// <param name="Station">The station that holds it.</param>
/// <param name="Pid">The holder's process id on its station.</param>
/// <param name="Runner">The holder process as <c>host:pid:start</c> (<see cref="JobHistory.ThisProcess"/>).</param>
/// <param name="JobId">The job it runs there, or null (not started yet, or a console command).</param>
/// <param name="Since">When the lease was taken.</param>
/// <param name="Heartbeat">Its last heartbeat.</param>
/// <param name="Expiry">How long after its last heartbeat it frees itself (the holder's setting).</param>
/// <param name="Now">The store's clock when this was read (expiry is judged by it, not by a station's clock).</param>
public sealed record LeaseHolder(string Machine, string Station, long Pid, string Runner, long? JobId, DateTimeOffset Since, DateTimeOffset Heartbeat, TimeSpan Expiry, DateTimeOffset Now)
{
    /// <summary>True when its holder stopped renewing it for longer than its expiry: any station may take it.</summary>
    public bool Expired => Heartbeat + Expiry < Now;
}

/// <summary>What taking a lease gave: taken (with the row as now held), or refused with who holds it.</summary>
/// <param name="Taken">True when this process holds the lease now.</param>
/// <param name="Holder">The lease as held after the attempt (this process's, or the other station's).</param>
public sealed record LeaseTake(bool Taken, LeaseHolder? Holder);

/// <summary>
/// Machine leases in the store (table <c>leases</c>, migration 6, both engines): one station's process at a time
/// drives a controller. Every change is one conditional statement (an upsert whose <c>WHERE</c> says when the row may
/// be replaced, a delete or update keyed by the holder), so two stations taking at once cannot both win, and every
/// value is a parameter. Times are the database's clock in milliseconds, so stations with skewed clocks agree on expiry.
/// </summary>
public sealed class MachineLeases : IDisposable
{
    private readonly Func<DbConnection> _open;
    private readonly string _now;
    private readonly IDisposable? _owned;

    private MachineLeases(Func<DbConnection> open, string now, string display, IDisposable? owned)
    {
        _open = open;
        _now = now;
        _owned = owned;
        Path = display;
    }

    /// <summary>The store, for messages (never its password).</summary>
    public string Path { get; }

    /// <summary>Opens the leases of a store (migrating it as opening its jobs does).</summary>
    /// <exception cref="JobStoreException">The store cannot be opened or reached.</exception>
    public static MachineLeases Open(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        if (location.Engine == StoreEngine.Sqlite)
        {
            using (JobStore.Open(location.Target))
            {
                // Created, checked and migrated as the job store does it.
            }

            var cs = new SqliteConnectionStringBuilder { DataSource = location.Target, Pooling = false, DefaultTimeout = 30 }.ToString();
            return new MachineLeases(() => new SqliteConnection(cs), "CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER)", location.Display, null);
        }

        try
        {
            using (PgSchema.OpenMigrated(location))
            {
            }
        }
        catch (Exception e) when (e is NpgsqlException or InvalidOperationException or ArgumentException)
        {
            throw new JobStoreException(location.Display, JobStoreProblem.Unavailable, $"{location.Display}: the store cannot be used: {StoreLocation.Redact(e.Message)}", e);
        }

        var source = new NpgsqlSlimDataSourceBuilder(location.Target).Build();
        return new MachineLeases(source.CreateConnection, "CAST(EXTRACT(EPOCH FROM clock_timestamp()) * 1000 AS BIGINT)", location.Display, source);
    }

    /// <summary>
    /// Takes <paramref name="machine"/>'s lease for this process when it is free, expired, already this process's, or
    /// held by a process of the same station on this host that is gone (a crash of this station); else returns who
    /// holds it. The take is one conditional upsert: a holder replaced since it was read is not replaced.
    /// </summary>
    /// <exception cref="DbException">The store cannot be reached.</exception>
    public LeaseTake Take(string machine, string station, long? jobId, TimeSpan expiry)
    {
        ArgumentNullException.ThrowIfNull(machine);
        ArgumentNullException.ThrowIfNull(station);
        var runner = JobHistory.ThisProcess;
        if (TryTake(machine, station, runner, jobId, expiry, gone: string.Empty))
        {
            return new LeaseTake(true, Get(machine));
        }

        var holder = Get(machine);
        if (holder is not null && string.Equals(holder.Station, station, StringComparison.Ordinal) && JobHistory.RunnerGone(holder.Runner)
            && TryTake(machine, station, runner, jobId, expiry, gone: holder.Runner))
        {
            return new LeaseTake(true, Get(machine));
        }

        return new LeaseTake(false, holder);
    }

    /// <summary>Renews this process's lease (and names its job); false when it holds it no more (it expired and was taken).</summary>
    /// <exception cref="DbException">The store cannot be reached.</exception>
    public bool Renew(string machine, long? jobId)
    {
        using var c = _open();
        c.Open();
        using var cmd = Command(c, $"UPDATE leases SET heartbeat_ms = {_now}, job_id = COALESCE(@j, job_id) WHERE machine = @m AND runner = @r");
        Add(cmd, "m", DbType.String, machine);
        Add(cmd, "r", DbType.String, JobHistory.ThisProcess);
        Add(cmd, "j", DbType.Int64, jobId);
        return cmd.ExecuteNonQuery() == 1;
    }

    /// <summary>Gives back this process's lease (a lease another process holds now is left alone).</summary>
    /// <exception cref="DbException">The store cannot be reached.</exception>
    public void Release(string machine)
    {
        using var c = _open();
        c.Open();
        using var cmd = Command(c, "DELETE FROM leases WHERE machine = @m AND runner = @r");
        Add(cmd, "m", DbType.String, machine);
        Add(cmd, "r", DbType.String, JobHistory.ThisProcess);
        cmd.ExecuteNonQuery();
    }

    /// <summary>The lease of one machine, or null when none is recorded.</summary>
    public LeaseHolder? Get(string machine) => Query("WHERE machine = @m", machine).FirstOrDefault();

    /// <summary>Every lease recorded (expired ones too), by machine.</summary>
    public IReadOnlyList<LeaseHolder> List() => Query("ORDER BY machine", null);

    /// <inheritdoc />
    public void Dispose() => _owned?.Dispose();

    private bool TryTake(string machine, string station, string runner, long? jobId, TimeSpan expiry, string gone)
    {
        using var c = _open();
        c.Open();
        using var cmd = Command(c, $"""
            INSERT INTO leases (machine, station, pid, runner, job_id, since_ms, heartbeat_ms, expiry_ms)
            VALUES (@m, @s, @pid, @r, @j, {_now}, {_now}, @e)
            ON CONFLICT (machine) DO UPDATE SET station = excluded.station, pid = excluded.pid, runner = excluded.runner,
              job_id = COALESCE(excluded.job_id, leases.job_id),
              since_ms = CASE WHEN leases.runner = excluded.runner THEN leases.since_ms ELSE excluded.since_ms END,
              heartbeat_ms = excluded.heartbeat_ms, expiry_ms = excluded.expiry_ms
            WHERE leases.runner = excluded.runner OR leases.heartbeat_ms + leases.expiry_ms < excluded.heartbeat_ms OR leases.runner = @gone
            RETURNING machine
            """);
        Add(cmd, "m", DbType.String, machine);
        Add(cmd, "s", DbType.String, station);
        Add(cmd, "pid", DbType.Int64, (long)Environment.ProcessId);
        Add(cmd, "r", DbType.String, runner);
        Add(cmd, "j", DbType.Int64, jobId);
        Add(cmd, "e", DbType.Int64, (long)expiry.TotalMilliseconds);
        Add(cmd, "gone", DbType.String, gone);
        return cmd.ExecuteScalar() is not null and not DBNull;
    }

    private List<LeaseHolder> Query(string where, string? machine)
    {
        using var c = _open();
        c.Open();
        // where: fixed text of this class
        using var cmd = Command(c, $"SELECT machine, station, pid, runner, job_id, since_ms, heartbeat_ms, expiry_ms, {_now} FROM leases {where}");
        if (machine is not null)
        {
            Add(cmd, "m", DbType.String, machine);
        }

        var list = new List<LeaseHolder>();
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            list.Add(new LeaseHolder(r.GetString(0), r.GetString(1), r.GetInt64(2), r.GetString(3), r.IsDBNull(4) ? null : r.GetInt64(4),
                Time(r.GetInt64(5)), Time(r.GetInt64(6)), TimeSpan.FromMilliseconds(r.GetInt64(7)), Time(Convert.ToInt64(r.GetValue(8), CultureInfo.InvariantCulture))));
        }

        return list;
    }

    private static DateTimeOffset Time(long ms) => DateTimeOffset.FromUnixTimeMilliseconds(ms);

    private static DbCommand Command(DbConnection c, string sql)
    {
        var cmd = c.CreateCommand();
        cmd.CommandText = sql;
        return cmd;
    }

    private static void Add(DbCommand cmd, string name, DbType type, object? value)
    {
        var p = cmd.CreateParameter();
        p.ParameterName = name;
        p.DbType = type;
        p.Value = value ?? DBNull.Value;
        cmd.Parameters.Add(p);
    }
}
