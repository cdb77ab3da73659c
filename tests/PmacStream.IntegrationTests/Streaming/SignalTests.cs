using System.Diagnostics;
using System.Globalization;
using System.Net;
using System.Text;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Sim.Servers;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Ctrl-C (SIGINT) and SIGTERM stop split, check and stream cleanly; SIGKILL cannot be handled, so the next split
/// removes what a killed one left.
/// </summary>
[Collection("stream-cli")]
public sealed class SignalTests : IDisposable
{
    private const int SigInt = PosixSignals.SigInt;
    private const int SigKill = PosixSignals.SigKill;
    private const int SigTerm = PosixSignals.SigTerm;
    private readonly TestFolder _temp = new("signal");
    private readonly string _folder;

    public SignalTests() => _folder = _temp.Path;

    public void Dispose() => _temp.Dispose();

    /// <summary>A program long enough that a split or check is still running when the signal comes.</summary>
    private string BigProgram(int lines = 1_500_000)
    {
        var path = Path.Combine(_folder, "big.nc");
        using var w = new StreamWriter(path, false, new UTF8Encoding(false), 1 << 16);
        w.Write("G21 G17 G90\nG00 X0 Y0\nG01 F3000\n");
        for (var i = 0; i < lines; i++)
        {
            w.Write(string.Create(CultureInfo.InvariantCulture, $"G01 X{i % 500}.5 Y{i / 500}.25\n"));
        }

        w.Write("M30\n");
        return path;
    }

    /// <summary>Starts pmacstream, waits for its first progress report, sends the signal, returns what it said on stderr.</summary>
    private static async Task<(int Code, string Err)> SignalDuringAsync(int signal, string waitFor, params string[] args)
    {
        using var p = Process.Start(CliProcess.Info(args))!;
        p.StandardInput.Close();
        var stderr = p.StandardError.ReadToEndAsync();
        var output = new StringBuilder();
        var sent = false;
        string? line;
        while ((line = await p.StandardOutput.ReadLineAsync()) is not null)
        {
            output.AppendLine(line);
            if (!sent && line.Contains(waitFor, StringComparison.Ordinal))
            {
                PosixSignals.Send(p.Id, signal).Should().Be(0);
                sent = true;
            }
        }

        await p.WaitForExitAsync();
        var err = await stderr;
        sent.Should().BeTrue($"the command should have reported '{waitFor}' before ending: {output}{err}");
        return (p.ExitCode, err);
    }

    private string[] WorkFolders() =>
        [.. Directory.EnumerateFileSystemEntries(_folder, ".big_chunks.tmp-*").Select(Path.GetFileName)!];

    [SkippableTheory]
    [InlineData(SigInt)]
    [InlineData(SigTerm)]
    public async Task A_signal_during_split_removes_the_partial_split_and_says_so(int signal)
    {
        Requires.NotWindows("POSIX signals");
        var src = BigProgram();

        var (code, err) = await SignalDuringAsync(signal, "split ", "split", src);

        code.Should().Be(1, err);
        err.Should().Contain($"pmacstream split: interrupted; the partial split was removed, {src} was not split");
        WorkFolders().Should().BeEmpty("an interrupted split leaves no hidden work folder");
        Directory.Exists(Splitter.DefaultOutDir(src)).Should().BeFalse();
    }

    [SkippableFact]
    public async Task The_next_split_removes_what_a_killed_split_left()
    {
        Requires.NotWindows("POSIX signals");
        var src = BigProgram();

        var (code, _) = await SignalDuringAsync(SigKill, "split ", "split", src);
        code.Should().Be(137);
        WorkFolders().Should().NotBeEmpty("SIGKILL cannot be handled: the work folder stays");

        var (again, stdout, stderr) = await CliRun.InProcessAsync(["split", src]);
        again.Should().Be(0, stderr);
        stdout.Should().Contain("written to");
        WorkFolders().Should().BeEmpty("the next split removed the killed one's folder and lock");
    }

    [SkippableTheory]
    [InlineData(SigInt)]
    [InlineData(SigTerm)]
    public async Task A_signal_during_check_stops_it_without_a_stack_trace(int signal)
    {
        Requires.NotWindows("POSIX signals");
        var src = BigProgram(4_000_000);
        var db = Path.Combine(_folder, "program.db");

        var start = Process.Start(CliProcess.Info("check", src, "--db", db))!;
        start.StandardInput.Close();
        var stderr = start.StandardError.ReadToEndAsync();
        var stdout = start.StandardOutput.ReadToEndAsync();
        await Task.Delay(1500);
        start.HasExited.Should().BeFalse("the check of 4M lines into a store takes longer than that");
        PosixSignals.Send(start.Id, signal).Should().Be(0);
        await start.WaitForExitAsync();

        start.ExitCode.Should().Be(1);
        (await stderr).Should().Be("pmacstream check: interrupted" + Environment.NewLine);
        await stdout;
        File.Exists(db).Should().BeFalse("a new store is built under a temporary name and only renamed when complete");
        Directory.EnumerateFiles(_folder).Select(Path.GetFileName).Should().BeEquivalentTo(["big.nc"]);
    }

    [SkippableFact]
    public async Task Sigterm_during_stream_stops_sending_leaves_the_job_resumable_and_resume_finishes_it_exactly()
    {
        Requires.NotWindows("POSIX signals");
        var src = Path.Combine(_folder, "part.nc");
        TestPrograms.Write(src, TestPrograms.Text(TestPrograms.Metric + "G01 F6000\n", 1500, TestPrograms.Grid(50, 2, decimals: true)));
        var db = Path.Combine(_folder, "jobs.db");
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Factor(20) });
        await new PmacStream.Pmac.InProcessConnection(sim.OpenPort("setup")).DownloadAsync(SimRig.Library);
        var ethernet = sim.OpenPort("ethernet");
        await using var server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        sim.StartClock();
        using var stopClock = new StopClockOnDispose(sim);

        using (var p = Process.Start(CliProcess.Info("stream", src, "--tcp", $"127.0.0.1:{server.Port}", "--load-library", "--lines", "250", "--job-db", db))!)
        {
            p.StandardInput.Close();
            var stderr = p.StandardError.ReadToEndAsync();
            var sw = Stopwatch.StartNew();
            while (sim.ReadVariable('M', 0) < 400 && sw.Elapsed < TimeSpan.FromSeconds(60))
            {
                await Task.Delay(20);
            }

            PosixSignals.Send(p.Id, SigTerm).Should().Be(0);
            await p.WaitForExitAsync();
            p.ExitCode.Should().Be(1);
            (await stderr).Should().MatchRegex(@"interrupted at line \d+: sending stopped; the controller keeps the lines it holds\. The job is resumable: pmacstream resume --job 1");
        }

        using (var store = JobStore.Open(db))
        {
            store.Get(1)!.Unfinished.Should().BeTrue();
        }

        var (code, stdout, err) = await CliRun.InProcessAsync(["resume", "--job-db", db, "--yes"]);
        code.Should().Be(0, err + stdout);
        sim.StopClock();
        sim.RunUntilIdle(TimeSpan.FromMinutes(10));
        var expected = ChunkedProgram.Open(Path.Combine(Splitter.DefaultOutDir(src), ChunkManifest.FileName)).TrackedLines().ToList();
        MoveLines.Blocks(sim.ExecutedMoves).Should().Equal(expected, "every block once, in order, across the SIGTERM");
    }
}
