using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// The presenter end to end: the real checker, splitter, streaming session and SQLite job store, talking to the simulated
/// Turbo PMAC in process. The test plays the form: it raises the view's events and calls the tick like timer1 does,
/// advancing the simulator's virtual clock between ticks.
/// </summary>
public sealed class HmiSimulatorTests : IAsyncLifetime
{
    private const double SecondsPerTick = 1.0;
    private readonly TestFolder _temp = new("hmi-sim");
    private readonly PmacSimulator _sim = new(new SimOptions { RecordRotaryLines = true });
    private readonly List<MainPresenter> _presenters = [];
    private string _source = string.Empty;

    /// <summary>This test's job store (never the user's ~/.pmacstream/jobs.db).</summary>
    private string JobDb => Path.Combine(_temp.Path, "jobs.db");

    public Task InitializeAsync()
    {
        _source = Path.Combine(_temp.Path, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, _source);
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        foreach (var p in _presenters)
        {
            await p.DisposeAsync();
        }

        _sim.Dispose();
        _temp.Dispose();
    }

    /// <summary>A fresh "process": backend, presenter and view, with the simulator as its controller.</summary>
    private (MainPresenter P, FakeView V) NewHmi()
    {
        // The job service the command line calls, with this test's simulator as the built-in one (its clock advanced by the test).
        var backend = new CoreHmiBackend(new JobService(new JobServiceOptions
        {
            Simulator = SimRig.BuiltIn(_sim, "hmi", step: false),
            JobDatabase = JobDb,
        }));
        var view = new FakeView();
        var sink = new HmiLogSink();
        var log = new Serilog.LoggerConfiguration().WriteTo.Hmi(sink).CreateLogger().ForContext<MainPresenter>();
        var p = new MainPresenter(view, backend, sink, log);
        _presenters.Add(p);
        return (p, view);
    }

    private static async Task Do(MainPresenter p, Action a)
    {
        a();
        await p.WhenIdleAsync();
    }

    private async Task<(MainPresenter P, FakeView V)> ReadyAsync()
    {
        var (p, v) = NewHmi();
        await Do(p, () => v.ChooseFile(_source));
        await Do(p, v.ClickConnect);
        await Do(p, v.ClickCheck);
        await Do(p, v.ClickSplit);
        v.Errors.Should().BeEmpty();
        return (p, v);
    }

    /// <summary>timer1_Tick, then let the controller run for a tick's worth of virtual time.</summary>
    private async Task Tick(MainPresenter p, int ticks = 1)
    {
        for (var i = 0; i < ticks; i++)
        {
            await p.TickAsync();
            _sim.Advance(TimeSpan.FromSeconds(SecondsPerTick));
            Ticks++;
        }
    }

    private async Task RunToEnd(MainPresenter p, int maxTicks = 40_000)
    {
        for (var i = 0; i < maxTicks && p.JobActive; i++)
        {
            await Tick(p);
        }

        p.JobActive.Should().BeFalse("the job should have finished");

        // The job is complete once M0 names the last block; let the controller finish that move.
        _sim.RunUntilIdle(TimeSpan.FromHours(1));
    }

    private int Ticks { get; set; }

    private List<int> TrackedLines() => ChunkedProgram.Open(Splitter.DefaultOutDir(_source)).TrackedLines().ToList();

    /// <summary>Source lines of the executed moves, repeats of one block folded, preamble moves (line 0) left out.</summary>
    private List<int> ExecutedLines() => MoveLines.Blocks(_sim.ExecutedMoves, ChunkedProgram.Open(Splitter.DefaultOutDir(_source)));

