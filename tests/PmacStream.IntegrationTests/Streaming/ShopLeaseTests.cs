using System.Diagnostics;
using System.Globalization;
using System.Net;
using System.Text.Json;
using Npgsql;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// A shop on one store, from the command line: a machine is leased by one station's process at a time (the second
/// is refused, exit 1, with who holds it; a killed holder's lease expires, then the other station resumes its job
/// exactly), <c>pmacstream shop</c> lists who runs what, a PostgreSQL server stopped for 10 s in the middle of a job
/// loses nothing of its history, and a password in the store's URI appears nowhere.
/// </summary>
[Collection("stream-cli")]
public sealed class ShopLeaseTests : IDisposable
{
    private readonly TestFolder _folder = new("shop");

    public void Dispose() => _folder.Dispose();

    [Fact]
    public async Task Shop_lists_the_machine_its_job_and_the_lease_given_back_on_sqlite()
    {
        var store = "sqlite:" + Path.Combine(_folder.Path, "store.db");
        var src = Program(300);
        await using var rig = ServedSim.Start(SimSpeed.Factor(50));
        var run = await RunAsync("stream", src, "--tcp", rig.Spec, "--load-library", "--machine", "mill-7", "--station", "cell-1", "--stops", "continue", "--store", store);
        run.Code.Should().Be(0, run.Out + run.Err);

        using var shop = JsonDocument.Parse((await RunAsync("shop", "--json", "--store", store)).Out);
        var m = shop.RootElement.EnumerateArray().Should().ContainSingle().Which;
        m.GetProperty("machine").GetString().Should().Be("mill-7");
        m.GetProperty("state").GetString().Should().Be("free", "the lease is given back when the job ends");
        m.GetProperty("station").ValueKind.Should().Be(JsonValueKind.Null);
        m.GetProperty("outcome").GetString().Should().Be("completed");
        m.GetProperty("program").GetString().Should().Be("part.nc");
        m.GetProperty("programId").GetInt64().Should().BeGreaterThan(0);
        m.GetProperty("blocksExecuted").GetInt64().Should().Be(m.GetProperty("blocksTotal").GetInt64()).And.Be(301);
        m.GetProperty("line").GetInt64().Should().BeGreaterThan(300);
        (await RunAsync("shop", "--store", store)).Out.Should().Contain("mill-7").And.Contain("completed").And.Contain("free");

        // Another station's live lease: stream and jog are refused, exit 1, and the controller hears nothing.
        using (var db = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={store["sqlite:".Length..]};Pooling=False"))
        {
            db.Open();
            using var cmd = db.CreateCommand();
            cmd.CommandText = "INSERT INTO leases (machine, station, pid, runner, job_id, since_ms, heartbeat_ms, expiry_ms) "
                + "VALUES ('mill-7', 'cell-9', 4242, 'otherhost:4242:1', NULL, CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER), CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER), 60000)";
            cmd.ExecuteNonQuery();
        }

        var packets = rig.PacketsServed;
        var refused = await RunAsync("stream", src, "--tcp", rig.Spec, "--machine", "mill-7", "--station", "cell-1", "--stops", "continue", "--store", store);
        refused.Code.Should().Be(1, refused.Out + refused.Err);
        refused.Err.Should().Contain("machine mill-7 is leased by station cell-9 (pid 4242) since ");
        var jog = await RunAsync("jog", "X", "+1", "--tcp", rig.Spec, "--machine", "mill-7", "--store", store);
        jog.Code.Should().Be(1, jog.Out + jog.Err);
        jog.Err.Should().Contain("is leased by station cell-9");
        rig.PacketsServed.Should().Be(packets, "refused before anything reached the controller");
    }

    [SkippableFact]
    public async Task A_second_station_is_refused_until_the_killed_holders_lease_expires_then_resumes_the_job_exactly()
    {
        var store = PgStore();
        // 20 s: the early resume below must reach the lease while it holds, on a loaded machine too. At 8 s, under load
        // 36, it timed out: a resume that finds the lease expired takes the job over, and with the controller's clock
        // stopped it never finishes.
        var settings = Settings(heartbeat: 1, expiry: 20);
        var machine = "mill-" + Guid.NewGuid().ToString("N")[..8];
        var src = Program(1500);
        await using var rig = ServedSim.Start(SimSpeed.Factor(2));
        string[] Common(params string[] more) => [.. more, "--tcp", rig.Spec, "--machine", machine, "--store", store, "--settings", settings, "--stops", "continue"];

        var a = Start(Common("stream", src, "--station", "A", "--load-library"));
        await rig.WaitForLineAsync(50, () => a.HasExited, async () => await a.Output + await a.Error);
        var refused = await RunAsync(Common("stream", src, "--station", "B"));
        refused.Code.Should().Be(1, refused.Out + refused.Err);
        refused.Err.Should().MatchRegex($@"machine {machine} is leased by station A \(pid {a.Id}, job \d+\) since \d\d:\d\d:\d\d; it expires 20 s after its last heartbeat");
        a.HasExited.Should().BeFalse("station A still runs its job");

        a.Kill(true); // SIGKILL: no last checkpoint, no lease given back
        await a.WaitForExitAsync();
        var killedAt = DateTime.UtcNow;
        rig.Sim.StopClock(); // the controller holds its place while the stations wait (as a slow link would)
        ((int)rig.Sim.ReadVariable('M', 0)).Should().BeInRange(50, 1500, "killed in the middle of the job");
        var job = Shop(store, machine);
        job.GetProperty("station").GetString().Should().Be("A");
        job.GetProperty("state").GetString().Should().Be("leased");
        var jobId = job.GetProperty("jobId").GetInt64().ToString(CultureInfo.InvariantCulture);

        var early = await RunAsync(Common("resume", "--job", jobId, "--station", "B", "--yes"));
        if (DateTime.UtcNow - killedAt < TimeSpan.FromSeconds(19))
        {
            early.Code.Should().Be(1, early.Out + early.Err);
            early.Err.Should().Contain("is leased by station A");
        }

        while (!Shop(store, machine).GetProperty("expired").GetBoolean())
        {
            (DateTime.UtcNow - killedAt).Should().BeLessThan(TimeSpan.FromSeconds(45), "the lease expires 20 s after its last heartbeat");
            await Task.Delay(250);
        }

        rig.Sim.StartClock();
        var resumed = await RunAsync(Common("resume", "--job", jobId, "--station", "B", "--yes"));
        resumed.Code.Should().Be(0, resumed.Out + resumed.Err);
        resumed.Out.Should().Contain("controller still holds the job");
        rig.Sim.StopClock();
        rig.Sim.RunUntilIdle(TimeSpan.FromMinutes(10));
        rig.ExecutedLines().Should().Equal(TrackedLines(src), "every block once, in order, across the kill and the other station's resume");

        var history = Job(store, jobId);
        history.GetProperty("outcome").GetString().Should().Be("completed");
        history.GetProperty("station").GetString().Should().Be("B");
        history.GetProperty("resumes").GetInt32().Should().Be(1);
        history.GetProperty("blocksExecuted").GetInt64().Should().Be(history.GetProperty("blocksTotal").GetInt64());
        Shop(store, machine).GetProperty("state").GetString().Should().Be("free");
    }

    [SkippableFact]
    public async Task PostgreSQL_stopped_for_10_s_mid_job_and_restarted_the_job_completes_and_its_history_is_complete()
    {
        // A cluster of this test's own: stopping the shared one would break the other test assemblies' PostgreSQL
        // tests that run at the same time (dotnet test runs the assemblies in parallel).
        using var server = PgServer.StartOwn();
        var store = server.Station;
        var settings = Settings(heartbeat: 1, expiry: 60);
        var machine = "mill-" + Guid.NewGuid().ToString("N")[..8];
        var src = Program(900); // 18 s in real time: the 10 s outage falls in the middle
        await using var rig = ServedSim.Start(SimSpeed.Factor(1));
        var a = Start("stream", src, "--tcp", rig.Spec, "--machine", machine, "--station", "A", "--store", store, "--settings", settings, "--stops", "continue", "--load-library");
        await rig.WaitForLineAsync(100, () => a.HasExited, async () => await a.Output + await a.Error);

        server.Stop();
        DateTimeOffset restarted;
        try
        {
            await Task.Delay(TimeSpan.FromSeconds(10));
            a.HasExited.Should().BeFalse("the station runs its job on while the store is down");
        }
        finally
        {
            server.Start();
            restarted = DateTimeOffset.UtcNow;
            NpgsqlConnection.ClearAllPools(); // this test process's own pooled connections died with the server
        }

        // The lease is renewed once the server is back, while the job still runs.
        var renewed = false;
        while (!a.HasExited && !renewed)
        {
            var lease = Shop(store, machine);
            renewed = lease.GetProperty("heartbeat").GetString() is { } beat && DateTimeOffset.Parse(beat, CultureInfo.InvariantCulture) > restarted;
            await Task.Delay(250);
        }

        await a.WaitForExitAsync().WaitAsync(TimeSpan.FromMinutes(2));
        var (stdout, stderr) = (await a.Output, await a.Error);
        a.ExitCode.Should().Be(0, stdout + stderr);
        renewed.Should().BeTrue("the heartbeat renewed the lease after the outage, before the job ended");
        stderr.Should().Contain("the job runs on and its records wait here", "the checkpoints written during the outage waited in the station");
        rig.Sim.StopClock();
        rig.Sim.RunUntilIdle(TimeSpan.FromMinutes(10));
        rig.ExecutedLines().Should().Equal(TrackedLines(src), "every block once, in order");

        var jobId = System.Text.RegularExpressions.Regex.Match(stdout, @"job (\d+):").Groups[1].Value;
        var history = Job(store, jobId, show: true);
        history.GetProperty("outcome").GetString().Should().Be("completed");
        history.GetProperty("blocksExecuted").GetInt64().Should().Be(901).And.Be(history.GetProperty("blocksTotal").GetInt64());
        history.GetProperty("checkpointState").GetString().Should().Be("Completed");
        history.GetProperty("lastLine").GetInt64().Should().Be(TrackedLines(src)[^1], "the last checkpoint is the job's last block");
        history.GetProperty("ended").GetString().Should().NotBeNullOrEmpty();
        Shop(store, machine).GetProperty("state").GetString().Should().Be("free");
    }

    [SkippableFact]
    public async Task A_password_in_the_store_uri_appears_nowhere_with_verbose_and_a_log_file()
    {
        var b = new NpgsqlConnectionStringBuilder(PgStore());
        Skip.If(string.IsNullOrEmpty(b.Password), "PMACSTREAM_TEST_PG has no password to hide");
        var uri = $"postgres://{b.Username}:{Uri.EscapeDataString(b.Password!)}@{b.Host}:{b.Port}/{b.Database}";
        var log = Path.Combine(_folder.Path, "verbose.log");
        await using var rig = ServedSim.Start(SimSpeed.Factor(50));
        var src = Program(200);
        var runs = new List<(int Code, string Out, string Err)>
        {
            await RunAsync("--verbose", "--log-file", log, "stream", src, "--tcp", rig.Spec, "--machine", "m-" + Guid.NewGuid().ToString("N")[..6], "--store", uri, "--stops", "continue", "--load-library"),
            await RunAsync("--verbose", "--log-file", log, "jobs", "--json", "--store", uri),
            await RunAsync("--verbose", "--log-file", log, "shop", "--store", uri),
            await RunAsync("--verbose", "--log-file", log, "store", "info", "--store", uri),
            await RunAsync("--verbose", "--log-file", log, "programs", "list", "--store", uri.Replace(b.Host!, "127.0.0.1", StringComparison.Ordinal).Replace($":{b.Port}/", ":1/", StringComparison.Ordinal)),
        };
        runs[0].Code.Should().Be(0, runs[0].Out + runs[0].Err);
        runs[^1].Code.Should().NotBe(0, "nothing listens on port 1: the error names the store");
        foreach (var (_, o, e) in runs)
        {
            (o + e).Should().NotContain(b.Password);
        }

        File.ReadAllText(log).Should().Contain("postgres://" + b.Username + "@").And.NotContain(b.Password);
    }

    private (string Station, string? Admin) Pg() => Requires.Postgres();

    private string PgStore()
    {
        var (station, admin) = Pg();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        return station;
    }

    private string Settings(double heartbeat, double expiry)
    {
        var path = Path.Combine(_folder.Path, "settings.json");
        File.WriteAllText(path, string.Create(CultureInfo.InvariantCulture, $"{{ \"leaseHeartbeatSeconds\": {heartbeat}, \"leaseExpirySeconds\": {expiry} }}"));
        return path;
    }

    /// <summary>A program of this run's own (the PostgreSQL store is shared): 2 mm moves at F6000, 20 ms each in real time.</summary>
    private string Program(int blocks) =>
        TestPrograms.Write(Path.Combine(_folder.NewFolder("p"), "part.nc"), TestPrograms.Text($"%\n({Guid.NewGuid():N})\n{TestPrograms.Metric}G01 F6000\n", blocks, TestPrograms.Grid(50, 2, decimals: true), TestPrograms.TapeEnd));

    private static List<int> TrackedLines(string src) =>
        ChunkedProgram.Open(Path.Combine(Splitter.DefaultOutDir(src), ChunkManifest.FileName)).TrackedLines().ToList();

    private JsonElement Shop(string store, string machine)
    {
        var (code, stdout, stderr) = RunAsync("shop", "--json", "--store", store).GetAwaiter().GetResult();
        code.Should().Be(0, stderr);
        using var doc = JsonDocument.Parse(stdout);
        return doc.RootElement.EnumerateArray().Single(m => m.GetProperty("machine").GetString() == machine).Clone();
    }

    private JsonElement Job(string store, string id, bool show = false)
    {
        var (code, stdout, stderr) = (show ? RunAsync("jobs", "show", id, "--json", "--store", store) : RunAsync("jobs", "--json", "--store", store)).GetAwaiter().GetResult();
        code.Should().Be(0, stderr);
        using var doc = JsonDocument.Parse(stdout);
        return (show ? doc.RootElement : doc.RootElement.EnumerateArray().Single(j => j.GetProperty("id").GetInt64().ToString(CultureInfo.InvariantCulture) == id)).Clone();
    }

    private CliRun Start(params string[] args)
    {
        var psi = CliProcess.Info(args);
        psi.Environment["HOME"] = _folder.Path; // the program cache lives there
        psi.Environment.Remove("PMACSTREAM_STORE");
        psi.Environment.Remove("PMACSTREAM_SETTINGS");
        return new CliRun(Process.Start(psi)!);
    }

    private async Task<(int Code, string Out, string Err)> RunAsync(params string[] args)
    {
        using var run = Start(args);
        await run.WaitForExitAsync().WaitAsync(TimeSpan.FromMinutes(2));
        return (run.ExitCode, await run.Output, await run.Error);
    }

    /// <summary>A command-line process whose output is read as it comes (a full pipe would stall it).</summary>
    private sealed class CliRun : IDisposable
    {
        private readonly Process _p;

        public CliRun(Process p)
        {
            _p = p;
            _p.StandardInput.Close();
            Output = _p.StandardOutput.ReadToEndAsync();
            Error = _p.StandardError.ReadToEndAsync();
        }

        public Task<string> Output { get; }

        public Task<string> Error { get; }

        public int Id => _p.Id;

        public bool HasExited => _p.HasExited;

        public int ExitCode => _p.ExitCode;

        public void Kill(bool tree) => _p.Kill(tree);

        public Task WaitForExitAsync() => _p.WaitForExitAsync();

        public void Dispose()
        {
            if (!_p.HasExited)
            {
                _p.Kill(true);
            }

            _p.Dispose();
        }
    }

    /// <summary>
    /// A throwaway cluster of one test's own (scripts/pg-throwaway.sh on a free port, migrated), stopped and started
    /// with pg_ctl as the postgres user when root, and removed at the end.
    /// </summary>
    private sealed class PgServer(string dataDir, string bin, string folder, string station) : IDisposable
    {
        public string Station => station;

        public static PgServer StartOwn()
        {
            var bin = Directory.Exists("/usr/lib/postgresql") ? Directory.GetDirectories("/usr/lib/postgresql").Select(d => Path.Combine(d, "bin")).Where(d => File.Exists(Path.Combine(d, "pg_ctl")))
                .OrderBy(d => int.TryParse(Path.GetFileName(Path.GetDirectoryName(d)), out var v) ? v : 0).LastOrDefault() : null;
            Skip.If(bin is null, "PostgreSQL is not installed (/usr/lib/postgresql/*/bin): no server to stop and start");
            // Under the temporary folder itself: the postgres user must be able to enter it (a test folder is the
            // runner's own, mode 700).
            var folder = Path.Combine(Path.GetTempPath(), "pmacstream-pg-restart-" + Guid.NewGuid().ToString("N")[..8]);
            var psi = new ProcessStartInfo("bash") { RedirectStandardOutput = true, RedirectStandardError = true, UseShellExecute = false };
            foreach (var a in new[] { Path.Combine(RepoRoot.Path, "scripts", "pg-throwaway.sh"), "start", folder })
            {
                psi.ArgumentList.Add(a);
            }

            psi.Environment["PORT"] = FreePort().ToString(CultureInfo.InvariantCulture);
            using var p = Process.Start(psi)!;
            var output = p.StandardOutput.ReadToEnd();
            var error = p.StandardError.ReadToEnd();
            p.WaitForExit(120_000).Should().BeTrue();
            p.ExitCode.Should().Be(0, $"pg-throwaway.sh start: {output}{error}");
            string Export(string name) => System.Text.RegularExpressions.Regex.Match(output, $"export {name}='([^']*)'").Groups[1].Value;
            using (PgSchema.OpenMigrated(StoreLocation.Parse(Export("PMACSTREAM_TEST_PG_ADMIN"))))
            {
            }

            return new PgServer(Export("PMACSTREAM_TEST_PG_DIR"), bin!, folder, Export("PMACSTREAM_TEST_PG"));
        }

        public void Dispose()
        {
            NpgsqlConnection.ClearAllPools();
            using var p = Process.Start("bash", [Path.Combine(RepoRoot.Path, "scripts", "pg-throwaway.sh"), "stop", folder]);
            p.WaitForExit(60_000);
        }

        private static int FreePort()
        {
            using var l = new System.Net.Sockets.TcpListener(IPAddress.Loopback, 0);
            l.Start();
            return ((IPEndPoint)l.LocalEndpoint).Port;
        }

        public void Stop() => PgCtl("-D", dataDir, "-m", "fast", "-w", "stop");

        public void Start() => PgCtl("-D", dataDir, "-l", Path.Combine(Path.GetDirectoryName(dataDir)!, "server.log"), "-w", "start");

        private void PgCtl(params string[] args)
        {
            var root = Environment.UserName == "root";
            var psi = new ProcessStartInfo(root ? "runuser" : Path.Combine(bin, "pg_ctl")) { RedirectStandardOutput = true, RedirectStandardError = true, UseShellExecute = false };
            if (root)
            {
                foreach (var a in new[] { "-u", "postgres", "--", Path.Combine(bin, "pg_ctl") })
                {
                    psi.ArgumentList.Add(a);
                }
            }

            foreach (var a in args)
            {
                psi.ArgumentList.Add(a);
            }

            using var p = Process.Start(psi)!;
            var output = p.StandardOutput.ReadToEnd() + p.StandardError.ReadToEnd();
            p.WaitForExit(60_000).Should().BeTrue();
            p.ExitCode.Should().Be(0, $"pg_ctl {string.Join(' ', args)}: {output}");
        }
    }
}
