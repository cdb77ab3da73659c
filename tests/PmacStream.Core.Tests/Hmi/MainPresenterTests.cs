using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Pmac;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>The presenter's logic against a fake view and a fake core (the simulator tests are in HmiSimulatorTests).</summary>
public sealed class MainPresenterTests : IAsyncLifetime
{
    private readonly TestFolder _temp = new("hmi");
    private readonly FakeView _view = new();
    private readonly FakeBackend _backend = new();
    private readonly HmiLogSink _sink = new();
    private MainPresenter _p = null!;

    public Task InitializeAsync()
    {
        _p = new MainPresenter(_view, _backend, _sink, Logger());
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _p.DisposeAsync();
        _temp.Dispose();
    }

    // The form configures the global logger with the sink; tests give the presenter its own so they stay independent.
    private Serilog.ILogger Logger() => new Serilog.LoggerConfiguration().WriteTo.Hmi(_sink).CreateLogger().ForContext<MainPresenter>();

    private string Program(int lines, Func<int, string>? text = null) =>
        TestPrograms.Write(Path.Combine(_temp.Path, "part.nc"), TestPrograms.Text(string.Empty, lines, text ?? (i => $"N{i} G1 X{i}.5 Y{i % 7}"), footer: string.Empty));

    private async Task Do(Action action)
    {
        action();
        await _p.WhenIdleAsync();
    }

    private async Task ReadyToRun(int lines = 100, int blocksPerChunk = 30)
    {
        await Do(() => _view.ChooseFile(Program(lines)));
        await Do(_view.ClickConnect);
        _view.BlocksPerChunk = blocksPerChunk;
        await Do(_view.ClickSplit);
        _view.Errors.Should().BeEmpty();
    }

    private async Task TickUntilFinished(int maxTicks = 10_000)
    {
        for (var i = 0; i < maxTicks && _p.JobActive; i++)
        {
            await _p.TickAsync();
        }

        _p.JobActive.Should().BeFalse("the job should have finished");
    }

    [Fact]
    public void Starts_in_the_chosen_language_with_nothing_to_run()
    {
        _view.Texts[TextId.Execute].Should().Be("Execute");
        _view.Strategies.Should().Equal("chunk", "pr", "adaptive");
        _view.ConnectionState.Should().Be("Not connected");
        _view.Commands.Should().Be(CommandStates.None with { Connect = true, Open = true });
        _view.Status.TotalFiles.Should().Be("-");
    }

    [Fact]
    public async Task The_profile_is_chosen_on_screen_used_by_every_call_and_a_change_drops_the_check_and_split()
    {
        _view.Profiles.Should().Equal(PmacStream.GCode.MachineProfile.BuiltInNames);
        _view.SelectedProfile.Should().Be("fanuc-mill");
        await ReadyToRun();
        await Do(_view.ClickCheck);
        _view.Diagnostics.Should().BeEmpty();
        _backend.ProfilesUsed.Should().Contain(["toolpath fanuc-mill", "prepare fanuc-mill", "check fanuc-mill"]);
        _backend.LibrariesLoaded.Should().Equal("fanuc-mill");
        _view.ChunkFiles.Should().NotBeEmpty();

        _backend.ProfilesUsed.Clear();
        await Do(() => _view.ChooseProfile("grbl"));
        _view.Errors.Should().BeEmpty();
        _view.ChunkFiles.Should().BeEmpty("the split was made under the other profile");
        _view.Commands.Execute.Should().BeFalse("split again first");
        _backend.ProfilesUsed.Should().Equal("toolpath grbl");
        _backend.LibrariesLoaded.Should().Equal("fanuc-mill", "grbl");

        await Do(_view.ClickSplit);
        await Do(_view.ClickExecute);
        _backend.ProfilesUsed.Should().Contain(["prepare grbl", "start grbl"]);

        // A job runs under one profile: the selector goes back.
        await Do(() => _view.ChooseProfile("linuxcnc-mill"));
        _view.Errors.Should().ContainSingle().Which.Should().Contain("the machine profile can change between jobs");
        _view.SelectedProfile.Should().Be("grbl");
    }

