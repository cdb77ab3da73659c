using System.Diagnostics;
using System.Globalization;
using System.Net;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Sim.Servers;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

[CollectionDefinition("stream-cli", DisableParallelization = true)]
public sealed class StreamCliCollection
{
}

[Collection("stream-cli")]
public sealed class StreamCliTests : IDisposable
{
    private readonly TestFolder _temp = new("cli");

    public void Dispose() => _temp.Dispose();

    private string Program(int blocks, double feed = 3000) =>
        TestPrograms.Write(Path.Combine(_temp.Path, "part.nc"), TestPrograms.Text(string.Create(CultureInfo.InvariantCulture, $"%\nO2000\n{TestPrograms.Metric}G01 F{feed}\n"), blocks, TestPrograms.Grid(50, 2, decimals: true), TestPrograms.TapeEnd));

    [Theory]
    [InlineData("chunk")]
    [InlineData("pr")]
    [InlineData("adaptive")]
    public void Stream_to_the_simulator_ends_with_the_count_and_underruns(string strategy)
    {
        var src = Program(900);
        var db = Path.Combine(_temp.Path, "jobs.db");
        var (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--strategy", strategy, "--lines", "200", "--sim-speed", "100x", "--job-db", db);
        code.Should().Be(0, stderr + stdout);
        stdout.Should().MatchRegex(@"executed 901 of 901 blocks, \d+ underruns");
        using var jobs = JobStore.Open(db);
        jobs.List().Should().ContainSingle().Which.Checkpoint!.State.Should().Be(SessionState.Completed);
    }

    [Fact]
    public void Stream_from_a_line_shows_the_preamble_and_needs_yes()
    {
        var src = Program(300);
        var db = Path.Combine(_temp.Path, "jobs.db");
        var refused = CliRun.InProcess("stream", src, "--sim", "--from-line", "150", "--job-db", db);
        refused.Code.Should().Be(2);
        refused.Out.Should().Contain("start at line 150").And.Contain("G90 G00 Z10");
        refused.Err.Should().Contain("--yes");

        var (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--from-line", "150", "--yes", "--sim-speed", "100x", "--job-db", db);
        code.Should().Be(0, stderr + stdout);
        // Blocks from line 150 to the last motion block (line 304: the final G01 is line 305? count from the split).
        stdout.Should().MatchRegex(@"executed (\d+) of \1 blocks");
    }

    [Fact]
    public void Bad_usage_and_missing_files_exit_2()
    {
        CliRun.InProcess("stream", Path.Combine(_temp.Path, "none.nc"), "--sim").Code.Should().Be(2);
        CliRun.InProcess("stream", Program(10)).Code.Should().Be(2);
        CliRun.InProcess("stream", Program(10), "--sim", "--strategy", "fast").Code.Should().Be(2);
        CliRun.InProcess("resume", "--job-db", Path.Combine(_temp.Path, "empty.db")).Code.Should().Be(2);
    }

    [SkippableTheory]
    [InlineData("sqlite")]
    [InlineData("postgres")]
    public async Task Host_killed_mid_job_then_resume_over_tcp_loses_and_repeats_nothing(string engine)
    {
        var src = Program(1500, feed: 6000);
        var store = Store(engine);
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Factor(20) });
        var lib = new InProcessConnection(sim.OpenPort("setup"));
        await lib.DownloadAsync(SimRig.Library);
        await lib.GetResponseAsync("P500=6000");
        // A Turbo PMAC has one Ethernet port whatever the number of TCP connections: a buffer the killed host left
        // open is still open on it, and the resuming host's CLOSE closes it.
        var ethernet = sim.OpenPort("ethernet");
        await using var server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        sim.StartClock();
        using var stopClock = new StopClockOnDispose(sim);
        var spec = $"127.0.0.1:{server.Port}";

        // First host: killed once execution is well into the job (past the first chunk boundary).
        using (var first = Process.Start(CliProcess.Info("stream", src, "--tcp", spec, "--load-library", "--lines", "250", "--store", store))!)
        {
            var sw = Stopwatch.StartNew();
            while (sim.ReadVariable('M', 0) < 400 && sw.Elapsed < TimeSpan.FromSeconds(60))
            {
                await Task.Delay(20);
            }

            first.Kill(true);
            await first.WaitForExitAsync();
        }

        var killedAt = (int)sim.ReadVariable('M', 0);
        killedAt.Should().BeGreaterThan(300, "the job ran before the kill");

        // The killed job on this connection (a shared PostgreSQL store holds other runs' jobs too).
        using var jobs = System.Text.Json.JsonDocument.Parse((await CliRun.InProcessAsync(["jobs", "--json", "--store", store])).Out);
        var killed = jobs.RootElement.EnumerateArray().First(j => j.GetProperty("connection").GetString()!.EndsWith(spec, StringComparison.Ordinal)).GetProperty("id").GetInt64();
        var (code, stdout, stderr) = await CliRun.InProcessAsync(["resume", "--job", killed.ToString(CultureInfo.InvariantCulture), "--store", store, "--yes"]);
        code.Should().Be(0, stderr + stdout);
        stdout.Should().Contain("controller still holds the job");
        sim.StopClock();
        sim.RunUntilIdle(TimeSpan.FromMinutes(10));

        var executed = new List<int>();
        foreach (var m in sim.ExecutedMoves)
        {
            if (m.SourceLine > 0 && (executed.Count == 0 || executed[^1] != m.SourceLine))
            {
                executed.Add(m.SourceLine);
            }
        }

        var manifest = ChunkManifest.Load(Path.Combine(Splitter.DefaultOutDir(src), ChunkManifest.FileName));
        var expected = ChunkedProgram.Open(Path.Combine(Splitter.DefaultOutDir(src), ChunkManifest.FileName)).TrackedLines().ToList();
        expected.Should().HaveCount(manifest.TotalMotionBlocks);
        executed.Should().Equal(expected, "no block lost, repeated or reordered across the host kill");
    }