    [Fact]
    public async Task Open_and_check_a_program_with_errors_lists_them_and_split_is_refused()
    {
        var bad = Path.Combine(_temp.Path, "bad.nc");
        File.WriteAllText(bad, "O1\nN10 G21 G90\nN20 G01 X10 Y10 F500\nN30 G01 X20 X30\nN40 G02 X40 Y10\nN50 M30\n");
        var (p, v) = NewHmi();
        await Do(p, () => v.ChooseFile(bad));
        await Do(p, v.ClickCheck);

        v.Diagnostics.Should().Contain(d => d.StartsWith("4:", StringComparison.Ordinal) && d.Contains("  E  "), "two X words in one block");
        v.Diagnostics.Should().Contain(d => d.StartsWith("5:", StringComparison.Ordinal) && d.Contains("  E  "), "an arc without R or I/J");
        var index = v.Diagnostics.ToList().FindIndex(d => d.StartsWith("5:", StringComparison.Ordinal));
        await Do(p, () => v.DoubleClickDiagnostic(index));
        v.FocusedLine.Should().Be(5);

        await Do(p, v.ClickSplit);
        v.Errors.Should().ContainSingle().Which.Should().Contain("bad.nc:4:");
        Directory.Exists(Splitter.DefaultOutDir(bad)).Should().BeFalse("nothing is split");
    }

    [Fact]
    public async Task Split_refuses_a_program_with_profile_errors_although_no_check_ran()
    {
        // Two codes of one modal group in a block and an unknown code: errors under the machine profile only.
        var bad = Path.Combine(_temp.Path, "bad.nc");
        File.WriteAllText(bad, "G21 G90\nG01 X10 Y10 F500\nG00 G01 X20\nG77 X30\nM30\n");
        var (p, v) = NewHmi();
        await Do(p, () => v.ChooseFile(bad));
        await Do(p, v.ClickConnect);
        await Do(p, v.ClickSplit);

        v.Errors.Should().ContainSingle().Which.Should().Contain("bad.nc:3:");
        v.Diagnostics.Should().HaveCount(2).And.Contain(d => d.StartsWith("3:", StringComparison.Ordinal)).And.Contain(d => d.StartsWith("4:", StringComparison.Ordinal) && d.Contains("E104"));
        Directory.Exists(Splitter.DefaultOutDir(bad)).Should().BeFalse("nothing is split");
        v.Commands.Execute.Should().BeFalse("nothing to run");
        _sim.ExecutedMoves.Should().BeEmpty();
    }

    [Fact]
    public async Task Split_refuses_codes_the_controller_cannot_run_yet_listing_each()
    {
        var toolChange = Path.Combine(_temp.Path, "tc.nc");
        File.WriteAllText(toolChange, "G21 G90\nG16\nG00 X0 Y0\nG01 X10 F500\nG63\nM30\n");
        var (p, v) = NewHmi();
        await Do(p, () => v.ChooseFile(toolChange));
        await Do(p, v.ClickSplit);

        v.Errors.Should().ContainSingle().Which.Should().Be(
            "The controller cannot run G16 (line 2), G63 (line 5) yet under profile fanuc-mill: the PMAC would skip each code and run the rest of its block");
        v.Diagnostics.Should().HaveCount(2).And.OnlyContain(d => d.Contains("  E  E127  "));
        v.Diagnostics[0].Should().StartWith("2:1  E  E127  G16 (polar coordinate command) cannot run on the controller yet");
        v.Commands.Execute.Should().BeFalse("nothing to run");
    }

