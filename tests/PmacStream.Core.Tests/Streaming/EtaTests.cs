using PmacStream.Preparation;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>
/// The ETA is real time: program seconds left scaled by the live feed (P500 over programmed F, or %) and by the rate
/// measured so far. A deterministic fake controller runs the moves at a rate different from the interpreter's.
/// </summary>
public class EtaTests(ITestOutputHelper output)
{
    [Fact]
    public void Estimator_converges_on_a_constant_rate_and_follows_a_feed_change()
    {
        var eta = new EtaEstimator(smoothingSeconds: 5);
        eta.Rate.Should().Be(1.0, "nothing measured yet");

        // Programmed: 1 s per block; the machine really takes 0.4 s per block at factor 1.
        var wall = 0.0;
        for (var block = 0; block < 100; block++)
        {
            eta.Observe(wall, block, 1.0, counting: true);
            wall += 0.4;
        }

        eta.Rate.Should().BeApproximately(2.5, 0.01);
        eta.Estimate(10, 1.0).TotalSeconds.Should().BeApproximately(4.0, 0.05);

        // The operator doubles the feed: the estimate halves at once, and the rate stays (the machine follows).
        eta.Estimate(10, 2.0).TotalSeconds.Should().BeApproximately(2.0, 0.05);
        for (var block = 100; block < 200; block++)
        {
            eta.Observe(wall, block, 2.0, counting: true);
            wall += 0.2;
        }

        eta.Rate.Should().BeApproximately(2.5, 0.05);

        // Held time does not count as slow running.
        eta.Observe(wall, 200, 2.0, counting: false);
        wall += 1000;
        eta.Observe(wall, 200, 2.0, counting: false);
        eta.Observe(wall + 0.2, 201, 2.0, counting: true);
        eta.Rate.Should().BeApproximately(2.5, 0.05);
    }

    public static IEnumerable<object[]> Cases() =>
    [
        // name, programmed s/block, programmed F, real s/block (fake), live P500 or %, override mode
        ["machine 2.5x faster than the move times", 0.025, 1000.0, 0.01, 1000.0, false],
        ["paper feed P500 twice the programmed F", 0.02, 500.0, 0.01, 1000.0, false],
        ["override 50 %", 0.01, 1000.0, 0.01, 50.0, true],
        ["machine slower and P500 above F", 0.01, 800.0, 0.016, 1000.0, false],
    ];

    [Theory]
    [MemberData(nameof(Cases))]
    public async Task Eta_converges_on_the_real_remaining_time(string name, double programmedSeconds, double programmedFeed, double realSeconds, double liveFeed, bool overrideMode)
    {
        using var temp = new TestFolder("eta");
        var folder = temp.Path;
        try
        {
            // 20,000 blocks: the measured rate replaces the move times only once half a smoothing span (15 s) of program
            // time is measured (EtaEstimator.Rate), which every case reaches well before a quarter of the job has run.
            var program = FakeSplit.Write(folder, FakeSplit.Program(20_000, 7), 200);
            var table = new MoveTimeTable(program.TrackedLines().Select(l => (l, programmedSeconds, programmedFeed)));
            var options = new StreamingOptions { BufferWords = 8000, Feed = overrideMode ? FeedMode.Override : FeedMode.Paper };
            var rig = new FakeRig(program, options, moveSeconds: realSeconds, capacityWords: 8000);
            if (overrideMode)
            {
                rig.Controller.Override = liveFeed;
            }
            else
            {
                rig.Controller.P[500] = liveFeed;
            }

            rig.Session = new StreamingSession(rig.Connection, program, options, rig.Sink, moveTimes: table, time: rig.Time);
            await rig.Session.StartAsync();
            var samples = new List<(double Time, double Percent, double Eta)>();
            (await rig.RunAsync(everyTick: _ =>
            {
                if (rig.Session.Status is { State: SessionState.Running, Eta: { } e, Percent: var p } && p > 0)
                {
                    samples.Add((rig.Controller.Now, p, e.TotalSeconds));
                }

                return Task.CompletedTask;
            })).Should().BeTrue();

            var end = rig.Controller.Moves[^1].StartSeconds + (realSeconds * (overrideMode ? 100 / liveFeed : 1));
            var worst = 0.0;
            foreach (var (t, p, e) in samples.Where(s => s.Percent >= 25 && s.Percent <= 90))
            {
                var truth = end - t;
                worst = Math.Max(worst, Math.Abs(e - truth) / truth);
            }

            var naive = table.TotalSeconds;
            output.WriteLine($"{name}: real run {end:0.00} s, program time {naive:0.00} s, worst ETA error from 25 % to 90 % of the job {worst:P1}, {samples.Count} samples");
            samples.Count(s => s.Percent >= 25 && s.Percent <= 90).Should().BeGreaterThan(20);
            worst.Should().BeLessThan(0.10, $"{name}: the ETA must be within 10 % of the real remaining time once a quarter of the job has run");
        }
        finally
        {
            Directory.Delete(folder, true);
        }
    }

    [Fact]
    public async Task Eta_follows_a_live_override_change_at_once()
    {
        using var temp = new TestFolder("eta-override");
        var folder = temp.Path;
        try
        {
            var program = FakeSplit.Write(folder, FakeSplit.Program(800, 3), 200);
            var table = new MoveTimeTable(program.TrackedLines().Select(l => (l, 0.01, 1000.0)));
            var options = new StreamingOptions { BufferWords = 8000, Feed = FeedMode.Override };
            var rig = new FakeRig(program, options, moveSeconds: 0.01, capacityWords: 8000);
            rig.Session = new StreamingSession(rig.Connection, program, options, rig.Sink, moveTimes: table, time: rig.Time);
            await rig.Session.StartAsync();
            var samples = new List<(double Time, double Percent, double Eta)>();
            var changed = false;
            (await rig.RunAsync(everyTick: async _ =>
            {
                if (rig.Session.Status is { State: SessionState.Running, Eta: { } e, Percent: var p })
                {
                    if (!changed && p >= 40)
                    {
                        await rig.Session.SetFeedAsync(50); // the machine now runs at half speed
                        changed = true;
                        return;
                    }

                    samples.Add((rig.Controller.Now, p, rig.Session.Status.Eta!.Value.TotalSeconds));
                }
            })).Should().BeTrue();

            var end = rig.Controller.Moves[^1].StartSeconds + 0.02;
            var after = samples.Where(s => s.Percent > 41 && s.Percent <= 90).ToList();
            var worst = after.Max(s => Math.Abs(s.Eta - (end - s.Time)) / (end - s.Time));
            output.WriteLine($"override 100 -> 50 % at 40 %: worst ETA error after the change {worst:P1} over {after.Count} samples");
            after.Count.Should().BeGreaterThan(20);
            worst.Should().BeLessThan(0.10);
        }
        finally
        {
            Directory.Delete(folder, true);
        }
    }
}