    [Fact]
    public async Task A_program_stop_shows_the_banner_and_state_resume_continues_and_optional_stop_follows_the_box()
    {
        await ReadyToRun(100, 30);
        _backend.StopAt = new JobStop(40, "M00");
        _view.OptionalStop.Should().BeTrue("M01 stops unless the operator says otherwise");
        await Do(() => _view.ToggleOptionalStop(false));
        await Do(_view.ClickExecute);
        _backend.Started.Single().OptionalStop.Should().BeFalse();

        for (var i = 0; i < 100 && _p.JobStatus?.State != HmiJobState.Stopped; i++)
        {
            await _p.TickAsync();
        }

        _view.ProgramStopBanner.Should().Be("Program stop (M00) at line 40: Resume continues");
        _view.Status.State.Should().Be("Program stop (M00) at line 40");
        _view.Commands.Resume.Should().BeTrue();
        _view.Commands.Hold.Should().BeFalse("nothing moves to hold");
        _view.Commands.Abort.Should().BeTrue();
        await _p.TickAsync();
        _p.JobStatus!.CurrentLine.Should().Be(40, "it waits there");

        await Do(() => _view.ToggleOptionalStop(true));
        _backend.Jobs.Single().Commands.Should().Contain("optional-stop=True", "the switch changes live");
        await Do(_view.ClickResume);
        _backend.Jobs.Single().Commands.Should().EndWith("R");
        _view.ProgramStopBanner.Should().BeEmpty("the banner goes when the job runs on");
        await TickUntilFinished();
        _view.ProgramStopBanner.Should().BeEmpty();
    }

    [Fact]
    public async Task Open_shows_the_lines_on_demand_and_the_count()
    {
        await Do(() => _view.ChooseFile(Program(500)));
        await _p.Program!.Completion;
        await _p.TickAsync();

        _view.Errors.Should().BeEmpty();
        _view.ProgramLineCount.Should().Be(500);
        _view.ProgramRow(1).Should().Be("N1 G1 X1.5 Y1");
        _view.ProgramRow(500).Should().Be("N500 G1 X500.5 Y3");
        _view.ProgramRow(501).Should().BeEmpty();
        _view.Status.ProgramLines.Should().Be("500");
        _view.Commands.Check.Should().BeTrue();
        _view.Commands.Execute.Should().BeFalse("not connected, not split");
    }

    [Fact]
    public async Task Opening_a_missing_file_says_so()
    {
        await Do(() => _view.ChooseFile(Path.Combine(_temp.Path, "nope.nc")));

        _view.Errors.Should().ContainSingle().Which.Should().Contain("nope.nc").And.Contain("no such program file");
    }

    [Fact]
    public async Task Check_lists_errors_double_click_jumps_and_split_is_refused()
    {
        await Do(() => _view.ChooseFile(Program(50, i => i is 12 or 40 ? $"G1 X1 BAD{i}" : $"G1 X{i}")));
        await Do(_view.ClickCheck);

        _view.Diagnostics.Should().Equal("12:7  E  E101  illegal character 'B'", "40:7  E  E101  illegal character 'B'");
        await Do(() => _view.DoubleClickDiagnostic(1));
        _view.FocusedLine.Should().Be(40);
        _view.Log.Should().Contain(l => l.Contains("2 errors, 0 warnings, 50 blocks"));

        await Do(_view.ClickSplit);
        _view.Errors.Should().ContainSingle().Which.Should().Contain("part.nc:12:7: error E101");
        _view.ChunkFiles.Should().BeEmpty();
    }

    [Fact]
    public async Task Split_without_a_check_is_refused_by_the_gate_with_the_errors_listed()
    {
        await Do(() => _view.ChooseFile(Program(50, i => i == 12 ? "G1 X1 BAD" : $"G1 X{i}")));
        await Do(_view.ClickSplit);

        _view.Errors.Should().ContainSingle().Which.Should().Contain("part.nc:12:7: error E101");
        _view.Diagnostics.Should().Equal("12:7  E  E101  illegal character 'B'");
        await Do(() => _view.DoubleClickDiagnostic(0));
        _view.FocusedLine.Should().Be(12, "the refusal's list works like the check's");
        _view.ChunkFiles.Should().BeEmpty();
        Directory.Exists(Path.Combine(_temp.Path, "part_chunks")).Should().BeFalse();
    }

