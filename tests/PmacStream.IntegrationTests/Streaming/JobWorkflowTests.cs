using System.Globalization;
using System.Net;
using System.Text;
using System.Text.RegularExpressions;
using PmacStream.Core.Tests.Hmi;
using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Sim.Servers;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 15: the command line and the HMI run one job workflow (the job service), so the drifts between their copies
/// are gone: the split cache honours the split options, one check gate, one buffer size, window and preamble.
/// </summary>
[Collection("stream-cli")]
public sealed class JobWorkflowTests : IDisposable
{
    private readonly TestFolder _temp = new("jobs");
    private readonly string _folder;

    public JobWorkflowTests() => _folder = _temp.Path;

    private string Db => Path.Combine(_folder, "jobs.db");

    public void Dispose() => _temp.Dispose();

    private string Program(int blocks, string? insert = null) =>
        TestPrograms.Write(Path.Combine(_folder, "part.nc"), TestPrograms.Text("%\nO2000\n" + TestPrograms.Metric + "G01 F3000\n", blocks, TestPrograms.Grid(50, 2, decimals: true), TestPrograms.TapeEnd, i => i == blocks / 2 ? insert : null));

    [Fact]
    public void Stream_with_500_lines_after_a_1000_line_split_streams_chunks_of_at_most_500_blocks()
    {
        var src = Program(2400);
        CliRun.InProcess("split", src).Code.Should().Be(0);
        var manifestPath = Path.Combine(Splitter.DefaultOutDir(src), ChunkManifest.FileName);
        ChunkManifest.Load(manifestPath).Chunks.Should().Contain(c => c.BlockCount > 500, "the earlier split has 1000-line chunks");

        var (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--lines", "500", "--sim-speed", "instant", "--job-db", Db);

        code.Should().Be(0, stderr + stdout);
        var manifest = ChunkManifest.Load(manifestPath);
        manifest.BlocksPerChunk.Should().Be(500);
        manifest.Chunks.Should().OnlyContain(c => c.BlockCount <= 500).And.HaveCountGreaterThanOrEqualTo(5);
        stdout.Should().Contain($"{manifest.Chunks.Count} chunks").And.MatchRegex(@"executed 2401 of 2401 blocks");
        using var jobs = JobStore.Open(Db);
        jobs.List().Single().ManifestPath.Should().Be(manifestPath, "the job ran the new split");
    }

    [Fact]
    public async Task Stream_of_a_program_with_profile_errors_exits_1_lists_every_error_and_sends_nothing()
    {
        // Two codes of one modal group, an unknown G code, a feed move before any feed, an axis word the profile lacks:
        // only the machine profile's check finds these; the lexer alone would let them through to the controller.
        var src = Path.Combine(_folder, "bad.nc");
        File.WriteAllText(src, "G21 G17 G90\nG00 X0 Y0\nG01 X5 Y5\nG01 F800 X6\nG00 G01 X10\nG77 X20\nG01 X30 U4\nM30\n");
        var errors = new List<Diagnostic>();
        new Checker(MachineProfile.Default).CheckFile(src, d =>
        {
            if (d.Severity == Severity.Error)
            {
                errors.Add(d);
            }
        });
        errors.Select(d => d.Code).Should().HaveCountGreaterThanOrEqualTo(4);

        using var sim = new PmacSimulator(new SimOptions { RecordRotaryLines = true });
        var ethernet = sim.OpenPort("ethernet");
        var connections = 0;
        await using var server = new PmacTcpServer(() =>
        {
            Interlocked.Increment(ref connections);
            return ethernet;
        }, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();

        var (code, stdout, stderr) = await CliRun.InProcessAsync(["stream", src, "--tcp", $"127.0.0.1:{server.Port}", "--job-db", Db]);

        code.Should().Be(1, stdout + stderr);
        var lines = stderr.Split('\n').Select(l => l.TrimEnd('\r')).Where(l => l.Length > 0).ToList();
        lines.Take(errors.Count).Should().Equal(errors.Select(d => d.Format(src)), "every error, as FILE:LINE:COL: error CODE: message, in line order");
        lines.Should().Contain(l => l.Contains($"{errors.Count} error(s) under profile 'fanuc-mill'; nothing sent", StringComparison.Ordinal));
        connections.Should().Be(0, "the check refused before the controller was even opened");
        sim.ExecutedMoves.Should().BeEmpty();
        sim.ExecutedRotaryLines.Should().BeEmpty();
        Directory.Exists(Splitter.DefaultOutDir(src)).Should().BeFalse("nothing was split");
        // The store keeps the program's revision with its diagnostics (stream imports first), but no job.
        using (var store = JobStore.Open(Db))
        {
            store.List().Should().BeEmpty("no job was recorded");
        }
    }

    [Fact]
    public void Stream_force_runs_a_program_the_check_refuses()
    {
        var src = Program(200, "G77 X3");
        var (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--force", "--sim-speed", "instant", "--job-db", Db);
        code.Should().Be(0, stdout + stderr);
        stdout.Should().MatchRegex(@"executed (\d+) of \1 blocks");
    }

    [Fact]
    public void The_window_is_set_from_the_command_line_and_kept_with_the_job()
    {
        var (code, stdout, stderr) = CliRun.InProcess("demo", "--sim-speed", "200x", "--window", "30-40%");
        code.Should().Be(0, stderr + stdout);
        var percents = Regex.Matches(stdout, @"chunk \d downloaded at M0=\d+, (\d+) % of chunk").Select(m => int.Parse(m.Groups[1].Value, CultureInfo.InvariantCulture)).ToList();
        percents.Should().HaveCount(3).And.OnlyContain(p => p >= 30 && p < 40, "the next chunk is downloaded inside the window 0.3-0.4");

        var src = Program(300);
        CliRun.InProcess("stream", src, "--sim", "--window", "0.5-0.8", "--buffer-words", "20000", "--sim-speed", "instant", "--job-db", Db).Code.Should().Be(0);
        using var jobs = JobStore.Open(Db);
        var settings = RunSettingsFile.Read(RunSettings.Default, Encoding.UTF8.GetBytes(jobs.List().Single().Settings!), "record");
        settings.Should().Be(RunSettings.Default with { WindowStart = 0.5, WindowEnd = 0.8, BufferWords = 20_000 });
    }

    [Fact]
    public async Task Stream_sets_the_feed_override_before_the_start_whatever_the_controller_held()
    {
        var src = Program(300);
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Factor(20) });
        var setup = new InProcessConnection(sim.OpenPort("setup"));
        await setup.DownloadAsync(SimRig.Library);
        await setup.GetResponseAsync("&1 %30"); // left by an earlier session
        var ethernet = sim.OpenPort("ethernet");
        await using var server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        sim.StartClock();
        var spec = $"127.0.0.1:{server.Port}";

        var (code, stdout, stderr) = await CliRun.InProcessAsync(["stream", src, "--tcp", spec, "--load-library", "--feed-override", "70", "--job-db", Db]);
        code.Should().Be(0, stderr + stdout);
        sim.StopClock();
        sim.RunUntilIdle(TimeSpan.FromMinutes(5));
        (await setup.GetResponseAsync("&1 %")).Should().StartWith("70");
        var from = sim.ExecutedMoves[0].StartTime + 2; // the override slews from where it was in the first second
        var moves = sim.ExecutedMoves.Where(m => m.Kind == MoveKind.Linear && m.StartTime >= from && m.Length > 0.5).ToList();
        moves.Should().HaveCountGreaterThan(100).And.OnlyContain(m => m.Feed == 3000, "the program's F3000, carried in P500");
        moves.Should().OnlyContain(m => Math.Abs((m.Length / m.Duration * 60) - 2100) < 21, "programmed x 70 %");

        // Without the option the start sets 100 %: an override left by an earlier session never carries over.
        await setup.GetResponseAsync("&1 A"); // the rotary program of the job above still waits for lines
        await setup.GetResponseAsync("&1 %30");
        sim.StartClock();
        var again = await CliRun.InProcessAsync(["stream", src, "--tcp", spec, "--load-library", "--job-db", Db]);
        again.Code.Should().Be(0, again.Err + again.Out);
        sim.StopClock();
        sim.RunUntilIdle(TimeSpan.FromMinutes(5));
        (await setup.GetResponseAsync("&1 %")).Should().StartWith("100");
        var refused = await CliRun.InProcessAsync(["stream", src, "--sim", "--feed-override", "250", "--job-db", Db]);
        refused.Code.Should().Be(2);
        refused.Err.Should().Contain("--feed-override: feed override 250 % is outside 0-200 %");
    }

    [Fact]
    public void A_bad_settings_file_is_reported_with_its_position_and_exit_2()
    {
        var settings = Path.Combine(_folder, "settings.json");
        File.WriteAllText(settings, "{\n  \"blocksPerChunk\": 500,\n  \"window\": \"0.6-0.7\"\n}\n");
        var (code, _, stderr) = CliRun.InProcess("stream", Program(10), "--sim", "--settings", settings, "--job-db", Db);
        code.Should().Be(2);
        stderr.Should().StartWith($"{settings}:3:3: error R002: unknown setting 'window'");
    }

    [Theory]
    [InlineData(false)]
    [InlineData(true)]
    public async Task Cli_and_hmi_start_the_same_job_with_the_same_buffer_window_and_preamble(bool settingsFile)
    {
        var src = Path.Combine(_folder, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, src);
        var file = Path.Combine(_folder, "settings.json");
        File.WriteAllText(file, """{ "bufferWords": 24000, "windowStart": 0.55, "windowEnd": 0.65, "safeZMode": "highest" }""");
        var args = new List<string> { "stream", src, "--sim", "--from-line", "1500", "--yes", "--sim-speed", "instant", "--job-db", Db };
        if (settingsFile)
        {
            args.AddRange(["--settings", file]);
        }

        // The command line: a whole job from line 1500.
        var (code, stdout, stderr) = await CliRun.InProcessAsync([.. args]);
        code.Should().Be(0, stderr + stdout);

        // The HMI: the presenter over the same job service, started from the same line on its own simulator.
        using var sim = new PmacSimulator();
        var service = new JobService(new JobServiceOptions
        {
            JobDatabase = Db,
            Simulator = _ => Task.FromResult(new SimulatorLink(new InProcessConnection(sim.OpenPort("hmi"), "simulator (in-process)"), new SimTimeProvider(sim))),
        });
        var view = new FakeView { SelectedLine = 1500 };
        await using (var presenter = new MainPresenter(view, new CoreHmiBackend(service), settings: settingsFile ? RunSettingsFile.Load(file) : RunSettings.Default))
        {
            foreach (var click in new Action[] { () => view.ChooseFile(src), view.ClickConnect, view.ClickSplit, view.ClickStartFromLine })
            {
                click();
                await presenter.WhenIdleAsync();
            }

            view.Errors.Should().BeEmpty();
            presenter.JobActive.Should().BeTrue();
            await presenter.TickAsync();
        }

        using var jobs = JobStore.Open(Db);
        var records = jobs.List();
        records.Should().HaveCount(2);
        var (hmi, cli) = (records[0], records[1]);
        hmi.Settings.Should().NotBeNull().And.Be(cli.Settings, "one buffer size, window, tick and safe Z");
        var expected = settingsFile ? RunSettingsFile.Load(file) : RunSettings.Default;
        RunSettingsFile.Read(RunSettings.Default, Encoding.UTF8.GetBytes(hmi.Settings!), "record").Should().Be(expected);
        hmi.FromLine.Should().Be(cli.FromLine).And.NotBeNull();
        hmi.Preamble.Should().NotBeNullOrEmpty().And.Equal(cli.Preamble, "the same preamble reached both controllers");
        hmi.ManifestPath.Should().Be(cli.ManifestPath, "the HMI reused the command line's split of the same program and options");
        var shown = stdout.Split('\n').Select(l => l.TrimEnd('\r')).SkipWhile(l => !l.Contains("preamble:", StringComparison.Ordinal)).Skip(1)
            .TakeWhile(l => l.StartsWith("  ", StringComparison.Ordinal)).Select(l => l.Trim()).ToList();
        view.Confirmations.Should().ContainSingle().Which.Text.Should().Contain(string.Join(Environment.NewLine, shown), "the operator saw what the command line printed");
    }

    [Fact]
    public async Task A_session_on_a_bare_connection_downloads_through_the_device_facade()
    {
        // Moves only: the chunk file itself goes to Download (no annotated copy), so its PComm log lands beside it.
        var src = Path.Combine(_folder, "moves.nc");
        File.WriteAllText(src, string.Concat(Enumerable.Range(1, 40).Select(i => $"G01 X{i} Y{i % 3} F900\n")));
        var split = Splitter.Split(src, new SplitOptions { BlocksPerChunk = 20 });
        using var sim = new PmacSimulator();
        await using var connection = new InProcessConnection(sim.OpenPort("test"), "sim");
        await connection.DownloadAsync(SimRig.Library);
        var session = new StreamingSession(connection, ChunkedProgram.Open(split.ManifestPath), new StreamingOptions { LineProbeVariable = null, DefineBuffer = true });

        await session.StartAsync();

        var log = Path.ChangeExtension(split.ChunkPaths.First(), ".log");
        File.Exists(log).Should().BeTrue("Download(..., log: true) writes the PComm log, on every face");
        File.ReadAllText(log).Should().Contain("; result: OK");
    }
}
