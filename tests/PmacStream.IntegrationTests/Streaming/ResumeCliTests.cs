using System.Diagnostics;
using System.Globalization;
using System.Net;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Sim.Servers;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 20 item 1 as the operator met it: `stream --tcp` killed mid-job, its job record rewound (or advanced) while
/// the controller runs on, then `resume --yes`. Before, the rewound record was re-sent from chunk 2 (blocks run twice,
/// out of order) and resume exited 0; now the controller's word decides.
/// </summary>
[Collection("stream-cli")]
public sealed class ResumeCliTests : IDisposable
{
    private readonly TestFolder _temp = new("resumecli");
    private readonly string _folder;

    public ResumeCliTests() => _folder = _temp.Path;

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _temp.Dispose();

    /// <summary>1500 moves of 2 mm at F3000 (40 ms each: 3 s at the simulator's 20x), 250 lines a chunk.</summary>
    private string Program() => TestPrograms.Write(Path.Combine(_folder, "part.nc"), TestPrograms.Text(TestPrograms.Metric + "G01 F3000\n", 1500, TestPrograms.Grid(50, 2, decimals: true)));

    /// <summary>Streams to the simulator over TCP and kills the host (SIGKILL: no last checkpoint) once M0 reaches <paramref name="line"/>.</summary>
    private static async Task<long> KillStreamAtAsync(PmacSimulator sim, int port, string src, string store, int line)
    {
        // The chunk strategy, the default when these positions were worked out: the full strategy (now the default)
        // has sent the whole job long before M0 reaches the line, so no checkpoint could be ahead of the controller.
        using var p = Process.Start(CliProcess.Info("stream", src, "--tcp", $"127.0.0.1:{port}", "--strategy", "chunk", "--lines", "250", "--store", store))!;
        p.StandardInput.Close();
        var sw = Stopwatch.StartNew();
        while (sim.ReadVariable('M', 0) < line && sw.Elapsed < TimeSpan.FromSeconds(60) && !p.HasExited)
        {
            await Task.Delay(10);
        }

        p.HasExited.Should().BeFalse("the job was still streaming");
        p.Kill();
        await p.WaitForExitAsync();

        // The killed job: the newest on this connection (a shared PostgreSQL store holds other runs' jobs too).
        using var jobs = JobStores.Open(Preparation.Store.StoreLocation.Parse(store));
        return jobs.List().First(j => j.Connection.EndsWith($"127.0.0.1:{port}", StringComparison.Ordinal)).Id;
    }

    /// <summary>Rewrites a job's checkpoint as a damaged or restored job store would hold it.</summary>
    private static void EditCheckpoint(string store, long id, Func<Checkpoint, Checkpoint> edit)
    {
        using var jobs = JobStores.Open(Preparation.Store.StoreLocation.Parse(store));
        var cp = jobs.Get(id)!.Checkpoint!;
        jobs.SaveCheckpoint(id, edit(cp), durable: true, executed: null);
    }

    /// <summary>This test's SQLite file, or the PostgreSQL server (migrated by its owner; SKIPPED without one).</summary>
    private string Store(string engine)
    {
        if (engine == "sqlite")
        {
            return "sqlite:" + Path.Combine(_folder, "jobs.db");
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

    private static async Task<(PmacSimulator Sim, PmacTcpServer Server)> ControllerAsync()
    {
        var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Factor(20) });
        await new PmacStream.Pmac.InProcessConnection(sim.OpenPort("setup")).DownloadAsync(SimRig.Library);
        var ethernet = sim.OpenPort("ethernet");
        var server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        sim.StartClock();
        return (sim, server);
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task Resume_yes_of_a_checkpoint_rewound_to_chunk_1_runs_every_block_once_in_order(string engine)
    {
        var store = Store(engine);
        var src = Program();
        var (sim, server) = await ControllerAsync();
        using var disposeSim = sim;
        await using var disposeServer = server;
        using var stopClock = new StopClockOnDispose(sim);

        var id = await KillStreamAtAsync(sim, server.Port, src, store, line: 800);
        EditCheckpoint(store, id, cp => cp with { LastExecutedLine = 0, CurrentChunk = 1, Next = new StreamPosition(2, 0), NextExact = true, ChunksDownloaded = 1 });

        var (code, stdout, stderr) = await CliRun.InProcessAsync(["resume", "--job", id.ToString(CultureInfo.InvariantCulture), "--store", store, "--yes"]);

        code.Should().Be(0, stderr + stdout);
        stdout.Should().Contain("executed 1501 of 1501 blocks");
        sim.StopClock();
        sim.RunUntilIdle(TimeSpan.FromMinutes(10));
        var expected = ChunkedProgram.Open(Path.Combine(Splitter.DefaultOutDir(src), ChunkManifest.FileName)).TrackedLines().ToList();
        MoveLines.Blocks(sim.ExecutedMoves).Should().Equal(expected, "every block once, in order, whatever the record said");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task Resume_yes_of_a_checkpoint_advanced_past_the_controller_exits_1_with_both_positions_and_sends_nothing(string engine)
    {
        var store = Store(engine);
        var src = Program();
        var (sim, server) = await ControllerAsync();
        using var disposeSim = sim;
        await using var disposeServer = server;
        using var stopClock = new StopClockOnDispose(sim);

        var id = await KillStreamAtAsync(sim, server.Port, src, store, line: 500);
        EditCheckpoint(store, id, cp => cp with { LastExecutedLine = 1400, CurrentChunk = 6, Next = new StreamPosition(7, 0), NextExact = true });
        var received = sim.Counters.LinesReceived;

        var (code, stdout, stderr) = await CliRun.InProcessAsync(["resume", "--job", id.ToString(CultureInfo.InvariantCulture), "--store", store, "--yes"]);

        code.Should().Be(1, stdout);
        stderr.Should().MatchRegex($@"pmacstream resume: cannot resume job {id}: the controller (executes|stopped at) line \d+, before line 1400 that the record says had already executed\. The controller: M0=\d+")
            .And.Contain("The job record: line 1400 executed, sending had reached chunk 7 line 0.")
            .And.Contain("so nothing was sent")
            .And.Contain($"to start again from a line: pmacstream stream {src} --from-line");
        stdout.Should().NotContain("restarting at the block of line", "no restart is proposed on a record the controller contradicts");
        sim.Counters.LinesReceived.Should().Be(received, "nothing reached a buffer");
    }
}
