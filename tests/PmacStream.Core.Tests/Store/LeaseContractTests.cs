using Microsoft.Data.Sqlite;
using Npgsql;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Store;

/// <summary>
/// Machine leases on both engines: one holder at a time, refused with who holds it, expired after the holder's
/// expiry by the database's clock, taken back by the same station when its old process is gone, renewed and given
/// back only by their holder. The PostgreSQL half reports SKIPPED without <c>PMACSTREAM_TEST_PG</c>.
/// </summary>
public sealed class LeaseContractTests : IDisposable
{
    private readonly TestFolder _folder = new("lease-contract");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void One_holder_at_a_time_refused_with_who_holds_it_then_expired_and_taken(string engine)
    {
        var location = Location(engine);
        var machine = "mill-" + Guid.NewGuid().ToString("N")[..8];
        using var leases = MachineLeases.Open(location);

        // Another station's live process holds it: refused, with the holder's name, pid and job.
        Insert(location, machine, "A", "otherhost:4242:1", jobId: 7, heartbeatAgo: TimeSpan.Zero, expiry: TimeSpan.FromSeconds(60));
        var refused = leases.Take(machine, "B", null, TimeSpan.FromSeconds(60));
        refused.Taken.Should().BeFalse();
        refused.Holder!.Station.Should().Be("A");
        refused.Holder.Expired.Should().BeFalse();
        MachineLease.Refusal(refused.Holder, machine).Should().MatchRegex($@"^machine {machine} is leased by station A \(pid 4242, job 7\) since \d\d:\d\d:\d\d; it expires 60 s after its last heartbeat");

        // Its heartbeat is older than its expiry: it frees itself, and the take is B's.
        Insert(location, machine, "A", "otherhost:4242:1", jobId: 7, heartbeatAgo: TimeSpan.FromSeconds(5), expiry: TimeSpan.FromSeconds(3));
        leases.Get(machine)!.Expired.Should().BeTrue();
        var taken = leases.Take(machine, "B", 9, TimeSpan.FromSeconds(60));
        taken.Taken.Should().BeTrue();
        taken.Holder!.Station.Should().Be("B");
        taken.Holder.Pid.Should().Be(Environment.ProcessId);
        taken.Holder.JobId.Should().Be(9);

        // The holder takes it again (a resume in the same process), renews it and gives it back; A cannot take it now.
        leases.Take(machine, "B", null, TimeSpan.FromSeconds(60)).Taken.Should().BeTrue();
        leases.Renew(machine, 10).Should().BeTrue();
        leases.Get(machine)!.JobId.Should().Be(10);
        leases.Release(machine);
        leases.Get(machine).Should().BeNull();
        leases.Renew(machine, null).Should().BeFalse("a lease given back is renewed no more");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void The_same_station_takes_its_lease_back_when_its_old_process_is_gone_another_station_does_not(string engine)
    {
        var location = Location(engine);
        var machine = "lathe-" + Guid.NewGuid().ToString("N")[..8];
        using var leases = MachineLeases.Open(location);
        var dead = $"{Environment.MachineName}:{int.MaxValue - 1}:0"; // a process of this host that does not run
        Insert(location, machine, "A", dead, jobId: 3, heartbeatAgo: TimeSpan.Zero, expiry: TimeSpan.FromSeconds(60));

        leases.Take(machine, "B", null, TimeSpan.FromSeconds(60)).Taken.Should().BeFalse("another station waits for the expiry");
        var back = leases.Take(machine, "A", null, TimeSpan.FromSeconds(60));
        back.Taken.Should().BeTrue("station A crashed and resumes: its old process is gone");
        back.Holder!.JobId.Should().Be(3, "the job stays named until the new holder names its own");
        leases.Release(machine);
    }

    [Fact]
    public void Station_settings_come_from_the_settings_file_and_run_settings_skip_them()
    {
        var file = Path.Combine(_folder.Path, "settings.json");
        File.WriteAllText(file, """{ "tickMs": 40, "store": "sqlite:/tmp/x.db", "station": "cell-2", "leaseHeartbeatSeconds": 2, "leaseExpirySeconds": 20 }""");
        var s = StationSettings.Load(file);
        s.Store.Should().Be("sqlite:/tmp/x.db");
        s.StationName(null).Should().Be("cell-2");
        s.StationName("cli").Should().Be("cli", "the option wins");
        s.LeaseHeartbeat.Should().Be(TimeSpan.FromSeconds(2));
        s.LeaseExpiry.Should().Be(TimeSpan.FromSeconds(20));
        RunSettingsFile.Load(file).TickPeriod.Should().Be(TimeSpan.FromMilliseconds(40), "the run settings read the rest of the same file");
        StationSettings.Default.LeaseExpiry.Should().Be(TimeSpan.FromSeconds(60));
        StationSettings.Default.LeaseHeartbeat.Should().Be(TimeSpan.FromSeconds(10));

        File.WriteAllText(file, "{\n  \"leaseExpirySeconds\": 600\n}");
        var bad = FluentActions.Invoking(() => StationSettings.Load(file)).Should().Throw<RunSettingsException>().Which;
        bad.Message.Should().StartWith($"{file}:2:25: error R003: leaseExpirySeconds:");
    }

    [Fact]
    public void The_store_option_beats_the_settings_file_which_beats_the_environment()
    {
        var before = Environment.GetEnvironmentVariable(StoreLocation.EnvironmentVariable);
        try
        {
            Environment.SetEnvironmentVariable(StoreLocation.EnvironmentVariable, "sqlite:/tmp/env.db");
            StoreLocation.Resolve("sqlite:/tmp/opt.db", null, "sqlite:/tmp/file.db").Target.Should().Be("/tmp/opt.db");
            StoreLocation.Resolve(null, null, "sqlite:/tmp/file.db").Target.Should().Be("/tmp/file.db");
            StoreLocation.Resolve(null, null, null).Target.Should().Be("/tmp/env.db");
        }
        finally
        {
            Environment.SetEnvironmentVariable(StoreLocation.EnvironmentVariable, before);
        }
    }

    /// <summary>Writes a lease row as another station would have (its heartbeat <paramref name="heartbeatAgo"/> by the database's clock).</summary>
    private static void Insert(StoreLocation location, string machine, string station, string runner, long jobId, TimeSpan heartbeatAgo, TimeSpan expiry)
    {
        const string Sql = "INSERT INTO leases (machine, station, pid, runner, job_id, since_ms, heartbeat_ms, expiry_ms) VALUES (@m, @s, 4242, @r, @j, {0} - @ago, {0} - @ago, @e) "
            + "ON CONFLICT (machine) DO UPDATE SET station = excluded.station, runner = excluded.runner, job_id = excluded.job_id, heartbeat_ms = excluded.heartbeat_ms, expiry_ms = excluded.expiry_ms";
        using System.Data.Common.DbConnection c = location.Engine == StoreEngine.Sqlite ? new SqliteConnection($"Data Source={location.Target}") : new NpgsqlConnection(location.Target);
        c.Open();
        using var cmd = c.CreateCommand();
        cmd.CommandText = string.Format(System.Globalization.CultureInfo.InvariantCulture, Sql,
            location.Engine == StoreEngine.Sqlite ? "CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER)" : "CAST(EXTRACT(EPOCH FROM clock_timestamp()) * 1000 AS BIGINT)");
        foreach (var (name, value) in new (string, object)[] { ("m", machine), ("s", station), ("r", runner), ("j", jobId), ("ago", (long)heartbeatAgo.TotalMilliseconds), ("e", (long)expiry.TotalMilliseconds) })
        {
            var p = cmd.CreateParameter();
            p.ParameterName = name;
            p.Value = value;
            cmd.Parameters.Add(p);
        }

        cmd.ExecuteNonQuery();
    }

    private StoreLocation Location(string engine)
    {
        if (engine == "sqlite")
        {
            return StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        }

        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        return StoreLocation.Parse(station);
    }
}
