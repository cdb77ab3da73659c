using System.Diagnostics;
using PmacStream.Hmi;
using Xunit.Abstractions;

namespace PmacStream.WinForms.UiTests;

/// <summary>
/// The operator's session on the real form: the win-x64 HMI under Wine in Xvfb, its real message loop and its real
/// <c>timer1</c> streaming <c>samples/demo.nc</c> into the built-in simulator (clock at 10x). The main path is
/// driven by real X input at the places <see cref="HmiLayout"/> gives; selecting a line or a chunk uses the form's
/// scripted mode. Every step waits (bounded) for what the screen shows and saves a screenshot.
/// </summary>
public sealed class HmiUnderWineTests(ITestOutputHelper output)
{
    private static readonly IReadOnlyDictionary<TextId, string> En = HmiText.All(HmiLanguage.English);
    private static readonly IReadOnlyDictionary<TextId, string> Zh = HmiText.All(HmiLanguage.Chinese);

    /// <summary>Gold, the executing row's background (MainForm.ExecutingBack).</summary>
    private const string ExecutingColour = "#FFD700";

    /// <summary>The toolpath pane's planned feed moves (PreviewPalette.Feed).</summary>
    private const string PlannedColour = "#1F4E9E";

    /// <summary>The toolpath pane's executed path (PreviewPalette.Executed).</summary>
    private const string ExecutedColour = "#78D678";

    // Status rows in HmiLayout.StatusRows order.
    private const int StateRow = 0, CurrentFileRow = 3, FeedOverrideRow = 6, FeedRow = 7, WindowRow = 8;

    [SkippableFact]
    public void The_operator_runs_holds_restarts_and_resumes_a_program_on_the_real_form()
    {
        var setup = UiTestSetup.Find();
        if (setup.MissingReason is { } why && UiTestSetup.Required)
        {
            throw new InvalidOperationException($"PMACSTREAM_UI_TEST_REQUIRED=1 but the UI test cannot run: {why}");
        }

        Skip.If(setup.MissingReason is not null, setup.MissingReason);

        var total = Stopwatch.StartNew();
        var folder = new TestFolder("ui");
        var work = folder.Path;
        try
        {
            Walkthrough(setup, work);
            output.WriteLine($"UI test: {total.Elapsed.TotalSeconds:0} s in all");
        }
        finally
        {
            folder.Dispose();
        }
    }