    [Fact]
    public async Task Lines_per_chunk_and_window_start_from_the_settings_and_bind_to_the_next_job()
    {
        await _p.DisposeAsync();
        var view = new FakeView();
        var settings = RunSettings.Default with { BlocksPerChunk = 40, WindowStart = 0.5, WindowEnd = 0.8, TickPeriod = TimeSpan.FromMilliseconds(25) };
        _p = new MainPresenter(view, _backend, _sink, Logger(), settings);
        view.BlocksPerChunk.Should().Be(40);
        view.DownloadWindow.Should().Be((0.5, 0.8));
        _p.TickPeriod.Should().Be(TimeSpan.FromMilliseconds(25), "the form's timer ticks with the settings' period");

        await Do(() => view.ChooseFile(Program(100)));
        await Do(view.ClickConnect);
        view.BlocksPerChunk = 25;
        await Do(view.ClickSplit);
        _backend.Prepared.Single().BlocksPerChunk.Should().Be(25);
        view.ChunkFiles.Should().HaveCount(4);

        await Do(() => view.SetWindow(0.65, 0.75));
        view.Errors.Should().BeEmpty();
        await Do(view.ClickExecute);
        var started = _backend.Started.Single().Settings;
        (started.WindowStart, started.WindowEnd, started.BlocksPerChunk, started.TickPeriod).Should().Be((0.65, 0.75, 25, TimeSpan.FromMilliseconds(25)));
        view.Log.Should().Contain(l => l.Contains("Download window set to 0.65-0.75"));
    }

    [Fact]
    public async Task A_window_that_cannot_work_is_refused_and_the_control_shows_the_one_in_force()
    {
        await Do(() => _view.SetWindow(0.8, 0.7));
        _view.Errors.Should().ContainSingle().Which.Should().Contain("0.8-0.7");
        _view.DownloadWindow.Should().Be((0.6, 0.7));
        _p.Settings.Should().Be(RunSettings.Default);
    }

    [Fact]
    public async Task Check_messages_follow_the_language()
    {
        await Do(() => _view.ChooseFile(Program(5, i => i == 3 ? "BAD" : "G0 X0")));
        await Do(() => _view.ChooseLanguage(HmiLanguage.Chinese));
        await Do(_view.ClickCheck);

        _view.Texts[TextId.Execute].Should().Be("程序段执行");
        _view.Diagnostics.Single().Should().EndWith("非法字符 'B'");
    }

    [Fact]
    public async Task Split_fills_listbox1_and_selecting_a_chunk_shows_its_lines()
    {
        await ReadyToRun(lines: 100, blocksPerChunk: 30);

        _view.ChunkFiles.Should().Equal(
            "part_0001.pmc   lines 1–30   (30 blocks)",
            "part_0002.pmc   lines 31–60   (30 blocks)",
            "part_0003.pmc   lines 61–90   (30 blocks)",
            "part_0004.pmc   lines 91–100   (10 blocks)");
        _view.Status.TotalFiles.Should().Be("4");

        await Do(() => _view.SelectChunk(1));
        _view.ChunkLineCount.Should().Be(33);
        _view.ChunkRow(1).Should().Be("CLOSE");
        _view.ChunkRow(3).Should().Be("M0==31 N31 G1 X31.5 Y3 F(P500)");
        _view.FocusedLine.Should().Be(31, "the program list shows where the chunk starts");

        await Do(() => _view.ChooseLanguage(HmiLanguage.Chinese));
        _view.ChunkFiles[0].Should().Be("part_0001.pmc   第 1–30 行   （30 段）");
    }

    [Fact]
    public async Task A_program_opened_from_the_store_is_split_and_run_as_its_revision_and_a_plain_file_as_none()
    {
        await _p.OpenStoredAsync(7, Program(40), null);
        await Do(_view.ClickConnect);
        await Do(_view.ClickSplit);
        await Do(_view.ClickExecute);
        await TickUntilFinished();
        _backend.Started.Single().ProgramId.Should().Be(7, "the job history names the revision, as stream --program 7");
        _backend.PreparedRevisions.Should().Equal(7L);

        await Do(() => _view.ChooseFile(Program(40)));
        await Do(_view.ClickSplit);
        await Do(_view.ClickExecute);
        await TickUntilFinished();
        _backend.Started.Should().HaveCount(2);
        _backend.Started[1].ProgramId.Should().BeNull("a file opened from disk is no revision");
        _backend.PreparedRevisions.Should().Equal(7L, null);
    }

