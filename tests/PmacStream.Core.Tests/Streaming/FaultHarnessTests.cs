using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>
/// Seeded fault injection: link resets, lost replies, ERR replies, slow replies and host kills (the session object is
/// dropped mid-call and a new one resumes from the last checkpoint). Whatever happens, the executed-move log must hold
/// every block exactly once, in order.
/// </summary>
public class FaultHarnessTests(ITestOutputHelper output)
{
    public static IEnumerable<object[]> Batches() => Enumerable.Range(0, 8).Select(b => new object[] { b });

    [Theory]
    [MemberData(nameof(Batches))]
    public async Task Faults_never_lose_repeat_or_reorder_a_block(int batch)
    {
        var stats = new int[4];
        LineCounts motion = default, nonMotion = default;
        var nonMotionLines = 0;
        for (var run = 0; run < 30; run++)
        {
            var seed = (batch * 1000) + run;
            var r = await RunOnce(seed, "P501");
            stats[0] += r.Faults;
            stats[1] += r.Kills;
            stats[2] += r.Recoveries;
            stats[3] += r.Injected;
            motion += r.Motion;
            nonMotion += r.NonMotion;
            nonMotionLines += r.NonMotionLines;
        }

        output.WriteLine($"batch {batch}: 30 runs, {stats[3]} faults injected, {stats[0]} session faults, {stats[1]} host kills, {stats[2]} recoveries");
        output.WriteLine($"batch {batch}: motion blocks {motion}; non-motion lines ({nonMotionLines} in all) {nonMotion}");
        stats[3].Should().BeGreaterThan(30, "the harness must actually inject faults");
        stats[1].Should().BeGreaterThan(0);
        motion.Exact.Should().BeTrue($"motion blocks: {motion}");
        nonMotion.Exact.Should().BeTrue($"non-motion lines: {nonMotion}");
        nonMotionLines.Should().BeGreaterThan(100, "the programs hold non-motion lines for the harness to count");
    }

    /// <summary>
    /// The mechanism of the old repeat: without the line probe, a download broken after a non-motion line that the
    /// controller got resumes after the last move M0 reports, and sends (and runs) that line again. The harness sees it.
    /// </summary>
    [Fact]
    public async Task Without_the_line_probe_a_broken_download_repeats_non_motion_lines()
    {
        LineCounts motion = default, nonMotion = default;
        for (var seed = 0; seed < 30; seed++)
        {
            var r = await RunOnce(seed, null);
            motion += r.Motion;
            nonMotion += r.NonMotion;
        }

        output.WriteLine($"probe off, 30 runs: motion {motion}; non-motion {nonMotion}");
        motion.Exact.Should().BeTrue("motion blocks are exact through M0 alone");
        nonMotion.Repeated.Should().BeGreaterThan(0, "without the probe some non-motion line that had arrived is sent again");
        nonMotion.Lost.Should().Be(0);
    }

    /// <summary>
    /// Paper placement (<c>... F(P500) M0==n</c>, M0 one block behind): the probe on every line keeps motion and
    /// non-motion lines exact under faults too. Counted from the controller's executed-line log, since M0 lags.
    /// </summary>
    [Fact]
    public async Task Faults_never_lose_repeat_or_reorder_a_line_with_paper_placement()
    {
        LineCounts motion = default, nonMotion = default;
        var injected = 0;
        for (var seed = 0; seed < 40; seed++)
        {
            var r = await RunOnce(seed + 90_000, "P501", TrackingPlacement.Paper);
            motion += r.Motion;
            nonMotion += r.NonMotion;
            injected += r.Injected;
        }

        output.WriteLine($"paper placement, 40 runs, {injected} faults injected: motion {motion}; non-motion {nonMotion}");
        injected.Should().BeGreaterThan(40);
        motion.Exact.Should().BeTrue($"motion lines: {motion}");
        nonMotion.Exact.Should().BeTrue($"non-motion lines: {nonMotion}");
    }

