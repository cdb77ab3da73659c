using System.Globalization;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The seeded fault harness on the real pieces: the splitter's chunks, the simulator (lookahead, synchronous M0==,
/// PR) and the session, with link resets, lost/slow/ERR replies and host kills (a new session resumes from the last
/// checkpoint). 0 lost, 0 repeated, 0 reordered blocks in the simulator's executed-move log.
/// </summary>
public class SimFaultHarnessTests(ITestOutputHelper output)
{
    public static IEnumerable<object[]> Batches() => Enumerable.Range(0, 4).Select(b => new object[] { b });

    [Theory]
    [MemberData(nameof(Batches))]
    public async Task Faults_never_lose_repeat_or_reorder_a_block_on_the_simulator(int batch)
    {
        int injected = 0, kills = 0, faults = 0, nonMotionLines = 0, fromLine = 0;
        LineCounts motion = default, nonMotion = default;
        for (var run = 0; run < 30; run++)
        {
            var r = await RunOnce((batch * 1000) + run + 500_000, "P501");
            injected += r.Injected;
            kills += r.Kills;
            faults += r.Faults;
            motion += r.Motion;
            nonMotion += r.NonMotion;
            nonMotionLines += r.NonMotionLines;
            fromLine += r.FromLine ? 1 : 0;
        }

        output.WriteLine($"batch {batch}: 30 runs ({fromLine} from a line behind a preamble), {injected} faults injected, {faults} session faults, {kills} host kills");
        output.WriteLine($"batch {batch}: motion blocks {motion}; non-motion lines ({nonMotionLines} in all) {nonMotion}");
        injected.Should().BeGreaterThan(30);
        kills.Should().BeGreaterThan(0);
        motion.Exact.Should().BeTrue($"motion blocks: {motion}");
        nonMotion.Exact.Should().BeTrue($"non-motion lines: {nonMotion}");
        nonMotionLines.Should().BeGreaterThan(100);
    }

    /// <summary>
    /// Fault storms during the start: until the run command is recorded, link faults and host kills hit about every
    /// third operation, so kills land in the clear, the preamble, the first chunk and the reload after a broken load.
    /// </summary>
    [Fact]
    public async Task Fault_storms_during_the_start_never_lose_or_repeat_a_preamble_or_program_line()
    {
        int kills = 0, fromLine = 0;
        LineCounts motion = default, nonMotion = default;
        for (var run = 0; run < 24; run++)
        {
            // seed % 4 == 1 starts from a line behind the preamble: half of these runs.
            var r = await RunOnce(((run / 2) * 4) + (run % 2) + 801_000, "P501", startStorm: true);
            kills += r.Kills;
            motion += r.Motion;
            nonMotion += r.NonMotion;
            fromLine += r.FromLine ? 1 : 0;
        }

        output.WriteLine($"start storms: 24 runs ({fromLine} from a line), {kills} host kills; motion {motion}; non-motion {nonMotion}");
        fromLine.Should().Be(12);
        kills.Should().BeGreaterThan(10);
        motion.Exact.Should().BeTrue();
        nonMotion.Exact.Should().BeTrue();
    }

    /// <summary>The old mechanism on the simulator: without the line probe, non-motion lines that had arrived before a break run twice.</summary>
    [Fact]
    public async Task Without_the_line_probe_the_simulator_runs_some_non_motion_lines_twice()
    {
        LineCounts motion = default, nonMotion = default;
        for (var run = 0; run < 30; run++)
        {
            var r = await RunOnce(run + 700_000, null);
            motion += r.Motion;
            nonMotion += r.NonMotion;
        }

        output.WriteLine($"probe off, 30 runs: motion {motion}; non-motion {nonMotion}");
        motion.Exact.Should().BeTrue();
        nonMotion.Repeated.Should().BeGreaterThan(0, "the harness must see the repeat the probe prevents");
    }

    private static string Source(string folder, int blocks, Random r)
    {
        var sb = new StringBuilder("G21 G17 G90\nG00 X0 Y0\nF3000\n");
        for (var i = 0; i < blocks; i++)
        {
            sb.Append(r.Next(16) switch
            {
                0 => "M08\n",
                1 => "(note)\n",
                12 => string.Create(CultureInfo.InvariantCulture, $"S{1000 + i} M03\n"),
                13 => string.Create(CultureInfo.InvariantCulture, $"F{2000 + i}\n"),
                14 => "M09\n",
                2 => string.Create(CultureInfo.InvariantCulture, $"G02 X{r.Next(50)}.0 Y{r.Next(50)}.0 R{60 + r.Next(10)}.0\n"),
                _ => string.Create(CultureInfo.InvariantCulture, $"G01 X{r.Next(50)}.{r.Next(10)} Y{r.Next(50)}.{r.Next(10)}\n"),
            });
        }

        sb.Append("M30\n");
        var path = Path.Combine(folder, "p.nc");
        File.WriteAllText(path, sb.ToString());
        return path;
    }