    [Fact]
    public async Task A_file_its_split_stored_runs_as_that_revision_until_the_profile_or_the_program_changes()
    {
        _backend.StoreFilesAs = (_, profile) => (profile.Name == "fanuc-mill" ? 12 : 13, null);
        await ReadyToRun(lines: 40);
        _view.Log.Should().Contain(l => l.Contains("(program 12 of the store)"));
        await Do(_view.ClickExecute);
        await TickUntilFinished();
        _backend.Started.Single().ProgramId.Should().Be(12, "the split found or stored the file as revision 12, as stream FILE does");
        _backend.PreparedRevisions.Should().Equal(new long?[] { null }, "a file is asked to be stored, not handed a revision");

        await Do(() => _view.ChooseProfile("linuxcnc-mill"));
        await Do(_view.ClickSplit);
        _view.SelectedLine = 10;
        await Do(_view.ClickStartFromLine);
        await TickUntilFinished();
        _backend.Started[1].FromLine.Should().Be(10);
        _backend.Started[1].ProgramId.Should().Be(13, "under another profile the file is another revision, found by the split again");
        _backend.PreparedRevisions.Should().Equal(new long?[] { null, null }, "each split of a file asks the store again");

        _backend.StoreFilesAs = null;
        await Do(() => _view.ChooseFile(Program(40)));
        await Do(_view.ClickSplit);
        await Do(_view.ClickExecute);
        await TickUntilFinished();
        _backend.Started[2].ProgramId.Should().BeNull("another program forgets the revision of the one before");
        _view.Errors.Should().BeEmpty();
    }

    [Fact]
    public async Task A_file_the_store_cannot_keep_still_runs_as_a_file_and_the_log_says_why()
    {
        _backend.StoreFilesAs = (_, _) => (null, "store sqlite:/shop/store.db: cannot import part.nc: database or disk is full");
        await ReadyToRun(lines: 40);
        _view.Log.Should().Contain(l => l.Contains("Not stored, run as a file") && l.Contains("disk is full"));
        await Do(_view.ClickExecute);
        await TickUntilFinished();
        _view.Errors.Should().BeEmpty();
        _backend.Started.Single().ProgramId.Should().BeNull("the job records no revision the store does not hold");
        _view.Status.State.Should().Be("Completed");
    }

    [Fact]
    public async Task Execute_runs_to_completion_with_the_highlight_following_m0()
    {
        await ReadyToRun(lines: 100, blocksPerChunk: 30);
        _view.Commands.Execute.Should().BeTrue();

        await Do(_view.ClickExecute);
        _view.Commands.Execute.Should().BeFalse();
        _view.Commands.Hold.Should().BeTrue();
        await TickUntilFinished();

        _backend.Started.Single().Should().Match<HmiJobRequest>(r => r.FromLine == null && r.Strategy == "chunk" && r.FeedOverride == 100);
        var highlighted = _view.ExecutingLines.Where(l => l > 0).ToList();
        highlighted.Should().BeInAscendingOrder().And.OnlyHaveUniqueItems();
        highlighted.Should().StartWith(7).And.EndWith(100);
        highlighted.Should().HaveCount(15, "one highlight per tick that moved (7 lines a tick, 100 lines)");
        _view.Status.State.Should().Be("Completed");
        _view.Status.ProgressPercent.Should().Be(100);
        _view.Status.CurrentFile.Should().Be("4/4  part_0004.pmc");
        _view.Log.Should().Contain(l => l.Contains("Job Completed at line 100"));
        _backend.Jobs.Single().Disposed.Should().BeTrue();
        _view.Commands.Execute.Should().BeTrue("a finished job frees the machine");
    }

