using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preparation;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// One start-from-line planner: the preamble the CLI prints for <c>--from-line N</c> is the one the HMI shows (and,
/// through the same plan, sends) for line N, for both safe-Z modes.
/// </summary>
[Collection("stream-cli")]
public sealed class StartPlanCliHmiTests : IDisposable
{
    private readonly TestFolder _temp = new("plan");

    public void Dispose() => _temp.Dispose();

    [Theory]
    [InlineData(1500, "fixed")]
    [InlineData(2400, "highest")]
    public async Task Cli_and_hmi_plan_the_same_preamble_for_a_line(int line, string mode)
    {
        var src = Path.Combine(_temp.Path, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, src);
        var (code, stdout, stderr) = await CliRun.InProcessAsync(["stream", src, "--sim", "--from-line", line.ToString(), "--safe-z-mode", mode, "--job-db", Path.Combine(_temp.Path, "jobs.db")]);
        code.Should().Be(2, "without --yes the start is refused after showing the plan; " + stderr);
        var shown = stdout.Split('\n').Select(l => l.TrimEnd('\r'));
        var cli = shown.SkipWhile(l => !l.Contains("preamble:", StringComparison.Ordinal)).Skip(1).TakeWhile(l => l.StartsWith("  ", StringComparison.Ordinal)).Select(l => l.Trim()).ToList();
        cli.Should().NotBeEmpty(stdout);

        var split = Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(_temp.Path, "hmi-split") });
        var options = new StartPlanOptions { SafeZMode = mode == "fixed" ? SafeZMode.Fixed : SafeZMode.HighestSoFar };
        var backend = new CoreHmiBackend(new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "hmi.db") }));
        var settings = RunSettings.Default with { SafeZMode = options.SafeZMode };
        var hmi = await backend.BuildPreambleAsync(new SplitView(src, split.OutputDirectory, [], split.Manifest.TotalBlocks), line, settings, PmacStream.GCode.MachineProfile.Default);

        hmi.Should().Equal(cli, "the HMI shows exactly the preamble the CLI shows for the same line");
        var plan = StartFromLine.Plan(src, line, StartPlanOptions.For(split.Manifest, options));
        plan.GCode.Should().Equal(hmi);
        stdout.Should().Contain($"start at line {plan.Line}");
        if (mode == "highest")
        {
            plan.SafeZ.Should().NotBe(10, "the highest Z so far plus clearance, not the fixed height");
        }
    }
}