    private static async Task<(int Injected, int Kills, int Faults, LineCounts Motion, LineCounts NonMotion, int NonMotionLines, bool FromLine)> RunOnce(int seed, string? probe, bool startStorm = false)
    {
        var r = new Random(seed);
        var folder = Path.Combine(Path.GetTempPath(), "pmacstream-simfault", seed.ToString(CultureInfo.InvariantCulture));
        if (Directory.Exists(folder))
        {
            Directory.Delete(folder, true);
        }

        Directory.CreateDirectory(folder);
        var src = Source(folder, 120 + r.Next(200), r);
        var split = Splitter.Split(src, new SplitOptions { BlocksPerChunk = 25 + r.Next(100), OutDir = Path.Combine(folder, "chunks") });
        var program = ChunkedProgram.Open(split.ManifestPath);

        // Every fourth run starts from a line, behind the restore preamble: that must be exact under faults too.
        StartPlan? plan = null;
        if (seed % 4 == 1)
        {
            var tracked = program.TrackedLines().ToList();
            plan = StartFromLine.Plan(src, tracked[tracked.Count / 3], StartPlanOptions.For(split.Manifest));
        }

        using var sim = new PmacSimulator(new SimOptions { RecordRotaryLines = true });
        var port = sim.OpenPort("host");
        SimRig.LoadLibrary(port);
        var faulty = new FaultyConnection(port, r, dt => sim.Advance(TimeSpan.FromSeconds(dt))) { FaultRate = 0.03, KillRate = 0.006 };
        var strategy = (StrategyKind)(seed % 3);
        var options = new StreamingOptions { LineProbeVariable = probe, Strategy = strategy, BufferWords = 8000, PrTargetLines = 20 + r.Next(60), AdaptiveMinLeadSeconds = 0.1 + (r.NextDouble() * 0.4) };
        var time = SimRig.Clock(sim);
        var sink = new MemorySink();
        var log = new List<string>();
        StreamingSession NewSession()
        {
            var ss = new StreamingSession(faulty, program, options, sink, time: time);
            ss.EventRaised += (_, e) => log.Add($"{e.Kind} {e.Message} m0={e.TrackedLine}");
            return ss;
        }

        var session = NewSession();
        int kills = 0, faults = 0, faultedTicks = 0;
        var started = false;
        var tickSeconds = 0.02 + (r.NextDouble() * 0.2);
        for (var tick = 0; tick < 100_000; tick++)
        {
            try
            {
                if (!started)
                {
                    if (sink.Last is not null)
                    {
                        // As a host resumes from the job store: a start that broke off while loading is loaded again.
                        await session.ResumeAsync(sink.Record());
                    }
                    else
                    {
                        await session.StartAsync(plan?.Line, plan?.PmacLines);
                    }

                    started = true;
                }
                else if (session.State == SessionState.Faulted)
                {
                    if (++faultedTicks >= 3)
                    {
                        faulty.Down = false;
                        if (await session.RecoverAsync())
                        {
                            faultedTicks = 0;
                        }
                    }
                }
                else
                {
                    await session.TickAsync();
                    if (session.State == SessionState.Faulted)
                    {
                        faults++;
                    }
                }
            }
            catch (HostKilledException)
            {
                kills++;
                faulty.Down = false;
                session = NewSession();
                started = false;
            }
            catch (Exception e) when (e is PmacLinkException or PmacErrorException)
            {
                faulty.Down = false;
                if (session.State == SessionState.Idle)
                {
                    session = NewSession();
                    started = false;
                }
                else
                {
                    started = true;
                }
            }

            if (started && session.State == SessionState.Completed)
            {
                break;
            }

            if (startStorm)
            {
                var inStart = sink.Last is not { Started: true };
                faulty.FaultRate = inStart ? 0.2 : 0.03;
                faulty.KillRate = inStart ? 0.12 : 0.006;
            }

            sim.Advance(TimeSpan.FromSeconds(tickSeconds));
        }

        sim.RunUntilIdle(TimeSpan.FromHours(1));
        session.State.Should().Be(SessionState.Completed, $"seed {seed} ({strategy}): {session.Status.Message}");
        var executed = new List<int>();
        foreach (var m in sim.ExecutedMoves)
        {
            if (m.SourceLine > 0 && (executed.Count == 0 || executed[^1] != m.SourceLine))
            {
                executed.Add(m.SourceLine);
            }
        }

        var expected = program.TrackedLines().Where(l => plan is null || l >= plan.Line).ToList();
        var k = 0;
        while (k < Math.Min(expected.Count, executed.Count) && expected[k] == executed[k])
        {
            k++;
        }

        var where = k < Math.Max(expected.Count, executed.Count)
            ? $"first difference at block {k}: expected ..{string.Join(",", expected.Skip(Math.Max(0, k - 3)).Take(6))}.. executed ..{string.Join(",", executed.Skip(Math.Max(0, k - 3)).Take(6))}..; events: {string.Join(" | ", log.TakeLast(12))}"
            : string.Empty;
        executed.Should().Equal(expected, $"seed {seed} ({strategy}): 0 lost, 0 repeated, 0 reordered; {where}");

        // Every program line, motion or not: the simulator's log of rotary lines against the chunk bodies as sent.
        bool IsMotion(string t) => program.Classify(t) is { } l && (l.IsMotion || l.TrackedLine > 0);
        var from = plan is null ? new StreamPosition(1, 0) : program.PositionOfBlock(plan.Line)!.Value;
        var sent = (plan?.PmacLines ?? []).Concat(Enumerable.Range(from.Chunk, program.TotalChunks - from.Chunk + 1)
            .SelectMany(c => program.Body(c).Skip(c == from.Chunk ? from.Line : 0)).Select(l => l.Text)).ToList();
        var ran = sim.ExecutedRotaryLines.Select(l => l.Text).ToList();
        var (motion, nonMotion) = LineAccounting.Compare(sent, ran, IsMotion);
        if (probe is not null && !(motion.Exact && nonMotion.Exact))
        {
            throw new Xunit.Sdk.XunitException($"seed {seed} ({strategy}): motion {motion}, non-motion {nonMotion}; events: {string.Join(" | ", log.TakeLast(12))}");
        }

        Directory.Delete(folder, true);
        return (faulty.Injected, kills, faults, motion, nonMotion, sent.Count(t => !IsMotion(t)), plan is not null);
    }
}