    [Fact]
    public async Task Hold_stops_the_highlight_and_resume_continues()
    {
        await ReadyToRun();
        await Do(_view.ClickExecute);
        await _p.TickAsync();
        await _p.TickAsync();
        await Do(_view.ClickHold);
        var heldAt = _view.ExecutingLine;
        _view.Status.State.Should().Be("Held");
        _view.Commands.Resume.Should().BeTrue();
        _view.Commands.Hold.Should().BeFalse();

        for (var i = 0; i < 5; i++)
        {
            await _p.TickAsync();
        }

        _view.ExecutingLine.Should().Be(heldAt, "nothing moves while held");
        await Do(_view.ClickResume);
        await _p.TickAsync();
        _view.ExecutingLine.Should().Be(heldAt + 7);
        _backend.Jobs.Single().Commands.Should().Equal("H", "R");
        await TickUntilFinished();
    }

    [Fact]
    public async Task Abort_ends_the_job()
    {
        await ReadyToRun();
        await Do(_view.ClickExecute);
        await _p.TickAsync();
        await Do(_view.ClickAbort);

        _p.JobActive.Should().BeFalse();
        _view.Status.State.Should().Be("Aborted");
        _view.Commands.ResumeInterrupted.Should().BeTrue();
    }

    [Fact]
    public async Task Start_from_selected_line_asks_with_the_preamble_and_respects_the_answer()
    {
        await ReadyToRun();
        _view.SelectedLine = 0;
        await Do(_view.ClickStartFromLine);
        _view.Errors.Should().ContainSingle().Which.Should().Be("Select a program line first.");
        _view.Errors.Clear();

        _view.SelectedLine = 42;
        _view.ConfirmAnswer = false;
        await Do(_view.ClickStartFromLine);
        _view.Confirmations.Should().ContainSingle();
        _view.Confirmations[0].Text.Should().Contain("line 42").And.Contain("G21 G17 G90 G54").And.Contain("RAPID Z50 (to line 42)");
        _backend.Started.Should().BeEmpty("the operator said no");
        _p.JobActive.Should().BeFalse();
        _view.Log.Should().Contain(l => l.Contains("declined"));

        _view.ConfirmAnswer = true;
        await Do(_view.ClickStartFromLine);
        _backend.Started.Single().FromLine.Should().Be(42);
        await _p.TickAsync();
        _view.ExecutingLine.Should().Be(48);
        await TickUntilFinished();
        _view.ExecutingLines.Where(l => l > 0).Min().Should().BeGreaterThanOrEqualTo(41);
    }

    [Fact]
    public async Task Start_from_a_block_to_a_block_asks_with_the_range_and_passes_it_to_the_job()
    {
        await ReadyToRun();
        _view.SelectedLine = 42;
        _view.ToBlock = 60;
        _view.ConfirmAnswer = true;
        await Do(_view.ClickStartFromLine);
        _view.Confirmations.Single().Text.Should().Contain("line 42").And.Contain("ends after line 60");
        _backend.Started.Single().FromLine.Should().Be(42);
        _backend.Started.Single().ToLine.Should().Be(60, "the job service cuts the range (selected-block execution)");

        _view.ToBlock = null;
        await TickUntilFinished();
        await Do(_view.ClickStartFromLine);
        _backend.Started[1].ToLine.Should().BeNull("an empty \"to block\" runs to the program's end");
    }

    [Fact]
    public async Task The_preview_of_a_program_opened_from_the_store_reads_its_stored_blocks_and_a_file_s_the_file()
    {
        await _p.OpenStoredAsync(7, Program(40), null);
        _backend.StoredToolpaths.Should().Equal(7L);
        await Do(() => _view.ChooseFile(Program(40)));
        _backend.StoredToolpaths.Should().Equal([7L], "a file opened from disk is drawn from the file");
    }