    private static async Task<(int Faults, int Kills, int Recoveries, int Injected, LineCounts Motion, LineCounts NonMotion, int NonMotionLines)> RunOnce(int seed, string? probe, TrackingPlacement placement = TrackingPlacement.Exact)
    {
        var r = new Random(seed);
        var strategy = (StrategyKind)(seed % 3);
        var lines = 150 + r.Next(250);
        var chunk = 25 + r.Next(120);
        using var temp = new TestFolder($"fault{seed}");
        var folder = temp.Path;
        var program = FakeSplit.Write(folder, FakeSplit.Program(lines, seed), chunk, placement);
        var options = new StreamingOptions { LineProbeVariable = probe, Strategy = strategy, BufferWords = 6000, PrTargetLines = 20 + r.Next(60), AdaptiveMinLeadSeconds = 0.1 + (r.NextDouble() * 0.4) };
        FakeRig? rig = null;
        var faulty = new FaultyConnection(new FakeRotaryController(), r, dt => rig!.Advance(dt));
        rig = new FakeRig(program, options, connection: null, moveSeconds: 0.002 + (r.NextDouble() * 0.02), capacityWords: 6000);
        faulty = new FaultyConnection(rig.Controller, r, dt => rig.Advance(dt)) { FaultRate = 0.03, KillRate = 0.006 };
        rig.Connection = faulty;
        rig.Session = rig.NewSession();
        rig.Controller.Override = r.Next(3) == 0 ? 50 + r.Next(100) : 100;

        int faults = 0, kills = 0, recoveries = 0, faultedTicks = 0;
        var started = false;
        for (var tick = 0; tick < 50_000; tick++)
        {
            try
            {
                if (!started)
                {
                    if (rig.Sink.Last is not null)
                    {
                        // As a host resumes from the job store: a start that broke off while loading is loaded again.
                        await rig.Session.ResumeAsync(rig.Sink.Record());
                    }
                    else
                    {
                        await rig.Session.StartAsync();
                    }

                    started = true;
                }
                else if (rig.Session.State == SessionState.Faulted)
                {
                    if (++faultedTicks >= 3)
                    {
                        faulty.Down = false;
                        if (await rig.Session.RecoverAsync())
                        {
                            recoveries++;
                            faultedTicks = 0;
                        }
                    }
                }
                else
                {
                    await rig.Session.TickAsync();
                    if (rig.Session.State == SessionState.Faulted)
                    {
                        faults++;
                    }
                }
            }
            catch (HostKilledException)
            {
                kills++;
                faulty.Down = false;
                rig.Session = rig.NewSession();
                started = false;
            }
            catch (Exception e) when (e is PmacLinkException or PmacErrorException)
            {
                // A start or resume that failed: link back after a while, then try again.
                faulty.Down = false;
                if (rig.Session.State == SessionState.Idle)
                {
                    rig.Session = rig.NewSession();
                    started = false;
                }
                else
                {
                    started = true;
                }
            }

            if (started && rig.Session.State == SessionState.Completed && !rig.Controller.InMove)
            {
                break;
            }

            rig.Advance(options.TickPeriod.TotalSeconds);
        }

        if (rig.Session.State != SessionState.Completed)
        {
            var c = rig.Controller;
            throw new Xunit.Sdk.XunitException($"seed {seed}: stuck {rig.Session.State} '{rig.Session.Status.Message}' ctl running={c.Running} held={c.Held} open={c.Open} pr={c.LinesAhead} m0={c.M0} moves={c.Moves.Count}/{program.Manifest.TotalMotionBlocks} next={rig.Session.Next} last cmds: {string.Join(" | ", c.Log.TakeLast(12))}");
        }

        var executed = rig.Controller.Moves.Select(m => m.SourceLine).ToList();
        var expected = program.TrackedLines().ToList();
        rig.Session.State.Should().Be(SessionState.Completed, $"seed {seed} ({strategy}) must finish; {rig.Session.Status.Message}");
        if (placement == TrackingPlacement.Exact)
        {
            executed.Should().Equal(expected, $"seed {seed} ({strategy}, {lines} lines, chunks of {chunk}): 0 lost, 0 repeated, 0 reordered");
        }

        rig.Controller.Violations.Should().BeEmpty($"seed {seed}");
        var sent = Enumerable.Range(1, program.TotalChunks).SelectMany(c => program.Body(c)).Select(l => l.Text).ToList();
        var (motion, nonMotion) = LineAccounting.Compare(sent, rig.Controller.ExecutedLines, t => program.Classify(t) is { } l && (l.IsMotion || l.TrackedLine > 0));
        if (probe is not null && !(nonMotion.Exact && motion.Exact))
        {
            throw new Xunit.Sdk.XunitException($"seed {seed} ({strategy}, {placement}): motion {motion}, non-motion lines {nonMotion}");
        }

        Directory.Delete(folder, true);
        return (faults, kills, recoveries, faulty.Injected, motion, nonMotion, sent.Count(t => !(program.Classify(t) is { } l && (l.IsMotion || l.TrackedLine > 0))));
    }
}
