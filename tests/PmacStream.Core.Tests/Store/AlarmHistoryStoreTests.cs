using PmacStream.Machine;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

/// <summary>
/// The alarm history in the store (migration 5), the same contract on both engines: alarms raised and cleared as the
/// console sees them, per machine, with the job they came during; an old alarms.jsonl read in once. The PostgreSQL half
/// runs where <c>PMACSTREAM_TEST_PG</c> names a server and reports SKIPPED otherwise.
/// </summary>
public sealed class AlarmHistoryStoreTests : IDisposable
{
    private static readonly DateTimeOffset T0 = new(2026, 11, 27, 8, 0, 0, TimeSpan.Zero);
    private readonly TestFolder _folder = new("alarm-store");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    private static MachineAlarm Limit(int motor) => new("limit+", motor, "X", "X axis (motor 1) on its positive hardware limit", AlarmSeverity.Alarm);

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void An_alarm_is_recorded_when_it_comes_with_its_job_and_closed_when_it_goes(string engine)
    {
        var location = Location(engine);
        var machine = "tcp:test-" + Guid.NewGuid().ToString("N"); // the PostgreSQL store is shared by every run
        new StoreAlarmHistory(location, machine).Observe([Limit(1)], T0, 7);
        new StoreAlarmHistory(location, machine).Observe([Limit(1)], T0.AddSeconds(1), 7); // another process sees the same alarm: not new
        var open = new StoreAlarmHistory(location, machine).List();
        open.Should().ContainSingle();
        open[0].Should().BeEquivalentTo(new { Code = "limit+", Motor = 1, Axis = "X", Raised = T0, Cleared = (DateTimeOffset?)null, JobId = (long?)7 });

        var history = new StoreAlarmHistory(location, machine);
        history.Observe([], T0.AddSeconds(5));
        history.Observe([new MachineAlarm("amp-fault", 2, "Y", "amplifier fault", AlarmSeverity.Alarm)], T0.AddSeconds(9));
        var list = history.List();
        list.Select(r => r.Code).Should().Equal("amp-fault", "limit+"); // newest first
        list[1].Cleared.Should().Be(T0.AddSeconds(5));
        list[0].JobId.Should().BeNull();
        new StoreAlarmHistory(location, machine + "-other").List().Should().BeEmpty("each machine has its own history");

        using var store = AlarmStores.Open(location);
        store.List(machine).Should().HaveCount(2);
    }

    [Fact]
    public void An_old_alarms_jsonl_is_read_into_the_store_once()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        var legacy = Path.Combine(_folder.Path, "alarms.jsonl");
        var file = new AlarmHistoryFile(legacy);
        file.Observe([Limit(1)], T0);
        file.Observe([], T0.AddSeconds(3));
        file.Observe([Limit(3)], T0.AddSeconds(4));

        var history = new StoreAlarmHistory(location, "sim", legacy);
        var list = history.List();
        list.Select(r => (r.Motor, r.Cleared)).Should().Equal((3, (DateTimeOffset?)null), (1, T0.AddSeconds(3)));
        File.Exists(legacy).Should().BeFalse();
        File.Exists(legacy + ".imported").Should().BeTrue();
        new StoreAlarmHistory(location, "sim", legacy).List().Should().HaveCount(2, "it is read in once");
    }

    [Fact]
    public void The_alarm_history_is_migration_5_of_the_sqlite_store()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "v.db"));
        using (AlarmStores.Open(location))
        {
        }

        using var db = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={location.Target}");
        db.Open();
        using var cmd = db.CreateCommand();
        cmd.CommandText = "SELECT name FROM schema_version WHERE version = 5";
        (cmd.ExecuteScalar() as string).Should().Be("alarm history");
    }

    private static StoreLocation PgLocation()
    {
        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        return StoreLocation.Parse(station);
    }

    private StoreLocation Location(string engine) =>
        engine == "sqlite" ? StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db")) : PgLocation();
}