    [Fact]
    public async Task Resume_after_interruption_continues_from_the_recorded_line()
    {
        await ReadyToRun(lines: 100, blocksPerChunk: 30);
        await Do(_view.ClickResumeInterrupted);
        _view.Errors.Should().ContainSingle().Which.Should().Be("No interrupted job recorded for this program.");
        _view.Errors.Clear();

        // A job that lost its link at line 64: the tick failure leaves it for "resume after interruption".
        await Do(_view.ClickExecute);
        for (var i = 0; i < 9; i++)
        {
            await _p.TickAsync();
        }

        _backend.Jobs[0].FailOnTick = new PmacLinkException("tcp 127.0.0.1:1025: connection reset");
        await _p.TickAsync();
        _p.JobActive.Should().BeFalse();
        _view.Status.State.Should().Be("Failed");
        _view.Errors.Should().ContainSingle().Which.Should().Contain("connection reset");
        _view.Errors.Clear();

        // The store recorded line 64 (chunk 3); the host restarts and the operator resumes.
        var manifest = _backend.Jobs[0].Status;
        manifest.CurrentLine.Should().Be(63);
        var split = _backend.Split(Path.Combine(_temp.Path, "part.nc"), 30);
        _backend.Interrupted = new InterruptedJobView(7, split, 64, 3, "chunk", DateTimeOffset.UtcNow);
        await _p.DisposeAsync();
        var view2 = new FakeView();
        _p = new MainPresenter(view2, _backend, _sink, Logger());
        view2.ChooseFile(Path.Combine(_temp.Path, "part.nc"));
        await _p.WhenIdleAsync();
        view2.ClickConnect();
        await _p.WhenIdleAsync();
        view2.ClickResumeInterrupted();
        await _p.WhenIdleAsync();

        view2.Errors.Should().BeEmpty();
        view2.Confirmations.Single().Text.Should().Contain("Resume job 7 at line 64 (file 3)");
        view2.ChunkFiles.Should().HaveCount(4, "the job's chunk files are listed again");
        _backend.Jobs[1].Status.CurrentLine.Should().Be(63, "nothing after the checkpoint is skipped");
        for (var i = 0; i < 100 && _p.JobActive; i++)
        {
            await _p.TickAsync();
        }

        view2.ExecutingLines.Where(l => l > 0).Should().StartWith(new[] { 63, 70 }, "the last executed line, then onwards").And.EndWith(100);
        view2.Status.State.Should().Be("Completed");
    }

    [Fact]
    public async Task The_feed_control_is_the_override_and_it_goes_to_the_job()
    {
        await ReadyToRun();
        _view.FeedOverride.Should().Be(100, "a job runs the programmed feeds as written unless the operator says otherwise");
        _view.Status.FeedOverride.Should().Be("100 %");
        await Do(() => _view.MoveFeedOverride(80));
        await Do(_view.ClickExecute);
        _backend.Started.Single().FeedOverride.Should().Be(80, "the override chosen before the start is set before the first block");

        await Do(() => _view.MoveFeedOverride(120));
        await Do(() => _view.MoveFeedOverride(999));
        _backend.Jobs[0].Commands.Should().Equal("%120", "%200");
        _view.Status.FeedOverride.Should().Be("200 %", "clamped to the control's 0-200 %");
        _view.Log.Should().Contain(l => l.Contains("Feed override set to 200 %"));
        await Do(_view.ClickAbort);
    }

    [Fact]
    public async Task The_override_holds_across_the_programs_feeds_and_the_status_shows_programmed_times_override()
    {
        await ReadyToRun();
        await Do(() => _view.MoveFeedOverride(80));
        await Do(_view.ClickExecute);
        var job = _backend.Jobs[0];
        job.ProgrammedFeed = 1000;
        await _p.TickAsync();
        _view.Status.Feed.Should().Be("F1000 × 80 % = 800");

        // The program's F1200 changes the programmed feed (P500), never the operator's override.
        job.ProgrammedFeed = 1200;
        await _p.TickAsync();
        _view.Status.Feed.Should().Be("F1200 × 80 % = 960");
        _view.FeedOverride.Should().Be(80, "the operator's setting holds");
        _view.Status.FeedOverride.Should().Be("80 %");

        // While the controller slews to a new setting the status shows both.
        job.ControllerOverride = 92.5;
        await Do(() => _view.MoveFeedOverride(60));
        job.ControllerOverride = 72.5;
        await _p.TickAsync();
        _view.Status.FeedOverride.Should().Be("72.5 % → 60 %");
        _view.Status.Feed.Should().Be("F1200 × 72.5 % = 870");
        _view.FeedOverride.Should().Be(60, "the control keeps the setting, not the slewing value");
        job.Commands.Should().Equal(["%60"], "showing the controller's value sends nothing back");
    }

