using System.Diagnostics;
using System.Text;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Program stops as the `pmacstream` process shows them: `program stop (M00) at line N`, Enter continues, `--stops
/// continue` goes on by itself, a program with stops is refused without a terminal unless told, Ctrl-C at a stop leaves
/// the job resumable.
/// </summary>
[Collection("stream-cli")]
public sealed class StopCliTests : IDisposable
{
    private readonly TestFolder _temp = new("stop-cli");

    private string _folder => _temp.Path;

    public void Dispose() => _temp.Dispose();

    /// <summary>M00 at line 24, M01 at line 45; 60 moves.</summary>
    private string Program(bool withM00 = true) => TestPrograms.Write(Path.Combine(_folder, "stops.nc"), TestPrograms.Text("G21 G90 G17\nG00 X0 Y0\nG01 F3000\n", 60, TestPrograms.Grid(10), after: i => i switch
    {
        20 => withM00 ? "M00" : "M08",
        40 => "M01",
        _ => null,
    }));

    [Fact]
    public void Without_a_terminal_a_program_with_stops_is_refused_unless_stops_continue_and_then_each_stop_is_printed()
    {
        var src = Program();
        var db = Path.Combine(_folder, "jobs.db");
        var (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--job-db", db, "--sim-speed", "instant");
        code.Should().Be(2, stdout + stderr);
        stderr.Should().Contain("the program stops at M00 (line 24), M01 (line 45) and input is not a terminal").And.Contain("--stops continue");
        stdout.Should().NotContain("job ", "refused before a job was made");

        (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--job-db", db, "--sim-speed", "instant", "--stops", "continue");
        code.Should().Be(0, stdout + stderr);
        stdout.Should().Contain("program stop (M00) at line 24; continuing (--stops continue)")
            .And.Contain("program stop (M01) at line 45; continuing (--stops continue)")
            .And.MatchRegex(@"executed (\d+) of \1 blocks, 0 underruns");
    }

    [Fact]
    public void With_optional_stop_off_M01_is_not_a_stop_and_needs_no_terminal()
    {
        var (code, stdout, stderr) = CliRun.InProcess("stream", Program(withM00: false), "--sim", "--job-db", Path.Combine(_folder, "jobs.db"), "--sim-speed", "instant",
            "--optional-stop", "off");
        code.Should().Be(0, stdout + stderr);
        stdout.Should().NotContain("program stop").And.MatchRegex(@"executed (\d+) of \1 blocks");
    }

    [Fact]
    public async Task Stops_wait_prints_the_stop_and_Enter_continues()
    {
        var psi = CliProcess.Info("stream", Program(), "--sim", "--job-db", Path.Combine(_folder, "jobs.db"), "--sim-speed", "50x", "--stops", "wait");
        using var p = Process.Start(psi)!;
        var stderr = p.StandardError.ReadToEndAsync();
        var output = new StringBuilder();
        var stops = 0;
        while (await p.StandardOutput.ReadLineAsync() is { } line)
        {
            output.AppendLine(line);
            if (line.StartsWith("program stop", StringComparison.Ordinal))
            {
                line.Should().Be(stops == 0
                    ? "program stop (M00) at line 24: press Enter to continue (Ctrl-C leaves the job resumable)"
                    : "program stop (M01) at line 45: press Enter to continue (Ctrl-C leaves the job resumable)");
                stops++;
                await Task.Delay(500); // it waits: the operator looks first
                await p.StandardInput.WriteLineAsync();
                await p.StandardInput.FlushAsync();
            }
        }

        await p.WaitForExitAsync();
        p.ExitCode.Should().Be(0, output + await stderr);
        stops.Should().Be(2);
        output.ToString().Should().MatchRegex(@"executed (\d+) of \1 blocks, 0 underruns");
    }

    [SkippableFact]
    public async Task Ctrl_C_at_a_stop_leaves_the_job_resumable_and_resume_restarts_at_the_stop()
    {
        Skip.If(OperatingSystem.IsWindows(), "needs Linux or macOS: POSIX signals");
        var src = Program();
        var db = Path.Combine(_folder, "jobs.db");
        using (var p = Process.Start(CliProcess.Info("stream", src, "--sim", "--job-db", db, "--sim-speed", "50x", "--stops", "wait"))!)
        {
            var stderr = p.StandardError.ReadToEndAsync();
            while (await p.StandardOutput.ReadLineAsync() is { } line)
            {
                if (line.StartsWith("program stop (M00) at line 24", StringComparison.Ordinal))
                {
                    await Task.Delay(300);
                    PosixSignals.Send(p.Id, PosixSignals.SigInt).Should().Be(0);
                }
            }

            await p.WaitForExitAsync();
            var err = await stderr;
            p.ExitCode.Should().Be(1, err);
            err.Should().Contain("interrupted at line 24").And.Contain("The job is resumable: pmacstream resume --job 1");
        }

        using (var store = JobStore.Open(db))
        {
            var cp = store.Get(1)!.Checkpoint!;
            cp.State.Should().Be(SessionState.Stopped, "the job was waiting at the stop");
            cp.LastExecutedLine.Should().Be(24);
        }

        // A new simulator lost the job: the restart (confirmed, with its preamble) goes on from the move after the
        // stop it had reached, and stops at the next one.
        var (code, stdout, stderr2) = await CliRun.InProcessAsync(["resume", "--job-db", db, "--yes", "--sim-speed", "instant", "--stops", "continue"]);
        code.Should().Be(0, stdout + stderr2);
        stdout.Should().Contain("restarting at the block of line 24").And.Contain("start at line 25")
            .And.NotContain("program stop (M00)")
            .And.Contain("program stop (M01) at line 45; continuing")
            .And.MatchRegex(@"executed (\d+) of \1 blocks");
    }
}