    [Fact]
    public async Task A_program_stop_is_shown_waits_without_underruns_and_resume_continues_on_the_simulator()
    {
        var stops = Path.Combine(_temp.Path, "stops.nc");
        var lines = new List<string> { "G21 G90 G17", "G00 X0 Y0", "G01 F300" }; // 0.2 s and more a move: a 1 s tick keeps the buffer fed
        for (var i = 1; i <= 120; i++)
        {
            lines.Add($"G01 X{i % 12} Y{i / 12}");
            if (i == 50)
            {
                lines.Add("M00"); // line 54
            }
            else if (i == 90)
            {
                lines.Add("M01"); // line 95
            }
        }

        File.WriteAllLines(stops, [.. lines, "M30"]);
        _source = stops;
        var (p, v) = NewHmi();
        await Do(p, () => v.ChooseFile(stops));
        await Do(p, v.ClickConnect);
        v.BlocksPerChunk = 40;
        await Do(p, v.ClickSplit);
        await Do(p, v.ClickExecute);
        v.Errors.Should().BeEmpty();

        foreach (var (line, code) in new[] { (54, "M00"), (95, "M01") })
        {
            for (var i = 0; i < 2000 && p.JobStatus?.State != HmiJobState.Stopped; i++)
            {
                await Tick(p);
            }

            v.ProgramStopBanner.Should().Be($"Program stop ({code}) at line {line}: Resume continues");
            v.Status.State.Should().Be($"Program stop ({code}) at line {line}");
            v.ExecutingLine.Should().Be(line, "the stop block is highlighted");
            v.Commands.Resume.Should().BeTrue();
            v.Commands.Hold.Should().BeFalse();
            var moves = _sim.ExecutedMoves.Count;
            await Tick(p, 50);
            _sim.ExecutedMoves.Count.Should().Be(moves, "the machine waits at the stop");
            p.JobStatus!.State.Should().Be(HmiJobState.Stopped);
            _sim.Counters.Underruns.Should().Be(0);

            await Do(p, v.ClickResume);
            v.Errors.Should().BeEmpty();
            await Tick(p, 2);
            v.ProgramStopBanner.Should().BeEmpty();
        }

        await RunToEnd(p);
        v.Status.State.Should().Be("Completed");
        ExecutedLines().Should().Equal(TrackedLines(), "every block once, in order, the stops among them");
        v.Log.Should().Contain(l => l.Contains("Program stop (M00) at line 54: Resume continues"));
    }

    [Fact]
    public async Task Execute_runs_every_block_once_with_the_highlight_following_m0()
    {
        var (p, v) = await ReadyAsync();
        v.ChunkFiles.Should().HaveCount(4);
        await Do(p, v.ClickExecute);
        v.Errors.Should().BeEmpty();
        await RunToEnd(p);

        v.Errors.Should().BeEmpty();
        v.Status.State.Should().Be("Completed");
        v.Status.ProgressPercent.Should().Be(100);
        var expected = TrackedLines();
        ExecutedLines().Should().Equal(expected, "every block executes exactly once, in order");
        Ticks.Should().BeGreaterThan(100);
        var highlighted = v.ExecutingLines.Where(l => l > 0).ToList();
        highlighted.Should().BeInAscendingOrder("the highlight only moves forward with M0");
        highlighted.Should().HaveCountGreaterThan(100, "the highlight followed the job, not only its end");
        highlighted.Should().OnlyContain(l => expected.Contains(l), "M0 only ever names motion blocks");
        highlighted[^1].Should().Be(expected[^1]);
        v.Status.CurrentFile.Should().StartWith("4/4");
        v.Log.Should().Contain(l => l.Contains("Job Completed"));
    }

    [Fact]
    public async Task Execute_while_another_program_runs_is_refused_and_leaves_its_feed_alone()
    {
        var (p, v) = await ReadyAsync();
        var pendant = _sim.OpenPort("pendant");
        foreach (var line in new[] { "P500=123", "&1 %90", "OPEN PROG 7 CLEAR", "LINEAR", "F600", "X100", "X0", "CLOSE", "&1 B7 R" })
        {
            pendant.ExecuteText(line).Should().NotContain("ERR", line);
        }

        _sim.Advance(TimeSpan.FromSeconds(1));
        v.FeedOverride = 40;
        await Do(p, v.ClickExecute);

        v.Errors.Should().ContainSingle().Which.Should().Contain("running a program");
        p.JobActive.Should().BeFalse();
        pendant.ExecuteText("P500").Should().StartWith("123", "the feed variable belongs to the program that is running");
        pendant.ExecuteText("&1 %").Should().StartWith("90", "so does the coordinate system's feed override");
        _sim.Advance(TimeSpan.FromSeconds(30));
        _sim.ExecutedMoves.Should().HaveCount(2, "the other program ran to its end");
    }