    [Fact]
    public async Task The_download_window_is_shown_with_the_lines_of_the_executing_chunk()
    {
        await ReadyToRun(lines: 100, blocksPerChunk: 30);
        _view.Status.DownloadWindow.Should().Be("60–70 % of a file");
        await Do(() => _view.SetWindow(0.5, 0.6));
        _view.Status.DownloadWindow.Should().Be("50–60 % of a file");
        await Do(_view.ClickExecute);
        await _p.TickAsync();
        _view.Status.DownloadWindow.Should().Be("50–60 %: file 2 at lines 15–18", "chunk 1 holds lines 1-30: M0 at 15-18 is 50-60 % into it");
        for (var i = 0; i < 4; i++)
        {
            await _p.TickAsync();
        }

        _view.Status.DownloadWindow.Should().Be("50–60 %: file 3 at lines 45–48");
        await Do(() => _view.SetWindow(0.7, 0.8));
        _view.Status.DownloadWindow.Should().StartWith("50–60 %", "a running job keeps the window it started with");
        await Do(_view.ClickAbort);
        _view.Status.DownloadWindow.Should().Be("70–80 % of a file", "the next job's window");
    }

    [Fact]
    public async Task The_chunk_lines_follow_execution_until_the_operator_looks_elsewhere()
    {
        await ReadyToRun(lines: 100, blocksPerChunk: 30);
        await Do(_view.ClickExecute);
        await _p.TickAsync();
        _view.SelectedChunk.Should().Be(0, "the executing chunk is selected in ListBox1");
        _p.ShownChunk.Should().Be(0);
        _view.ChunkLineCount.Should().Be(33);
        _view.ChunkRow(_view.ChunkExecutingLine).Should().StartWith("M0==7 ", "the highlighted row is the executing block's synchronous assignment");

        for (var i = 0; i < 4; i++)
        {
            await _p.TickAsync();
        }

        _view.ExecutingLine.Should().Be(35);
        _view.SelectedChunk.Should().Be(1, "execution entered chunk 2 and the list followed");
        _view.ChunkRow(_view.ChunkExecutingLine).Should().StartWith("M0==35 ");

        // The operator looks at chunk 4: the list stays there while chunk 2 and 3 execute.
        await Do(() => _view.SelectChunk(3));
        _p.ChunkLinesFollow.Should().BeFalse();
        var focused = _view.FocusedLine;
        var selections = _view.SelectedChunks.Count;
        for (var i = 0; i < 5; i++)
        {
            await _p.TickAsync();
        }

        _view.ExecutingLine.Should().Be(70);
        _p.ShownChunk.Should().Be(3, "the operator's choice is kept");
        _view.SelectedChunks.Should().HaveCount(selections, "nothing moved ListBox1");
        _view.ChunkExecutingLine.Should().Be(0, "the executing block is not in the chunk shown");
        _view.FocusedLine.Should().Be(focused, "following never moves the operator's selection in ListBox2");

        // Selecting the executing chunk again follows again.
        await Do(() => _view.SelectChunk(2));
        _p.ChunkLinesFollow.Should().BeTrue();
        _view.ChunkRow(_view.ChunkExecutingLine).Should().StartWith("M0==70 ");

        // Looking ahead at chunk 4 again: following resumes when execution gets there.
        await Do(() => _view.SelectChunk(3));
        await TickUntilFinished();
        _p.ShownChunk.Should().Be(3);
        _p.ChunkLinesFollow.Should().BeTrue("execution reached the chunk the operator was looking at");
        _view.ChunkRow(_view.ChunkExecutingLine).Should().StartWith("M0==100 ");
    }

