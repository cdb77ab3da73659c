using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The one gate of every command that reads a program, as the `pmacstream` process shows it: errors and codes the
/// controller cannot run yet refused with every finding as FILE:LINE:COL, the real option named, nothing sent or
/// written; the profile a job ran under kept for its resume.
/// </summary>
[Collection("stream-cli")]
public sealed class GateCliTests : IDisposable
{
    private readonly TestFolder _temp = new("gate");

    public void Dispose() => _temp.Dispose();

    private string Write(string name, string text)
    {
        var path = Path.Combine(_temp.Path, name);
        File.WriteAllText(path, text);
        return path;
    }

    private static string Moves(int n) => TestPrograms.Text(string.Empty, n, TestPrograms.Grid(20), footer: string.Empty);

    [Fact]
    public void Stream_refuses_codes_the_controller_cannot_run_yet_naming_each_and_force_and_sends_nothing()
    {
        var src = Write("toolchange.nc", "G21 G90 G17\nG16\nG00 X0 Y0\nG01 F600\n" + Moves(40) + "G63\nM30\n");
        var db = Path.Combine(_temp.Path, "jobs.db");
        var (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--job-db", db, "--sim-speed", "instant");

        code.Should().Be(1, stdout + stderr);
        var lines = stderr.Split('\n', StringSplitOptions.RemoveEmptyEntries | StringSplitOptions.TrimEntries);
        lines.Should().Contain(l => l.EndsWith("toolchange.nc:2:1: error E127: G16 (polar coordinate command) cannot run on the controller yet under profile 'fanuc-mill': the PMAC would skip the code and run the rest of the block", StringComparison.Ordinal));
        lines.Should().Contain(l => l.Contains("toolchange.nc:45:1: error E127: G63 (", StringComparison.Ordinal));
        lines[^1].Should().MatchRegex(@"^pmacstream stream: .*toolchange\.nc: the controller cannot run G16 \(line 2\), G63 \(line 45\) yet under profile 'fanuc-mill' .*nothing sent to the controller \(--force runs it anyway\)$");
        stdout.Should().NotContain("job ", "no job is created for a refused program");
        if (File.Exists(db))
        {
            using var store = JobStore.Open(db);
            store.List().Should().BeEmpty("nothing reached the controller, so there is nothing to resume");
        }

        (code, stdout, stderr) = CliRun.InProcess("stream", src, "--sim", "--job-db", db, "--sim-speed", "instant", "--force");
        code.Should().Be(0, stdout + stderr);
        stderr.Should().Contain("--force: the controller cannot run G16 (line 2), G63 (line 45) yet under profile 'fanuc-mill': it skips each of them and runs the rest of its block");
        stdout.Should().MatchRegex(@"executed (\d+) of \1 blocks");
    }

    [Fact]
    public void Stream_split_and_preview_refuse_errors_in_the_one_format_and_take_the_profile()
    {
        // M06 is an error under grbl (no tool changer), the A word too (three axes).
        var src = Write("grbl.nc", "G21 G90\nG00 X0 Y0\nM06 T1\nG01 X5 A3 F100\nM30\n");
        var png = Path.Combine(_temp.Path, "grbl.png");
        foreach (var (args, what) in new (string[] Args, string What)[]
                 {
                     (["stream", src, "--sim", "--profile", "grbl", "--job-db", Path.Combine(_temp.Path, "j.db")], "nothing sent to the controller (--force runs it anyway)"),
                     (["split", src, "--profile", "grbl"], "not split (--force splits anyway)"),
                     (["preview", src, "--png", png, "--profile", "grbl"], "grbl.png not written (--force draws what can be read)"),
                 })
        {
            var (code, stdout, stderr) = CliRun.InProcess(args);
            code.Should().Be(1, stdout + stderr);
            var lines = stderr.Split('\n', StringSplitOptions.RemoveEmptyEntries | StringSplitOptions.TrimEntries);
            lines.Should().Contain(l => l.EndsWith("grbl.nc:3:1: error E105: unknown M code M06: not in machine profile 'grbl'", StringComparison.Ordinal), args[0]);
            lines.Should().Contain(l => l.EndsWith("grbl.nc:4:8: error E118: address letter 'A' is not used by machine profile 'grbl' (letters FGIJKLMNPRSTXYZ)", StringComparison.Ordinal), args[0]);
            lines[^1].Should().StartWith($"pmacstream {args[0]}: ").And.Contain("2 error(s) under profile 'grbl'").And.EndWith(what);
            stderr.Should().NotContain("Diagnostic {", "findings are printed in the one format, never as a record");
        }

        File.Exists(png).Should().BeFalse("a refused preview writes nothing");
        Directory.Exists(Splitter.DefaultOutDir(src)).Should().BeFalse("a refused split leaves no chunks");
        var (forced, _, err) = CliRun.InProcess("preview", src, "--png", png, "--profile", "grbl", "--force");
        forced.Should().Be(0, err);
        File.Exists(png).Should().BeTrue();
        err.Should().Contain("--force: 2 error(s) listed above");
    }

    [Fact]
    public void Resume_takes_the_profile_the_job_ran_under_and_refuses_it_once_changed()
    {
        var profileFile = Write("mill.json", MachineProfile.Default.ToJson().Replace("\"name\": \"fanuc-mill\"", "\"name\": \"shop-mill\"", StringComparison.Ordinal));
        var profile = MachineProfile.Resolve(profileFile);
        var src = Write("part.nc", "G21 G90 G17\nG00 X0 Y0\nG01 F3000\n" + Moves(300) + "M30\n");
        var db = Path.Combine(_temp.Path, "jobs.db");
        using (var jobs = JobStore.Open(db))
        {
            var split = Splitter.Split(src, new SplitOptions { OutDir = Splitter.DefaultOutDir(src), BlocksPerChunk = 100, CheckProfile = profile });
            var id = jobs.CreateJob(src, split.Manifest.SourceSha256, split.ManifestPath, StrategyKind.Chunk, "sim", null, profile: (profile.Source, profile.Identity));
            jobs.SaveCheckpoint(id, new Checkpoint(150, 2, new StreamPosition(3, 0), true, 2, SessionState.Running, DateTimeOffset.UtcNow), durable: true);
        }

        var (code, stdout, stderr) = CliRun.InProcess("resume", "--job-db", db, "--yes", "--profile", "grbl");
        code.Should().Be(2, stdout + stderr);
        stderr.Should().Contain("ran under machine profile").And.Contain("mill.json (shop-mill@").And.Contain("the profile asked for, grbl, is grbl@").And.Contain("the profile changed since the job started");

        File.WriteAllText(profileFile, File.ReadAllText(profileFile).Replace("\"toolCount\": 9999", "\"toolCount\": 40", StringComparison.Ordinal));
        (code, stdout, stderr) = CliRun.InProcess("resume", "--job-db", db, "--yes");
        code.Should().Be(2, stdout + stderr);
        stderr.Should().Contain("mill.json now reads as shop-mill@").And.Contain("the profile changed since the job started");
        stdout.Should().NotContain("restarting", "nothing was sent");
    }
}