    /// <summary>The store of a test on <paramref name="engine"/>: this test's SQLite file, or the PostgreSQL server (migrated by its owner).</summary>
    private string Store(string engine)
    {
        if (engine == "sqlite")
        {
            return "sqlite:" + Path.Combine(_temp.Path, "jobs.db");
        }

        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (Preparation.Store.PgSchema.OpenMigrated(Preparation.Store.StoreLocation.Parse(admin)))
            {
            }
        }

        return station;
    }

    [Fact]
    public void Resume_refuses_when_the_program_changed()
    {
        var src = Program(200);
        var db = Path.Combine(_temp.Path, "jobs.db");
        using (var jobs = JobStore.Open(db))
        {
            var split = Splitter.Split(src, new SplitOptions { OutDir = Splitter.DefaultOutDir(src) });
            var id = jobs.CreateJob(src, split.Manifest.SourceSha256, split.ManifestPath, StrategyKind.Chunk, "sim", null);
            jobs.SaveCheckpoint(id, new Checkpoint(50, 1, new StreamPosition(1, 120), true, 1, SessionState.Running, DateTimeOffset.UtcNow), durable: true);
        }

        File.AppendAllText(src, "G01 X1 Y1\n");
        var (code, _, stderr) = CliRun.InProcess("resume", "--job-db", db, "--yes");
        code.Should().Be(1);
        stderr.Should().Contain("changed since the job started");
    }

    [Fact]
    public void Resume_on_a_fresh_simulator_restarts_at_the_checkpoint_line_with_a_preamble()
    {
        var src = Program(400);
        var db = Path.Combine(_temp.Path, "jobs.db");
        long id;
        using (var jobs = JobStore.Open(db))
        {
            var split = Splitter.Split(src, new SplitOptions { OutDir = Splitter.DefaultOutDir(src), BlocksPerChunk = 100 });
            id = jobs.CreateJob(src, split.Manifest.SourceSha256, split.ManifestPath, StrategyKind.Chunk, "sim", null);
            jobs.SaveCheckpoint(id, new Checkpoint(250, 3, new StreamPosition(4, 0), true, 3, SessionState.Running, DateTimeOffset.UtcNow), durable: true);
        }

        var (code, stdout, stderr) = CliRun.InProcess("resume", "--job-db", db, "--yes", "--sim-speed", "100x");
        code.Should().Be(0, stderr + stdout);
        stdout.Should().Contain("restarting at the block of line 250").And.Contain("G90 G00 Z10");
        // Lines 250..405 are the motion blocks from the restart (the last G01 is source line 405).
        stdout.Should().MatchRegex(@"executed (\d+) of \1 blocks");
        using var after = JobStore.Open(db);
        after.Get(id)!.Checkpoint!.State.Should().Be(SessionState.Completed);
    }
}

/// <summary>Stops the simulator's clock thread even when an assertion fails, before the simulator is disposed.</summary>
internal sealed class StopClockOnDispose(PmacSimulator sim) : IDisposable
{
    public void Dispose() => sim.StopClock();
}
