using System.Globalization;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The host dies at every step of a start (clear, preamble, first chunk, run command), and at every step of the
/// reload after a first load broke off; a new session resumes from the job store (SQLite). Every preamble and program
/// line, motion or not, runs exactly once, in order, on the simulator.
/// </summary>
public class StartKillTests(ITestOutputHelper output)
{
    private static readonly double[] Fractions = [0, 0.5, 1];

    [Theory]
    [InlineData(true)]
    [InlineData(false)]
    public async Task A_host_killed_at_any_step_of_the_start_resumes_from_the_job_store_exactly_once(bool fromLine)
    {
        using var job = new Job(fromLine, seed: 11);
        var ops = await job.CountOpsAsync(breakAt: null);
        var cases = 0;
        for (var kill = 1; kill <= ops + 1; kill++)
        {
            foreach (var f in Fractions)
            {
                var r = await job.RunAsync(breakAt: null, killAt: kill, f);
                r.Killed.Should().BeTrue($"operation {kill} of {ops} is part of the start");
                cases++;
            }
        }

        output.WriteLine($"start {(fromLine ? "from a line behind a preamble" : "from the top")}: {ops} operations, {cases} kills, each resumed exactly once");
        cases.Should().BeGreaterThan(20);
    }

    [Theory]
    [InlineData(true)]
    [InlineData(false)]
    public async Task A_host_killed_while_reloading_after_a_broken_first_load_resumes_from_the_job_store_exactly_once(bool fromLine)
    {
        using var job = new Job(fromLine, seed: 23);
        var startOps = await job.CountOpsAsync(breakAt: null);
        var log = job.LastLog;
        var firstLoad = log.FindIndex(l => l.EndsWith(" OPEN ROT", StringComparison.Ordinal)) + 1;
        firstLoad.Should().BeGreaterThan(0);
        var cases = 0;

        // Break the link at each operation of the first load (OPEN ROT, CLEAR, CLOSE, preamble, first chunk).
        for (var brk = firstLoad; brk < startOps; brk++)
        {
            var recoveryOps = await job.CountOpsAsync(breakAt: brk) - brk;
            recoveryOps.Should().BeGreaterThan(3, $"break at {brk} ({log[brk - 1]}): recovery reloads");
            for (var kill = brk + 1; kill <= brk + recoveryOps + 1; kill++)
            {
                foreach (var f in Fractions)
                {
                    var r = await job.RunAsync(brk, kill, f);
                    r.Killed.Should().BeTrue();
                    cases++;
                }
            }
        }

        output.WriteLine($"reload {(fromLine ? "from a line behind a preamble" : "from the top")}: {cases} kills during recovery, each resumed exactly once");
        cases.Should().BeGreaterThan(40);
    }

    /// <summary>
    /// A job that started with another line-probe variable (P777) is resumed by a session configured with the default
    /// (P501): the resume reads the variable from the job record, and every line runs once. Resumed with P501 instead
    /// (the record altered), the same breaks repeat non-motion lines: the recorded variable is what makes it exact.
    /// </summary>
    [Fact]
    public async Task A_job_recorded_with_another_probe_variable_resumes_with_that_one()
    {
        using var job = new Job(fromLine: false, seed: 31, probe: "P777");
        await job.CountOpsAsync(breakAt: null);
        var downloads = job.LastLog.Select((l, i) => (l, Op: i + 1)).Where(x => x.l.Contains(" download ", StringComparison.Ordinal)).Select(x => x.Op).Skip(1).Take(2).ToList();
        downloads.Should().HaveCount(2, "later chunks are downloaded while the program runs");
        LineCounts recorded = default, wrong = default;
        var runs = 0;
        foreach (var op in downloads)
        {
            for (var f = 0.1; f < 0.95; f += 0.1)
            {
                job.AlterRecord = null;
                var r = await job.RunAsync(null, op, f);
                r.Killed.Should().BeTrue();
                job.ResumedProbe.Should().Be("P777");
                recorded += r.NonMotion;
                job.AlterRecord = rec => rec with { LineProbeVariable = "P501" };
                var w = await job.RunAsync(null, op, f, requireExact: false, stripProbe: true);
                job.ResumedProbe.Should().Be("P501");
                w.Motion.Exact.Should().BeTrue("M0 keeps motion exact either way");
                wrong += w.NonMotion;
                runs++;
            }
        }

        output.WriteLine($"{runs} kills mid-download: with the recorded probe non-motion {recorded}; with P501 instead {wrong}");
        recorded.Exact.Should().BeTrue();
        wrong.Repeated.Should().BeGreaterThan(0, "reading the wrong variable, the drain cannot see the non-motion lines that arrived");
    }