    [Fact]
    public async Task Hold_stops_motion_and_resume_continues_without_losing_a_block()
    {
        var (p, v) = await ReadyAsync();
        await Do(p, v.ClickExecute);
        await Tick(p, 200);
        await Do(p, v.ClickHold);
        v.Status.State.Should().Be("Held");
        await Tick(p, 10);
        var heldAt = v.ExecutingLine;
        var moves = _sim.Counters;
        await Tick(p, 40);

        v.ExecutingLine.Should().Be(heldAt, "nothing moves while held");
        _sim.Counters.MovesExecuted.Should().Be(moves.MovesExecuted);
        await Do(p, v.ClickResume);
        v.Status.State.Should().Be("Running");
        await RunToEnd(p);

        ExecutedLines().Should().Equal(TrackedLines());
        v.Status.State.Should().Be("Completed");
    }

    [Fact]
    public async Task Start_from_selected_line_shows_the_preamble_and_obeys_the_answer()
    {
        var (p, v) = await ReadyAsync();
        var tracked = TrackedLines();
        var from = tracked[1500];
        v.SelectedLine = from;
        var received = _sim.Counters.LinesReceived;

        v.ConfirmAnswer = false;
        await Do(p, v.ClickStartFromLine);
        v.Confirmations.Should().ContainSingle();
        var text = v.Confirmations[0].Text;
        text.Should().Contain($"line {from}").And.Contain("G17 G54").And.Contain("G90 G00 Z10").And.Contain("M03");

        // The unified preamble: exactly what the CLI's planner gives for this line (modal state, retract to the safe
        // Z, rapid in XY, feed down, then distance mode, motion mode and feed), in work coordinates.
        var manifest = ChunkManifest.Load(Path.Combine(Splitter.DefaultOutDir(_source), ChunkManifest.FileName));
        var plan = StartFromLine.Plan(_source, from, StartPlanOptions.For(manifest));
        text.Should().Contain(string.Join(Environment.NewLine, plan.GCode));
        var g = plan.GCode.ToList();
        var retract = g.FindIndex(l => l.StartsWith("G90 G00 Z", StringComparison.Ordinal));
        g[retract + 1].Should().StartWith("G00 X", "rapid in XY after the retract");
        g[retract + 2].Should().StartWith("G01 Z", "then feed down to the block's start");
        g.Take(retract).Should().Contain(l => l.Contains("M03", StringComparison.Ordinal)).And.Contain("M08").And.NotContain("T1");
        p.JobActive.Should().BeFalse();
        _sim.Counters.LinesReceived.Should().Be(received, "a declined start sends nothing");

        v.ConfirmAnswer = true;
        await Do(p, v.ClickStartFromLine);
        v.Errors.Should().BeEmpty();
        await RunToEnd(p);
        _sim.ExecutedRotaryLines.Select(l => l.Text).Take(plan.PmacLines.Count).Should().Equal(plan.PmacLines, "the controller runs the plan's preamble first, as the CLI would send it");

        ExecutedLines().Should().Equal(tracked.SkipWhile(l => l < from), "from the chosen block to the end, each once");
        _sim.ExecutedMoves.First().SourceLine.Should().Be(0, "the preamble's approach runs first");
        v.Status.State.Should().Be("Completed");
    }

    [Fact]
    public async Task Resume_after_a_host_crash_continues_from_the_job_store_without_losing_or_repeating()
    {
        var (p, v) = await ReadyAsync();
        await Do(p, v.ClickExecute);
        while (v.ExecutingLine < 1500)
        {
            await Tick(p);
        }

        // The host dies: no abort, no goodbye. The controller runs on with what is in its rotary buffer.
        _presenters.Remove(p);
        _sim.Advance(TimeSpan.FromSeconds(20));
        using (var store = JobStore.Open(JobDb))
        {
            // The record `pmacstream resume --job-db` reads: program, split, strategy, connection and the last checkpoint.
            var job = store.LatestUnfinished();
            job.Should().NotBeNull();
            job!.ProgramPath.Should().Be(_source);
            job.ManifestPath.Should().Be(Path.Combine(Splitter.DefaultOutDir(_source), ChunkManifest.FileName));
            job.Strategy.Should().Be(StrategyKind.Chunk);
            job.Connection.Should().Be("sim");
            job.Checkpoint!.LastExecutedLine.Should().BeGreaterThanOrEqualTo(1500);
            job.Checkpoint.State.Should().Be(SessionState.Running);
        }

        var (p2, v2) = NewHmi();
        await Do(p2, () => v2.ChooseFile(_source));
        await Do(p2, v2.ClickConnect);
        v2.Commands.ResumeInterrupted.Should().BeTrue();
        await Do(p2, v2.ClickResumeInterrupted);
        v2.Errors.Should().BeEmpty();
        v2.Confirmations.Single().Text.Should().Contain("Resume job").And.Contain("(file 2)");
        v2.ChunkFiles.Should().HaveCount(4, "the job's chunk files are shown again");
        await RunToEnd(p2);

        ExecutedLines().Should().Equal(TrackedLines(), "no block lost or repeated across the crash");
        v2.Status.State.Should().Be("Completed");
        await Do(p2, v2.ClickResumeInterrupted);
        v2.Errors.Should().ContainSingle().Which.Should().Be("No interrupted job recorded for this program.");
    }