    [Fact]
    public async Task The_toolpath_pane_shows_the_planned_path_and_the_executed_part_grows()
    {
        // A square spiral: every line a feed move of its own, so the executed part grows line by line.
        await Do(() => _view.ChooseFile(Program(100, i => i == 1 ? "G21 G90 G01 X0 Y0 F500" : $"G01 X{(i % 2 == 0 ? i : -i)} Y{(i % 4 < 2 ? i : -i)}")));
        await Do(_view.ClickConnect);
        _view.BlocksPerChunk = 30;
        await Do(_view.ClickSplit);
        for (var i = 0; i < 200 && !_p.ToolpathReady; i++)
        {
            await _p.TickAsync();
            await Task.Delay(20);
        }

        _p.ToolpathReady.Should().BeTrue("the planned path is drawn in the background");
        var frame = _view.Toolpath!;
        (frame.Width, frame.Height).Should().Be((HmiLayout.ToolpathPane.Width, HmiLayout.ToolpathPane.Height));
        _view.ToolpathCaption.Should().Be("Toolpath of part.nc: 99 moves; executed in green, the tool at the red mark");
        var palette = new PmacStream.Preview.PreviewPalette();
        frame.CountPixels(palette.Feed).Should().BeGreaterThan(500, "the planned feed moves are drawn");
        frame.CountPixels(palette.Executed).Should().Be(0, "nothing executed yet");

        await Do(_view.ClickExecute);
        var executed = new List<int>();
        while (_p.JobActive)
        {
            await _p.TickAsync();
            executed.Add(frame.CountPixels(palette.Executed));
        }

        await _p.TickAsync();
        executed.Add(frame.CountPixels(palette.Executed));
        executed.Should().HaveCountGreaterThan(10);
        for (var i = 1; i < executed.Count; i++)
        {
            // Only the moving position marker may hide a few executed pixels from one tick to the next.
            executed[i].Should().BeGreaterThan(executed[i - 1] - 200, "the executed part only grows");
        }

        executed[1].Should().BeGreaterThan(0);
        executed[executed.Count / 2].Should().BeGreaterThan(executed[1] + 500);
        executed[^1].Should().BeGreaterThan(executed[executed.Count / 2] + 500, "it grew to the end");
        frame.CountPixels(palette.Marker).Should().BeGreaterThan(10, "the tool's position is marked");
        _p.ToolpathExecutedMoves.Should().Be(99, "every move drawn once, when its line had executed");
    }

    [Fact]
    public async Task Single_block_runs_one_line_per_resume()
    {
        await ReadyToRun();
        await Do(() => _view.ToggleSingleBlock(true));
        await Do(_view.ClickExecute);
        _backend.Started.Single().SingleBlock.Should().BeTrue();
        await _p.TickAsync();
        _view.ExecutingLine.Should().Be(0);
        _view.Commands.Resume.Should().BeTrue();

        await Do(_view.ClickResume);
        await Do(_view.ClickResume);
        _view.ExecutingLine.Should().Be(2);
        await Do(() => _view.ToggleSingleBlock(false));
        _backend.Jobs[0].Commands.Should().Equal("R", "R", "single=False");
        await _p.TickAsync();
        _view.ExecutingLine.Should().Be(9);
    }

    [Fact]
    public async Task Connection_failure_is_shown_and_nothing_runs()
    {
        _view.ConnectionSettings = new ConnectionSettings(DeviceKind.Ethernet, EthernetAddress: "unreachable");
        await Do(_view.ClickConnect);

        _view.Errors.Should().ContainSingle().Which.Should().Contain("connection refused");
        _view.ConnectionState.Should().Be("Not connected");
        _view.Commands.Connect.Should().BeTrue();

        _view.ConnectionSettings = new ConnectionSettings(DeviceKind.Simulator);
        await Do(_view.ClickConnect);
        _view.ConnectionState.Should().Be("Connected: fake");
        await Do(_view.ClickDisconnect);
        _backend.Connected.Should().BeFalse("Disconnect closes the link the backend holds");
    }

    [Fact]
    public async Task Ticks_do_not_overlap()
    {
        await ReadyToRun();
        await Do(_view.ClickExecute);
        var gate = new TaskCompletionSource();
        _backend.Jobs[0].TickGate = gate;
        var t1 = _p.TickAsync();
        var t2 = _p.TickAsync();

        t2.IsCompleted.Should().BeTrue("a tick that finds the previous one still busy is skipped");
        _backend.Jobs[0].TickCalls.Should().Be(1);
        gate.SetResult();
        await t1;
        _view.ExecutingLine.Should().Be(7);
    }
}
