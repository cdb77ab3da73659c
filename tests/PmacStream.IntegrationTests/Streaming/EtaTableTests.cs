using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 28's ETA table: on the demo and every corpus program the gate passes, the session's ETA at 0 %, 10 % and
/// 50 % of the program (in machine time: the simulator's clock is the session's) against the simulator's own
/// execution with the Turbo timing (docs/turbo-pmac-timing.md). Program stops are left out of both sides: the actual
/// time left is the sum of the moves (and dwells) still to run, not the time the machine stood at M00/M06. Every
/// entry must be within 5 %.
/// </summary>
public sealed class EtaTableTests(ITestOutputHelper output) : IDisposable
{
    private static readonly double[] Points = [0, 10, 50];

    private readonly TestFolder _temp = new("eta-table");

    public void Dispose() => _temp.Dispose();

    [SkippableFact]
    public async Task The_first_eta_is_within_5_percent_of_the_machine_time_on_the_demo_and_the_corpus()
    {
        var programs = new List<string> { RepoRoot.DemoProgram };
        programs.AddRange(Requires.Corpus().Where(f => CorpusRunnable.Contains(Path.GetFileName(f))).Order(StringComparer.Ordinal));
        programs.Should().HaveCount(1 + CorpusRunnable.Count);
        var rows = new List<string> { "| program | machine s | ETA 0 % | ETA 10 % | ETA 50 % | worst |", "|---|---:|---|---|---|---:|" };
        var worst = new List<(string Name, double Error)>();
        foreach (var path in programs)
        {
            var (actualTotal, cells, error) = await RunAsync(path);
            rows.Add($"| {Path.GetFileName(path)} | {actualTotal:0.0} | {string.Join(" | ", cells)} | {error:P1} |");
            worst.Add((Path.GetFileName(path), error));
        }

        output.WriteLine(string.Join(Environment.NewLine, rows));
        worst.Where(w => !KnownSplitDefects.ContainsKey(w.Name)).Should().OnlyContain(w => w.Error <= 0.05, "every estimate at 0, 10 and 50 % must be within 5 % of the machine time left");
        foreach (var (name, why) in KnownSplitDefects)
        {
            output.WriteLine($"{name}: not held to 5 %: {why}");
        }
    }

    /// <summary>
    /// Programs whose machine time differs from the G-code's for a defect of the split, not of the timing: the ETA is
    /// the G-code's, the controller runs what the chunk says. Reported in docs/turbo-pmac-timing.md; not fixed here.
    /// </summary>
    private static readonly Dictionary<string, string> KnownSplitDefects = new()
    {
        // None now: smiley.nc's "Z0.3 G00" retracts (written "Z0.3 G00", run at feed) are written "G00 Z0.3" since the
        // split writes a block's G codes before its axis words.
    };

    /// <summary>The programs of ../shared/gcode-corpus that run as they are (CorpusStreamTests' list).</summary>
    private static readonly HashSet<string> CorpusRunnable =
    [
        "SabirHusnain__CNC-GCode-Milling-and-Lathe__Nikola.nc", "Sienci-Labs__gsender__MB-2.3_test.nc", "CauldronDevelopmentLLC__CAMotics__flower_mold.nc",
        "CauldronDevelopmentLLC__CAMotics__vcarve.ngc", "LMHDPRO__MAC__1003.nc", "SafetyDav3__cnc-sprayer__fusion-inch.nc", "Sienci-Labs__gsender__KB-22_test.gcode",
        "rustyford__cam__router_panel.ngc", "stcline__CNC_Training__smiley.nc",
    ];

    private async Task<(double Actual, List<string> Cells, double Worst)> RunAsync(string source)
    {
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });
        var prepared = await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { OutDir = Path.Combine(_temp.Path, Path.GetFileNameWithoutExtension(source)) });
        var program = prepared.Program;
        var times = MoveTimeTable.FromProgram(source, profile: prepared.Profile)!;
        // The simulated machine is the profile's: rapids at its rapid rate, as the command line's simulators run it.
        using var sim = new PmacSimulator(new SimOptions { RetainExecutedMoves = false, RapidFeed = prepared.Profile.RapidRate });
        var moves = new List<(double Start, double End)>();
        sim.MoveExecuted += m => moves.Add((m.StartTime, m.EndTime));
        var port = sim.OpenPort("stream");
        SimRig.LoadLibrary(port);
        var options = RunSettings.Default.ToStreamingOptions(StrategyKind.Full, singleBlock: false, defineBuffer: true);
        var session = new StreamingSession(new InProcessConnection(port, "sim"), program, options, moveTimes: times, time: SimRig.Clock(sim));
        await session.StartAsync();
        var samples = new List<(double Percent, double At, double Eta)>();
        var next = 0;
        for (var tick = 0; tick < 400_000 && session.State != SessionState.Completed; tick++)
        {
            session.State.Should().NotBe(SessionState.Faulted, session.Status.Message);
            await session.TickAsync();
            if (session.State == SessionState.Stopped)
            {
                await session.ResumeMotionAsync(); // the operator goes on at a program stop
            }
            else if (next < Points.Length && session.Status is { State: SessionState.Running, Eta: { } eta, Percent: var p } && p >= Points[next])
            {
                samples.Add((p, sim.Now, eta.TotalSeconds));
                next++;
            }

            sim.Advance(TimeSpan.FromSeconds(0.25));
        }

        session.State.Should().Be(SessionState.Completed, session.Status.Message);
        sim.RunUntilIdle(TimeSpan.FromHours(24));
        samples.Should().HaveCount(Points.Length);
        var cells = new List<string>();
        var worst = 0.0;
        foreach (var (percent, at, eta) in samples)
        {
            // Machine time left: what the moves still to run take (a move under way counts from here), stops left out.
            var left = moves.Sum(m => Math.Max(0, m.End - Math.Max(m.Start, at)));
            var error = Math.Abs(eta - left) / left;
            worst = Math.Max(worst, error);
            cells.Add(string.Create(CultureInfo.InvariantCulture, $"{eta:0.0} / {left:0.0} s ({(eta - left) / left:+0.0%;-0.0%}) at {percent:0.0} %"));
        }

        return (moves.Sum(m => m.End - m.Start), cells, worst);
    }
}