    [Fact]
    public async Task The_feed_override_holds_across_the_programs_feeds_and_the_machine_runs_programmed_times_override()
    {
        var (p, v) = await ReadyAsync();
        await Do(p, () => v.MoveFeedOverride(50));
        await Do(p, v.ClickExecute);
        var shown = new HashSet<string>();
        var controls = new HashSet<double>();
        for (var i = 0; i < 3000 && p.JobActive && !(shown.Contains("F1200 × 50 % = 600") && shown.Contains("F900 × 50 % = 450")); i++)
        {
            await Tick(p);
            shown.Add(v.Status.Feed);
            controls.Add(v.FeedOverride);
        }

        // demo.nc programs F1200 and F900; paper-mode chunks carry them into P500, and the override scales them.
        shown.Should().Contain(["F1200 × 50 % = 600", "F900 × 50 % = 450"]);
        controls.Should().Equal([50.0], "the program's F words never move the operator's control");
        v.Status.FeedOverride.Should().Be("50 %");
        var pendant = _sim.OpenPort("pendant");
        pendant.ExecuteText("&1 %").Should().StartWith("50");
        var from = _sim.ExecutedMoves[0].StartTime + 2; // the override slews from 100 % in the first second
        for (var i = 0; i < 200 && !RunFeeds(from).Any(m => m.Programmed == 900); i++)
        {
            await Tick(p); // until an F900 move has finished
        }

        var half = RunFeeds(from);
        half.Select(m => m.Programmed).Should().Contain([1200.0, 900.0], "the programmed feeds reached the controller (P500)");
        half.Should().OnlyContain(m => Math.Abs(m.Actual - (m.Programmed * 0.5)) < m.Programmed * 0.01, "every move ran at programmed x 50 %");

        // A live change: &1 %150 at once, the program's feeds still its own.
        await Do(p, () => v.MoveFeedOverride(150));
        var changedAt = _sim.ExecutedMoves[^1].EndTime;
        await Tick(p, 20);
        var fast = RunFeeds(from: changedAt + 3);
        fast.Should().NotBeEmpty().And.OnlyContain(m => Math.Abs(m.Actual - (m.Programmed * 1.5)) < m.Programmed * 0.01, "programmed x 150 % after the slew");
        v.Status.FeedOverride.Should().Be("150 %");
        await Do(p, v.ClickAbort);
    }

    /// <summary>Programmed and actual feed (length over time, per minute) of the linear moves that started at or after <paramref name="from"/>.</summary>
    private List<(double Programmed, double Actual)> RunFeeds(double from) =>
        _sim.ExecutedMoves
            .Where(m => m.Kind == MoveKind.Linear && m.StartTime >= from && m.Length > 0.5 && m.Duration > 0)
            .Select(m => (m.Feed, m.Length / m.Duration * 60))
            .ToList();

    [Fact]
    public async Task Resume_refuses_a_program_changed_since_the_job_started()
    {
        var (p, v) = await ReadyAsync();
        await Do(p, v.ClickExecute);
        await Tick(p, 50);
        _presenters.Remove(p);
        File.AppendAllText(_source, "N99999 G00 Z50.\n");

        var (p2, v2) = NewHmi();
        await Do(p2, () => v2.ChooseFile(_source));
        await Do(p2, v2.ClickConnect);
        var received = _sim.Counters.LinesReceived;
        await Do(p2, v2.ClickResumeInterrupted);

        v2.Errors.Should().ContainSingle().Which.Should().Contain("SHA-256");
        v2.Confirmations.Should().BeEmpty();
        p2.JobActive.Should().BeFalse();
        _sim.Counters.LinesReceived.Should().Be(received, "nothing is sent for a refused resume");
    }