    private void Walkthrough(UiTestSetup setup, string work)
    {
        var shots = Environment.GetEnvironmentVariable("PMACSTREAM_UI_SCREENSHOTS") is { Length: > 0 } dir
            ? Path.GetFullPath(dir)
            : Path.Combine(RepoRoot.Path, "artifacts", "ui-test");
        Directory.CreateDirectory(shots);
        foreach (var old in Directory.EnumerateFiles(shots, "*.png"))
        {
            File.Delete(old);
        }

        var program = Path.Combine(work, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, program);
        var lines = File.ReadAllLines(program);
        var channel = Path.Combine(work, "channel");
        Directory.CreateDirectory(channel);

        using var x = XServer.Start();
        var prefix = WineHmi.EnsurePrefix(x.Display);
        output.WriteLine($"X display {x.Display}; Wine prefix {WineHmi.Prefix} {(prefix == TimeSpan.Zero ? "reused" : $"created in {prefix.TotalSeconds:0} s")}; screenshots in {shots}");
        var clock = Stopwatch.StartNew();
        // 10x: the demo lasts about 3 minutes of wall time, so the steps that need a running job (hold, look back, abort)
        // still find one on a loaded machine; at 20x a clean-clone run under load saw the job end before them.
        using var hmi = WineHmi.Start(setup.HmiExe, x.Display, channel, Path.Combine(work, "jobs.db"), "10x");
        var screen = new HmiScreen(channel, x.Display, shots, output);

        Step("the form comes up, its timer ticking");
        var s = screen.WaitFor("timer1 ticking", v => v.Ticks > 5, TimeSpan.FromMinutes(3));
        output.WriteLine($"  form up {clock.Elapsed.TotalSeconds:0.0} s after wine started");
        var window = screen.WaitForWindow(En[TextId.Title]);
        (window.Width, window.Height).Should().Be((ConsoleLayout.FormWidth, HmiLayout.ClientHeight + HmiLayout.StatusStripHeight), "the X window is the form's client area (no window manager, no frame)");
        (s.ClientX, s.ClientY).Should().Be((window.X, window.Y), "the form's client origin is where X put its window");
        s.Controls["btnConnect"].Enabled.Should().BeTrue();
        s.Controls["btnExecute"].Should().Be(new UiControl(En[TextId.Execute], false));
        s.Status[StateRow].Should().Be(En[TextId.StateIdle]);
        screen.Screenshot("01-start");

        Step("connect to the built-in simulator (real click)");
        screen.Click(HmiLayout.ConnectButton, HmiLayout.ConnectionGroup);
        s = screen.WaitFor("connected", v => v.Controls["btnDisconnect"].Enabled && !v.Controls["btnConnect"].Enabled);
        s.Controls["lblConnectionState"].Text.Should().Contain("simulator");
        s.Controls["grpFeed"].Text.Should().Be(En[TextId.FeedOverride], "the feed control is labelled as the feed override");
        s.Controls["lblFeed"].Text.Should().Be(En[TextId.FeedOverrideHint]);
        (s.Controls["numFeed"].Text, s.Controls["lblFeedUnit"].Text).Should().Be(("100", "%"));
        s.Status[FeedOverrideRow].Should().Be("100 %");
        (s.Controls["numWindowStart"].Text, s.Controls["numWindowEnd"].Text).Should().Be(("60", "70"), "the download window control shows the run settings' window");
        s.Status[WindowRow].Should().Be("60–70 % of a file");
        screen.Screenshot("02-connected");

        Step("open samples/demo.nc through the open dialog (real click, typed path, Return)");
        screen.Click(HmiLayout.OpenButton, HmiLayout.ProgramGroup);
        var title = screen.WaitFor("the open dialog", v => v.DialogTitle == En[TextId.Open].TrimEnd('…')).DialogTitle!;
        var dialog = screen.WaitForWindow(title);
        screen.PointAt(dialog.X + (dialog.Width / 2), dialog.Y + (dialog.Height / 2));
        screen.Type(WineHmi.WindowsPath(program));
        screen.Key("Return");
        s = screen.WaitFor("the program's lines listed", v => v.ProgramLineCount == lines.Length && v.Controls["lblPath"].Text == "demo.nc");
        s.Controls["btnCheck"].Enabled.Should().BeTrue();
        s.Status[2].Should().Be(lines.Length.ToString("N0", System.Globalization.CultureInfo.InvariantCulture));
        s = screen.WaitFor("the planned toolpath in its pane", v => v.Controls["lblToolpath"].Text.StartsWith("Toolpath of demo.nc: ", StringComparison.Ordinal) && v.Controls["lblToolpath"].Text.Contains("moves", StringComparison.Ordinal));
        var shot = screen.Screenshot("03-opened");
        HmiScreen.CountColour(shot, HmiLayout.ToolpathPane, PlannedColour).Should().BeGreaterThan(1000, "the pane shows the planned feed moves");
        HmiScreen.CountColour(shot, HmiLayout.ToolpathPane, ExecutedColour).Should().Be(0, "nothing executed yet");

        Step("check (real click)");
        screen.Click(HmiLayout.CheckButton, HmiLayout.ProgramGroup);
        s = screen.WaitFor("the check's summary in the log", v => v.LogTail.Any(l => l.Contains("Checked", StringComparison.Ordinal)) && v.Controls["btnSplit"].Enabled);
        s.Diagnostics.Should().NotContain(d => d.Contains("  E  ", StringComparison.Ordinal), "demo.nc has no errors");
        screen.Screenshot("04-checked");

        Step("split into 1000-block chunk files (real click)");
        screen.Click(HmiLayout.SplitButton, HmiLayout.ProgramGroup);
        s = screen.WaitFor("four chunk files in ListBox1", v => v.ChunkFiles.Count == 4);
        s.ChunkFiles[0].Should().StartWith("demo_0001.pmc");
        s.Controls["btnExecute"].Enabled.Should().BeTrue();
        screen.Script("select-chunk 1");
        s = screen.WaitFor("the second chunk's lines", v => v.ChunkLineCount > 1000 && v.SelectedChunk == 1);
        s.ChunkExecutingLine.Should().Be(0, "nothing executes yet");
        screen.Screenshot("05-split");

        Step("narrow the download window to 55-70 % (real typing in the window's start box)");
        screen.Click(HmiLayout.WindowStartBox, HmiLayout.ProgramGroup);
        screen.Key("End", "BackSpace", "BackSpace", "BackSpace");
        screen.Type("55");
        screen.Key("Return");
        s = screen.WaitFor("the window set", v => v.Status[WindowRow] == "55–70 % of a file");
        s.LogTail.Should().Contain(l => l.Contains("Download window set to 0.55-0.7", StringComparison.Ordinal));
        s.Controls["numWindowStart"].Text.Should().Be("55");

        Step("execute (real click) and follow the highlighted line in the program and in the chunk's lines");
        screen.Click(HmiLayout.ExecuteButton);
        s = screen.WaitFor("running", v => v.Status[StateRow] == En[TextId.StateRunning] && v.ExecutingLine > 0);
        var seen = new List<int>();
        var chunksFollowed = new HashSet<int>();
        s = screen.WaitFor("execution in the second chunk, past line 1480", v =>
        {
            if (v.ExecutingLine > 0 && (seen.Count == 0 || seen[^1] != v.ExecutingLine))
            {
                v.ExecutingLine.Should().BeGreaterThanOrEqualTo(seen.LastOrDefault(), "the executing line never goes back");
                v.ExecutingLine.Should().BeInRange(v.TopLine, v.TopLine + v.VisibleLines, "the executing line is kept in view");
                v.ExecutingRowText.Should().Be(lines[v.ExecutingLine - 1], "the highlighted row shows that line of the program");
                if (v.ChunkExecutingLine > 0 && v.Status[CurrentFileRow].StartsWith($"{v.SelectedChunk + 1}/", StringComparison.Ordinal))
                {
                    // The chunk's lines follow: its row with the executing block's synchronous assignment, in view.
                    v.ChunkExecutingRowText.Should().Contain($"M0=={v.ExecutingLine}", "the highlighted chunk row is the executing block's");
                    v.ChunkExecutingLine.Should().BeInRange(v.ChunkTopLine, v.ChunkTopLine + v.ChunkVisibleLines, "the chunk's executing row is kept in view");
                    chunksFollowed.Add(v.SelectedChunk);
                }

                seen.Add(v.ExecutingLine);
            }

            return v.ExecutingLine >= 1480;
        }, TimeSpan.FromSeconds(180));
        seen.Count.Should().BeGreaterThan(10, "the highlight followed M0 through many lines");
        chunksFollowed.Should().Contain([0, 1], "the chunk lines followed execution from the first file into the second");
        s.Status[CurrentFileRow].Should().StartWith("2/4", "the current chunk file is the second");
        s.Status[WindowRow].Should().StartWith("55–70 %: file 3 at lines ", "the status names the lines where the next file goes");
        s.Status[FeedRow].Should().MatchRegex(@"^F\d+ × 100 % = [\d.]+$", "programmed feed x override = resulting feed");
        shot = screen.ScreenshotWhenPainted("06-executing", png =>
            HmiScreen.CountColour(png, HmiLayout.ProgramLinesList, ExecutingColour) > 200 && HmiScreen.CountColour(png, HmiLayout.ChunkLinesList, ExecutingColour) > 200);
        HmiScreen.CountColour(shot, HmiLayout.ProgramLinesList, ExecutingColour).Should().BeGreaterThan(200, "the executing row is highlighted on the screen");
        HmiScreen.CountColour(shot, HmiLayout.ChunkLinesList, ExecutingColour).Should().BeGreaterThan(200, "so is the executing row of the chunk's lines");

        Step("hold (real click): the line stops");
        var executedPixels = HmiScreen.CountColour(shot, HmiLayout.ToolpathPane, ExecutedColour);
        executedPixels.Should().BeGreaterThan(300, "the executed part is drawn over the planned toolpath");
        File.Copy(shot, Path.Combine(shots, "hmi-screen.png"), overwrite: true);
        s = screen.ClickUntil("held", HmiLayout.HoldButton, v => v.Status[StateRow] == En[TextId.StateHeld] && v.Controls["btnResume"].Enabled);
        // A hold slews the override to 0 (Isx95), so the move in progress decelerates before the line stands still.
        var held = screen.WaitTicks(10).ExecutingLine;
        var stopping = Stopwatch.StartNew();
        for (var next = screen.WaitTicks(10).ExecutingLine; next != held; next = screen.WaitTicks(10).ExecutingLine)
        {
            stopping.Elapsed.Should().BeLessThan(TimeSpan.FromSeconds(20), "a held job comes to a stop");
            held = next;
        }

        screen.WaitTicks(20).ExecutingLine.Should().Be(held, "nothing moves while held (20 more ticks of timer1)");
        screen.Screenshot("07-held");

        Step("resume (real click): the line moves on");
        screen.Click(HmiLayout.ResumeButton);
        s = screen.WaitFor("running past the held line", v => v.Status[StateRow] == En[TextId.StateRunning] && v.ExecutingLine > held + 20);
        shot = screen.Screenshot("08-resumed");
        HmiScreen.CountColour(shot, HmiLayout.ToolpathPane, ExecutedColour).Should().BeGreaterThan(executedPixels, "the executed part grows as M0 advances");

        Step("set the feed override to 50 % (real typing in the override box); the program's F words leave it alone");
        screen.Click(HmiLayout.FeedBox, HmiLayout.FeedGroup);
        screen.Key("End", "BackSpace", "BackSpace", "BackSpace", "BackSpace", "BackSpace", "BackSpace");
        screen.Type("50");
        screen.Key("Return");
        s = screen.WaitFor("the override sent to the controller", v => v.LogTail.Any(l => l.Contains("Feed override set to 50 %", StringComparison.Ordinal)));
        s.LogTail.Where(l => l.Contains("Feed override set to", StringComparison.Ordinal)).Should().ContainSingle("the typed value is sent once, on Return, not digit by digit");
        var feeds = new HashSet<string>();
        s = screen.WaitFor("the override in force across the program's feeds", v =>
        {
            v.Controls["numFeed"].Text.Should().Be("50", "the operator's setting holds");
            if (v.Status[FeedOverrideRow] == "50 %")
            {
                v.Status[FeedRow].Should().MatchRegex(@"^F\d+ × 50 % = [\d.]+$");
                feeds.Add(v.Status[FeedRow]);
            }

            return feeds.Count >= 1;
        }, TimeSpan.FromSeconds(60));
        // The controller slews the override (about 1 s from 100 % to 50 %) and the session reads it back every 20 ticks,
        // so the row may show "59.9 % → 50 %" for a while: wait for the controller to report the setting reached.
        screen.WaitTicks(20);
        screen.WaitFor("the controller reports 50 % in force", v => v.Status[FeedOverrideRow] == "50 %", TimeSpan.FromSeconds(30));
        s = screen.WaitTicks(40);
        (s.Controls["numFeed"].Text, s.Status[FeedOverrideRow]).Should().Be(("50", "50 %"), "the override holds while the program runs on (two reads from the controller later)");
        output.WriteLine($"  feeds shown: {string.Join(", ", feeds)}");
        screen.Screenshot("09-feed-override");

        Step("look back at the first chunk while the job is held in another: the chunk lines stay there, then follow again");
        // Held first: on a loaded machine the last chunks of the demo can run out before the steps that need a job.
        screen.ClickUntil("held again", HmiLayout.HoldButton, v => v.Status[StateRow] == En[TextId.StateHeld]);
        screen.Script("select-chunk 0");
        s = screen.WaitTicks(10);
        (s.SelectedChunk, s.ChunkExecutingLine).Should().Be((0, 0), "the operator's choice holds while another chunk is the job's");
        s.ChunkLineCount.Should().BeGreaterThan(1000, "the first chunk's lines are shown");
        var executing = int.Parse(s.Status[CurrentFileRow].Split('/')[0], System.Globalization.CultureInfo.InvariantCulture) - 1;
        screen.Script($"select-chunk {executing}");
        screen.WaitFor("following again", v => v.SelectedChunk >= executing && v.ChunkExecutingLine > 0);

        Step("abort (real click), the job held");
        s = screen.ClickUntil("aborted", HmiLayout.AbortButton, v => v.Status[StateRow] == En[TextId.StateAborted] && v.Controls["btnExecute"].Enabled);
        output.WriteLine($"  aborted at line {s.ExecutingLine}");
        screen.Screenshot("10-aborted");

        Step("start from a selected line: the preamble is shown and confirmed (real click, real key)");
        screen.Script("select-line 2000");
        screen.WaitFor("line 2000 selected and in view", v => v.SelectedLine == 2000 && v.TopLine <= 2000 && 2000 <= v.TopLine + v.VisibleLines);
        screen.Click(HmiLayout.StartFromLineButton);
        s = screen.WaitFor("the confirmation", v => v.DialogTitle == En[TextId.ConfirmStartTitle]);
        // Lengths go to the controller in millimetres (the host converts inch programs), so the preamble names no units code.
        s.DialogText.Should().Contain("2000").And.Contain("G17 G54").And.Contain("S6000 M03", "the preamble restores plane, work offset, spindle and the approach");
        screen.Screenshot("11-start-from-line-confirmation");
        Confirm(screen, En[TextId.ConfirmStartTitle]);
        s = screen.WaitFor("running from line 2000, the next file downloaded", v => v.DialogTitle is null && v.Status[StateRow] == En[TextId.StateRunning] && v.ExecutingLine >= 2000
            && v.LogTail.Any(l => l.Contains("chunk 3 (", StringComparison.Ordinal) && l.Contains("download", StringComparison.Ordinal)));
        s.LogTail.SkipWhile(l => !l.Contains("from line 2000", StringComparison.Ordinal)).Should().NotContain(
            l => l.Contains("late download", StringComparison.Ordinal) || l.Contains("window missed", StringComparison.Ordinal), "a start past the window is no missed window");
        screen.Screenshot("12-started-from-line");
        screen.Script("click btnAbort");
        s = screen.WaitFor("aborted again", v => v.Status[StateRow] == En[TextId.StateAborted]);
        var interrupted = s.ExecutingLine;
        output.WriteLine($"  interrupted at line {interrupted}");

        Step("resume after interruption: the checkpoint's preamble shown and confirmed");
        screen.Click(HmiLayout.ResumeInterruptedButton);
        s = screen.WaitFor("the resume confirmation", v => v.DialogTitle == En[TextId.ConfirmResumeTitle]);
        s.DialogText.Should().Contain("G17 G54").And.Contain("M03");
        var resumeAt = int.Parse(System.Text.RegularExpressions.Regex.Match(s.DialogText!, @"line (\d+)").Groups[1].Value, System.Globalization.CultureInfo.InvariantCulture);
        resumeAt.Should().BeInRange(2000, interrupted, "the checkpoint resumes where the interrupted job was, never past it");
        screen.Screenshot("13-resume-confirmation");
        Confirm(screen, En[TextId.ConfirmResumeTitle]);
        screen.WaitFor("running again from the checkpoint", v => v.DialogTitle is null && v.Status[StateRow] == En[TextId.StateRunning] && v.ExecutingLine >= resumeAt);
        screen.Screenshot("14-resumed-after-interruption");

        Step("switch to 简体中文 (real click on the language selector, Down, Return)");
        screen.Click(HmiLayout.LanguageCombo, HmiLayout.ProgramGroup);
        screen.Key("Down");
        screen.Key("Return");
        s = screen.WaitFor("Chinese texts", v => v.Controls["btnExecute"].Text == Zh[TextId.Execute] && v.Controls["cboLanguage"].Text == "简体中文");
        s.Status[StateRow].Should().BeOneOf(Zh[TextId.StateRunning], Zh[TextId.StateCompleted]);
        s.Controls["btnResumeInterrupted"].Text.Should().Be(Zh[TextId.ResumeInterrupted]);
        var running = s.Status[StateRow] == Zh[TextId.StateRunning];
        shot = running
            ? screen.ScreenshotWhenPainted("15-chinese", png => HmiScreen.CountColour(png, HmiLayout.ProgramLinesList, ExecutingColour) > 200)
            : screen.Screenshot("15-chinese");
        if (running)
        {
            HmiScreen.CountColour(shot, HmiLayout.ProgramLinesList, ExecutingColour).Should().BeGreaterThan(200, "the executing row is highlighted");
        }

        File.Copy(shot, Path.Combine(shots, "hmi-screen-zh.png"), overwrite: true);

        Step("the resumed job runs to the end");
        s = screen.WaitFor("completed", v => v.Status[StateRow] == Zh[TextId.StateCompleted], TimeSpan.FromSeconds(180));
        s.ExecutingLine.Should().BeGreaterThan(3200, "the last moves of the program ran");
        s.Errors.Should().BeEmpty();
        screen.Screenshot("16-completed");

        // The range is selected by script (as a Shift+click leaves it): Shift+Down from xdotool did not reach Wine's
        // virtual list view on the CI run of 2026-11-27; the start and the confirmation are real input.
        Step("selected blocks: lines 2500..2520 selected; the confirmation (real click) names the range's end; the job runs them and ends at 2520");
        screen.Script("select-line 2500");
        screen.WaitFor("line 2500 selected", v => v.SelectedLine == 2500 && v.ToBlock is null);
        screen.Script("select-lines 2500 2520");
        s = screen.WaitFor("lines 2500..2520 selected", v => v.SelectedLine == 2500 && v.ToBlock == 2520);
        screen.Click(HmiLayout.StartFromLineButton);
        s = screen.WaitFor("the confirmation with the range's end", v => v.DialogTitle == Zh[TextId.ConfirmStartTitle]);
        s.DialogText.Should().Contain("2500").And.Contain(string.Format(System.Globalization.CultureInfo.InvariantCulture, Zh[TextId.ConfirmRangeEnd], 2520));
        screen.Screenshot("17-selected-blocks-confirmation");
        Confirm(screen, Zh[TextId.ConfirmStartTitle]);
        s = screen.WaitFor("the selected blocks ran and the job completed at their last line", v => v.DialogTitle is null
            && v.Status[StateRow] == Zh[TextId.StateCompleted] && v.ExecutingLine == 2520, TimeSpan.FromSeconds(120));
        s.Errors.Should().BeEmpty();
        s.LogTail.Should().Contain(l => l.Contains("from line 2500", StringComparison.Ordinal), "the job started at the range's first line");
        screen.Screenshot("18-selected-blocks-completed");

        Step("another profile (real click on the profile selector, Down, Return): the split is dropped, the toolpath drawn anew");
        var stops = Path.Combine(work, "stops.nc");
        File.WriteAllLines(stops, StopsProgram());
        screen.Script($"open {WineHmi.WindowsPath(stops)}");
        s = screen.WaitFor("stops.nc open", v => v.Controls["lblPath"].Text == "stops.nc" && v.Controls["lblToolpath"].Text.Contains("stops.nc", StringComparison.Ordinal));
        s.Controls["cboProfile"].Text.Should().Be("fanuc-mill", "the default profile");
        screen.Script("click btnSplit");
        screen.WaitFor("stops.nc split", v => v.ChunkFiles.Count == 1);
        screen.Click(HmiLayout.ProfileCombo, HmiLayout.ProgramGroup);
        screen.Key("Down");
        screen.Key("Return");
        s = screen.WaitFor("linuxcnc-mill chosen, the split dropped", v => v.Controls["cboProfile"].Text == "linuxcnc-mill" && v.ChunkFiles.Count == 0 && !v.Controls["btnExecute"].Enabled);
        s.LogTail.Should().Contain(l => l.Contains("Machine profile fanuc-mill -> linuxcnc-mill", StringComparison.Ordinal));
        screen.WaitFor("the toolpath drawn under it", v => v.Controls["lblToolpath"].Text.Contains("stops.nc", StringComparison.Ordinal) && v.Controls["lblToolpath"].Text.Contains("12", StringComparison.Ordinal));
        screen.Screenshot("19-profile-changed");

        Step("a program stop: split under the new profile, execute; at M0 the banner shows and Resume (real click) continues");
        s.Controls["chkOptionalStop"].Text.Should().Be("checked", "M01 stops unless the operator says otherwise");
        screen.Script("click btnSplit");
        screen.WaitFor("split again", v => v.ChunkFiles.Count == 1 && v.Controls["btnExecute"].Enabled);
        screen.Click(HmiLayout.ExecuteButton);
        s = screen.WaitFor("stopped at line 9", v => v.Controls["lblProgramStop"].Text.Length > 0, TimeSpan.FromSeconds(60));
        var banner = StopText(Zh[TextId.ProgramStopBanner], "M0", 9);
        (s.Controls["lblProgramStop"].Text, s.Status[StateRow]).Should().Be((banner, StopText(Zh[TextId.StateStopped], "M0", 9)));
        s.ExecutingLine.Should().Be(9, "the stop block is the executing line");
        (s.Controls["btnResume"].Enabled, s.Controls["btnHold"].Enabled).Should().Be((true, false), "Resume continues; nothing moves to hold");
        screen.WaitTicks(20).ExecutingLine.Should().Be(9, "the machine waits at the stop (20 more ticks)");
        shot = screen.Screenshot("20-program-stop");
        HmiScreen.CountColour(shot, HmiLayout.ProgramStopBanner, "#FFA500").Should().BeGreaterThan(500, "the banner is on the screen, in orange");
        screen.Click(HmiLayout.ResumeButton);
        s = screen.WaitFor("stopped at the M1 on line 15", v => v.Controls["lblProgramStop"].Text == StopText(Zh[TextId.ProgramStopBanner], "M1", 15), TimeSpan.FromSeconds(60));
        screen.Click(HmiLayout.ResumeButton);
        s = screen.WaitFor("completed after the stops", v => v.Status[StateRow] == Zh[TextId.StateCompleted] && v.Controls["lblProgramStop"].Text.Length == 0, TimeSpan.FromSeconds(60));
        s.LogTail.Should().Contain(l => l.Contains("Program stop (M0) at line 9", StringComparison.Ordinal));
        s.Errors.Should().BeEmpty();
        screen.Screenshot("21-stops-completed");

        Step("close");
        screen.Send("close");
        hmi.WaitForExit(TimeSpan.FromSeconds(30)).Should().BeTrue("the form closes when no job runs");

        if (Environment.GetEnvironmentVariable("PMACSTREAM_UI_DOCS") == "1")
        {
            // The README's pictures: taken here, copied into docs/ on request only (CI leaves the tree alone).
            File.Copy(Path.Combine(shots, "hmi-screen.png"), Path.Combine(RepoRoot.Path, "docs", "hmi-screen.png"), overwrite: true);
            File.Copy(Path.Combine(shots, "hmi-screen-zh.png"), Path.Combine(RepoRoot.Path, "docs", "hmi-screen-zh.png"), overwrite: true);
        }
    }

    /// <summary>Twelve moves with an M00 at line 9 and an M01 at line 15.</summary>
    private static string[] StopsProgram() =>
    [
        "G21 G90 G17", "G00 X0 Y0", "G01 F600", "G01 X5", "G01 Y5", "G01 X0", "G01 Y0", "G01 X5 Y5", "M00",
        "G01 X10", "G01 Y10", "G01 X5", "G01 Y5", "G01 X0 Y0", "M01", "G01 X3", "G01 Y3", "M30",
    ];

    private static string StopText(string format, string code, int line) => string.Format(System.Globalization.CultureInfo.InvariantCulture, format, code, line);

    /// <summary>Answers Yes to the open message box with a real key press (Y), the pointer over the box so it has the keyboard.</summary>
    private static void Confirm(HmiScreen screen, string title)
    {
        var box = screen.WaitForWindow(title);
        screen.PointAt(box.X + (box.Width / 2), box.Y + 20);
        screen.Key("y");
    }

    private void Step(string what) => output.WriteLine($"step: {what}");
}
