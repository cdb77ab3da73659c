using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>Wall time for a simulator whose clock runs <paramref name="speed"/> times faster than real time.</summary>
public sealed class AcceleratedWallTime(PmacSimulator sim, double speed) : TimeProvider
{
    public override long TimestampFrequency => 1_000_000;

    public override long GetTimestamp() => (long)(sim.Now / speed * 1_000_000);
}

/// <summary>
/// The ETA on the simulator with an accelerated clock (the HMI's 60x case, where the old program-time ETA was far
/// off): wall time runs 60 times slower than the machine, and the estimate must converge on the real remaining time.
/// </summary>
public class SimEtaTests(ITestOutputHelper output)
{
    [Fact]
    public async Task Eta_converges_on_real_time_with_a_60x_simulator_clock()
    {
        const double speed = 60;
        // The faces' feed control (the % override, RunSettings.ToStreamingOptions): in paper mode the factor is the
        // live P500 over the block's programmed F, and P500, read once a wall second (a minute of machine time at
        // 60x), carries the program's own feed changes, so it is stale between readings (issue 28's note).
        using var rig = new SimRig(RepoRoot.DemoProgram, 1000, new StreamingOptions { BufferWords = 20_000, Feed = PmacStream.Preparation.FeedMode.Override });
        var times = MoveTimeTable.FromProgram(RepoRoot.DemoProgram)!;
        rig.Session = new StreamingSession(rig.Connection, rig.Program, rig.Options, rig.Sink, moveTimes: times, time: new AcceleratedWallTime(rig.Sim, speed));
        await rig.Session.StartAsync();
        var samples = new List<(double Wall, double Percent, double Eta, double Old)>();
        var final = rig.Program.FinalTrackedLine;
        for (var i = 0; i < 20_000 && rig.Session.State != SessionState.Completed; i++)
        {
            await rig.Session.TickAsync();
            if (rig.Session.Status is { State: SessionState.Running, Eta: { } e, Percent: var p, CurrentLine: var line } && p > 0)
            {
                // Old: the program time left at programmed feed, shown as if it were wall time.
                samples.Add((rig.Sim.Now / speed, p, e.TotalSeconds, times.SecondsBetween(line, final)));
            }

            rig.Sim.Advance(TimeSpan.FromSeconds(0.05 * speed));
        }

        rig.Session.State.Should().Be(SessionState.Completed);
        rig.Sim.RunUntilIdle(TimeSpan.FromHours(1));
        var end = rig.Sim.ExecutedMoves[^1].EndTime / speed;
        var window = samples.Where(s => s.Percent >= 25 && s.Percent <= 90).ToList();
        var errors = window.Select(s => Math.Abs(s.Eta - (end - s.Wall)) / (end - s.Wall)).ToList();
        var naive = window.Select(s => Math.Abs(s.Old - (end - s.Wall)) / (end - s.Wall)).Average();
        output.WriteLine($"demo at 60x: real run {end:0.0} s wall ({end * speed:0} s machine), program time {times.TotalSeconds:0} s; ETA error from 25 % to 90 %: mean {errors.Average():P1}, worst {errors.Max():P1} (program-time ETA: mean {naive:P0}) over {window.Count} samples; at 50 %: {errors[window.FindIndex(s => s.Percent >= 50)]:P1}");
        window.Count.Should().BeGreaterThan(20);
        errors.Max().Should().BeLessThan(0.15, "the ETA must converge on the real remaining time");
        errors.Average().Should().BeLessThan(0.08);
        naive.Should().BeGreaterThan(10, "a program-time ETA would be about 60x off here");
    }
}