    /// <summary>One program, split; each run gets a fresh simulator and job database.</summary>
    private sealed class Job : IDisposable
    {
        private readonly string _folder;
        private readonly string _source;
        private readonly ChunkedProgram _program;
        private readonly StartPlan? _plan;
        private int _runs;

        public Job(bool fromLine, int seed, string? probe = "P501")
        {
            Probe = probe;
            _folder = Path.Combine(Path.GetTempPath(), "pmacstream-startkill", $"{fromLine}-{seed}-{Environment.ProcessId}");
            if (Directory.Exists(_folder))
            {
                Directory.Delete(_folder, true);
            }

            Directory.CreateDirectory(_folder);
            var r = new Random(seed);
            var sb = new StringBuilder("G21 G17 G90\nG00 X0 Y0\nF3000\nS1200 M03\nM08\n");
            for (var i = 0; i < 60; i++)
            {
                sb.Append((i % 7) switch
                {
                    2 => "M08\n",
                    4 => string.Create(CultureInfo.InvariantCulture, $"F{2000 + i}\n"),
                    6 => string.Create(CultureInfo.InvariantCulture, $"S{1000 + i} M03\n"),
                    _ => string.Create(CultureInfo.InvariantCulture, $"G01 X{r.Next(5)}.{r.Next(10)} Y{r.Next(5)}.{r.Next(10)}\n"),
                });
            }

            sb.Append("M09\nM30\n");
            _source = Path.Combine(_folder, "p.nc");
            File.WriteAllText(_source, sb.ToString());
            var split = Splitter.Split(_source, new SplitOptions { BlocksPerChunk = 20, OutDir = Path.Combine(_folder, "chunks") });
            _program = ChunkedProgram.Open(split.ManifestPath);
            if (fromLine)
            {
                var tracked = _program.TrackedLines().ToList();
                _plan = StartFromLine.Plan(_source, tracked[tracked.Count / 3], StartPlanOptions.For(split.Manifest));
                _program.PositionOfBlock(_plan.Line)!.Value.Line.Should().BeGreaterThan(0, "the start lies inside a chunk");
                _plan.PmacLines.Should().HaveCountGreaterThan(5);
            }
        }

        public List<string> LastLog { get; private set; } = [];

        /// <summary>The line probe the job starts with (the resuming session is created with the default, P501).</summary>
        public string? Probe { get; }

        /// <summary>Changes the record read back before the resume (null: as stored).</summary>
        public Func<JobRecord, JobRecord>? AlterRecord { get; set; }

        /// <summary>The resumed session's probe variable (after the last run).</summary>
        public string? ResumedProbe { get; private set; }

        /// <summary>Operations of the start (and of the recovery after a break) when nothing kills the host.</summary>
        public async Task<int> CountOpsAsync(int? breakAt)
        {
            var r = await RunAsync(breakAt, killAt: null, 0);
            r.Killed.Should().BeFalse();
            return r.StartOps;
        }

