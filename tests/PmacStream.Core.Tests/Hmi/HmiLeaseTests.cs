using System.Net;
using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Sim.Servers;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// The HMI's job start goes through the machine's lease, as <c>stream</c>'s does: headless, over the real job service
/// and a simulator served over TCP (the built-in simulator is each process's own and not leased). Refused with who
/// holds the machine while another station does; leased by the HMI's station for its job; given back when it ends.
/// </summary>
public sealed class HmiLeaseTests : IAsyncLifetime
{
    private readonly TestFolder _folder = new("hmi-lease");
    private readonly PmacSimulator _sim = new(new SimOptions());
    private PmacTcpServer _server = null!;

    public Task InitializeAsync()
    {
        SimRig.LoadLibrary(_sim.OpenPort("library"));
        var ethernet = _sim.OpenPort("ethernet");
        _server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        _server.Start();
        _sim.StartClock();
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _server.DisposeAsync();
        _sim.Dispose();
        _folder.Dispose();
    }

    [Fact]
    public async Task The_hmi_is_refused_while_another_station_holds_the_machine_and_leases_it_for_its_own_job()
    {
        var store = StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        var source = Path.Combine(_folder.Path, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, source);
        await using var backend = new CoreHmiBackend(new JobService(new JobServiceOptions { Store = store }))
        {
            Station = "hmi-1",
            Machine = "mill-hmi",
            StationSettings = StationSettings.Default,
        };
        await backend.ConnectAsync(new ConnectionSettings(DeviceKind.Ethernet, $"127.0.0.1:{_server.Port}"), MachineProfile.Default);
        var split = await backend.PrepareAsync(source, RunSettings.Default, MachineProfile.Default);
        var request = new HmiJobRequest(split, "chunk", null, false, 100, RunSettings.Default);
        using (ProgramStores.Open(store))
        {
            // The store's schema, leases table included.
        }

        // Another station's live process holds the machine (its row as that station wrote it).
        Sql(store, "INSERT INTO leases (machine, station, pid, runner, job_id, since_ms, heartbeat_ms, expiry_ms) " +
                   "VALUES ('mill-hmi', 'cell-9', 4242, 'otherhost:4242:1', NULL, CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER), " +
                   "CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER), 60000)");
        var refused = () => backend.StartAsync(request);
        (await refused.Should().ThrowAsync<JobException>()).Which.Message.Should().StartWith("machine mill-hmi is leased by station cell-9 (pid 4242");
        backend.Service.JobHistory().Should().BeEmpty("nothing was recorded or sent");
        Sql(store, "DELETE FROM leases WHERE machine = 'mill-hmi'"); // that station gave it back

        var job = await backend.StartAsync(request);
        var shop = backend.Service.ShopViews().Single(m => m.Machine == "mill-hmi");
        shop.Should().BeEquivalentTo(new { Station = "hmi-1", State = "leased" });
        shop.JobId.Should().NotBeNull();
        backend.Service.JobHistory().Single().Should().BeEquivalentTo(new { Station = "hmi-1", Machine = "mill-hmi" });

        await job.AbortAsync();
        await job.DisposeAsync();
        backend.Service.ShopViews().Single(m => m.Machine == "mill-hmi").State.Should().Be("free", "the job's end gives the machine back");
    }

    private static void Sql(StoreLocation store, string sql)
    {
        using var c = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={store.Target};Pooling=False");
        c.Open();
        using var cmd = c.CreateCommand();
        cmd.CommandText = sql;
        cmd.ExecuteNonQuery();
    }
}