    [Fact]
    public async Task A_job_recorded_by_the_cli_is_found_and_resumed_by_the_hmi()
    {
        var (p, v) = await ReadyAsync();
        var program = ChunkedProgram.Open(Splitter.DefaultOutDir(_source));
        var tracked = TrackedLines();
        var line = tracked[1200];
        long id;
        using (var store = JobStore.Open(JobDb))
        {
            // What `pmacstream stream --job-db` writes, with the controller since reset (it no longer holds the job).
            id = store.CreateJob(_source, program.Manifest.SourceSha256, Path.Combine(program.Folder, ChunkManifest.FileName), StrategyKind.Pr, "sim", null);
            var chunk = program.ChunkOfTracked(line);
            store.SaveCheckpoint(id, new Checkpoint(line, chunk, new StreamPosition(chunk + 1, 1), true, chunk, SessionState.Running, DateTimeOffset.UtcNow), durable: true);
        }

        await Do(p, v.ClickResumeInterrupted);
        v.Errors.Should().BeEmpty();
        v.Confirmations.Single().Text.Should().Contain($"job {id} at line {line}");
        await RunToEnd(p);

        ExecutedLines().Should().Equal(tracked.SkipWhile(l => l < line), "from the checkpoint's block to the end, each once");
        v.Status.State.Should().Be("Completed");
        using (var store = JobStore.Open(JobDb))
        {
            store.Get(id)!.Checkpoint!.State.Should().Be(SessionState.Completed, "the HMI wrote its checkpoints to the CLI's job record");
            store.LatestUnfinished().Should().BeNull();
        }
    }

    [Fact]
    public async Task A_job_whose_start_broke_off_while_loading_is_loaded_again_with_its_recorded_preamble_and_probe()
    {
        var (p, v) = await ReadyAsync();
        var program = ChunkedProgram.Open(Splitter.DefaultOutDir(_source));
        var tracked = TrackedLines();
        var plan = StartFromLine.Plan(_source, tracked[900], StartPlanOptions.For(program.Manifest));
        var preamble = new[] { "P901=42" }.Concat(plan.PmacLines).ToList();
        long id;
        using (var store = JobStore.Open(JobDb))
        {
            // What a host that died while loading its start leaves: the start recorded, a checkpoint taken while loading.
            id = store.CreateJob(_source, program.Manifest.SourceSha256, Path.Combine(program.Folder, ChunkManifest.FileName), StrategyKind.Chunk, "sim", plan.Line, "P777");
            store.RecordStart(id, new JobStart(plan.Line, preamble, "P777"));
            var at = program.PositionOfBlock(plan.Line)!.Value;
            store.SaveCheckpoint(id, new Checkpoint(0, at.Chunk, at, false, 0, SessionState.Idle, DateTimeOffset.UtcNow, Started: false, Loaded: false), durable: true);
        }

        await Do(p, v.ClickResumeInterrupted);
        v.Errors.Should().BeEmpty();
        await RunToEnd(p);

        ExecutedLines().Should().Equal(tracked.SkipWhile(l => l < plan.Line), "from the recorded start block to the end, each once");
        var ran = _sim.ExecutedRotaryLines.Select(l => l.Text.Trim()).ToList();
        ran.Take(preamble.Count).Should().Equal(preamble, "the recorded preamble runs first, once");
        ran.Should().Contain(t => t.StartsWith("P777=", StringComparison.Ordinal), "the job's lines carry its recorded probe");
        ran.Should().NotContain(t => t.StartsWith("P501=", StringComparison.Ordinal));
        using var check = JobStore.Open(JobDb);
        check.Get(id)!.Checkpoint!.State.Should().Be(SessionState.Completed);
    }
}