        public async Task<(bool Killed, int StartOps, LineCounts Motion, LineCounts NonMotion)> RunAsync(int? breakAt, int? killAt, double fraction, bool requireExact = true, bool stripProbe = false)
        {
            using var sim = new PmacSimulator(new SimOptions { RecordRotaryLines = true });
            var port = sim.OpenPort("host");
            SimRig.LoadLibrary(port);
            var conn = new ScriptedConnection(port) { BreakAt = breakAt, KillAt = killAt, KillFraction = fraction };
            var db = Path.Combine(_folder, $"jobs{++_runs}.db");
            using var store = JobStore.Open(db);
            var jobId = store.CreateJob(_source, _program.Manifest.SourceSha256, Path.Combine(_program.Folder, ChunkManifest.FileName), StrategyKind.Chunk, "sim", _plan?.Line, Probe);
            var options = new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = 8000 };
            var time = SimRig.Clock(sim);
            StreamingSession NewSession(string? probe = "P501") => new(conn, _program, options with { LineProbeVariable = probe }, store.SinkFor(jobId), time: time);
            var what = $"break at {breakAt}, kill at {killAt} ({fraction:0.0})";

            var session = NewSession(Probe);
            var killed = false;
            var startOps = 0;
            try
            {
                try
                {
                    await session.StartAsync(_plan?.Line, _plan?.PmacLines);
                }
                catch (PmacLinkException)
                {
                    if (session.State == SessionState.Idle)
                    {
                        await session.StartAsync(_plan?.Line, _plan?.PmacLines);
                    }
                    else
                    {
                        (await session.RecoverAsync()).Should().BeTrue(what);
                    }
                }

                startOps = conn.Ops;
                await RunToEndAsync(session, sim, what);
            }
            catch (HostKilledException)
            {
                // The host died: nothing of the session survives but the job store.
                killed = true;
                var record = store.Get(jobId)!;
                record.LineProbeVariable.Should().Be(Probe, "the job record keeps the start's line probe");
                session = NewSession();
                await session.ResumeAsync(AlterRecord?.Invoke(record) ?? record);
                ResumedProbe = session.Program.LineProbeVariable;
                await RunToEndAsync(session, sim, what);
            }

            LastLog = conn.Log;
            var isMotion = (string t) => _program.Classify(t) is { } l && (l.IsMotion || l.TrackedLine > 0);
            var from = _plan is null ? new StreamPosition(1, 0) : _program.PositionOfBlock(_plan.Line)!.Value;
            var sent = (_plan?.PmacLines ?? []).Concat(Enumerable.Range(from.Chunk, _program.TotalChunks - from.Chunk + 1)
                .SelectMany(c => _program.Body(c).Skip(c == from.Chunk ? from.Line : 0)).Select(l => l.Text)).ToList();
            var ran = sim.ExecutedRotaryLines.Select(l => l.Text).ToList();
            if (stripProbe)
            {
                // Compare the program lines without the probe assignments (lines sent after a resume with another
                // variable differ in it): what counts is which lines ran how often.
                static string Strip(string t) => System.Text.RegularExpressions.Regex.Replace(t.Trim(), @"^P\d+=\d+\s+", string.Empty);
                sent = sent.Select(Strip).ToList();
                ran = ran.Select(Strip).ToList();
            }

            var (motion, nonMotion) = LineAccounting.Compare(sent, ran, isMotion);
            if (requireExact && (!(motion.Exact && nonMotion.Exact) || ran.Count != sent.Count))
            {
                throw new Xunit.Sdk.XunitException(
                    $"{what}: motion {motion}, non-motion {nonMotion}, {ran.Count} lines ran of {sent.Count}; first ran: {string.Join(" | ", ran.Take(12))}; ops: {string.Join(" | ", conn.Log.Take(30))}");
            }

            return (killed, startOps, motion, nonMotion);
        }

        public void Dispose()
        {
            try
            {
                Directory.Delete(_folder, true);
            }
            catch (IOException)
            {
            }
        }

        private static async Task RunToEndAsync(StreamingSession session, PmacSimulator sim, string what)
        {
            for (var tick = 0; tick < 20_000 && session.State != SessionState.Completed; tick++)
            {
                await session.TickAsync();
                session.State.Should().NotBe(SessionState.Faulted, $"{what}: {session.Status.Message}");
                sim.Advance(TimeSpan.FromSeconds(0.1));
            }

            sim.RunUntilIdle(TimeSpan.FromHours(1));
            session.State.Should().Be(SessionState.Completed, $"{what}: {session.Status.Message}");
        }
    }
}
