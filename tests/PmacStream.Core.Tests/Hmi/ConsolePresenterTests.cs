using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Machine;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>The console pages' presenter over a fake console: what it shows, what it sends, what it refuses to write.</summary>
public sealed class ConsolePresenterTests : IAsyncLifetime
{
    private readonly FakeConsoleView _view = new();
    private readonly FakeConsoleBackend _console = new();
    private readonly FakeBackend _hmi = new();
    private ConsolePresenter _p = null!;

    public async Task InitializeAsync()
    {
        _p = new ConsolePresenter(_view, _console, _hmi, () => MachineProfile.Default) { PollPeriod = TimeSpan.Zero };
        await TickAsync();
    }

    public async Task DisposeAsync() => await _p.DisposeAsync();

    private async Task TickAsync()
    {
        await _p.TickAsync();
        await _p.WhenIdleAsync();
    }

    private async Task Do(Action a)
    {
        a();
        await _p.WhenIdleAsync();
        await TickAsync();
    }

    [Fact]
    public async Task The_DRO_shows_machine_work_and_homed_marks_to_the_micron()
    {
        _console.Machine[0] = 12.3456;
        _console.Tables = _console.Tables.With(_console.Tables.Offset("G54") with { X = 2 });
        await TickAsync();

        _view.Dro.Should().HaveCount(3);
        _view.Dro[0].Should().Be(new DroRow("X", "12.346", "10.346", "0.000", false));
        _view.MachineSummary.Should().Contain("G54").And.Contain("500").And.Contain("100 %");
        _view.ConsoleEnabled.Should().BeTrue();
    }

    [Fact]
    public async Task The_DRO_shows_every_axis_of_a_four_axis_machine_with_its_homed_mark_and_the_jog_panel_offers_them()
    {
        _console.Names = ["X", "Y", "Z", "A"];
        _console.Machine[3] = 90;
        _console.Homed[3] = true;
        await TickAsync();

        _view.Dro.Select(r => r.Axis).Should().Equal("X", "Y", "Z", "A");
        _view.Dro[3].Should().Be(new DroRow("A", "90.000", "90.000", "0.000", true));
        _view.Dro[0].Homed.Should().BeFalse();
        _view.ConsoleAxes.Should().Equal("X", "Y", "Z", "A");
    }

    [Fact]
    public void The_DRO_layout_keeps_its_height_for_any_number_of_axes_and_three_axes_as_before()
    {
        ConsoleLayout.DroCell(3, 1, 3).Should().Be(ConsoleLayout.DroCell(3, 1));
        ConsoleLayout.DroCell(1, 0, 3).Y.Should().Be(ConsoleLayout.DroTop + ConsoleLayout.DroRowHeight);
        foreach (var axes in Enumerable.Range(4, 6))
        {
            var last = ConsoleLayout.DroCell(axes, 6, axes);
            (last.Y + last.Height).Should().BeLessThanOrEqualTo(ConsoleLayout.DroCell(3, 6).Y + ConsoleLayout.DroCell(3, 6).Height, $"{axes} axes fit the three-axis DRO's height");
            ConsoleLayout.DroCell(2, 0, axes).Y.Should().BeGreaterThan(ConsoleLayout.DroCell(1, 0, axes).Y + ConsoleLayout.DroCell(1, 0, axes).Height - 1, "rows do not overlap");
            ConsoleLayout.DroFontSize(axes).Should().BeLessThan(14f).And.BeGreaterThanOrEqualTo(6f);
        }
    }

    [Fact]
    public async Task Home_all_and_a_jog_step_go_to_the_console_and_the_DRO_follows()
    {
        await Do(_view.HomeAll);
        _view.Dro.Should().OnlyContain(r => r.Homed);

        _view.JogAxis = "X";
        _view.JogIncrement = 1;
        _view.JogFeed = 600;
        await Do(() => _view.PressJog(+1));
        await Do(() => _view.ReleaseJog(+1));
        await Do(() => _view.PressJog(+1));

        _console.Calls.Where(c => c != "state").Should().Equal("home all", "jog X 1 F600", "jog X 1 F600");
        _view.Dro[0].Machine.Should().Be("2.000");
        _view.ConsoleMessage.Should().StartWith("Done: ");
    }

    [Fact]
    public async Task Continuous_jog_starts_on_press_and_stops_on_release()
    {
        _view.JogAxis = "Y";
        _view.JogIncrement = null;
        _view.JogFeed = 250;
        await Do(() => _view.PressJog(-1));
        await Do(() => _view.ReleaseJog(-1));

        _console.Calls.Where(c => c != "state").Should().Equal("start Y-1 F250", "stop Y");
    }

    [Fact]
    public async Task A_refusal_shows_the_consoles_reason_in_the_chosen_language()
    {
        _console.Refuse = ConsoleResult.Refused(ConsoleRefusal.ProgramRuns, "a program runs");
        _view.ChangeLanguage(HmiLanguage.Chinese);
        await Do(() => _view.Home("Z"));

        _view.ConsoleMessage.Should().Be("被拒绝：a program runs");
    }

    [Fact]
    public async Task MDI_keeps_a_history_and_empties_the_line_when_done()
    {
        await Do(() => _view.SendMdi("G0 X10 Y10"));
        await Do(() => _view.SendMdi("G1 X0 F300"));

        _console.Calls.Should().Contain("mdi G0 X10 Y10");
        _view.MdiHistory.Should().Equal("G0 X10 Y10", "G1 X0 F300");
        _view.MdiText.Should().BeEmpty();
        _view.PickMdi(0);
        _view.MdiText.Should().Be("G0 X10 Y10");
    }

    [Fact]
    public async Task The_alarm_banner_shows_while_an_alarm_is_active_on_every_language()
    {
        _console.Alarms.Add(new MachineAlarm(AlarmText.PlusLimit, 1, "X", "x", AlarmSeverity.Alarm));
        _console.History.Add(new AlarmRecord(AlarmText.PlusLimit, 1, "X", "x", DateTimeOffset.Now, null));
        await TickAsync();
        _view.AlarmBanner.Should().StartWith("ALARM: ").And.Contain(AlarmText.Text(AlarmText.PlusLimit, "X", 1));
        _view.AlarmHistory.Should().ContainSingle();

        _view.ChangeLanguage(HmiLanguage.Chinese);
        _view.AlarmBanner.Should().StartWith("报警：").And.Contain(AlarmText.Text(AlarmText.PlusLimit, "X", 1, "zh-CN"));

        await Do(_view.ClearAlarms);
        _view.AlarmBanner.Should().BeEmpty();
    }

    [Fact]
    public async Task The_offsets_grid_writes_only_what_changed_after_showing_it()
    {
        _view.OffsetRows.Should().HaveCount(MachineTables.Names.Count);
        _view.EditOffset("G55", 1, "100");
        _view.EditOffset("G55", 3, "-10");
        await Do(_view.ApplyOffsets);

        _view.Confirmations.Should().ContainSingle().Which.Should().Contain("G55: X 0 → 100, Z 0 → -10");
        _console.Calls.Where(c => c.StartsWith("offset", StringComparison.Ordinal)).Should().Equal("offset G55 X100 Y0 Z-10");
        _view.OffsetRows.Single(r => r[0] == "G55").Should().Equal("G55", "100", "0", "-10");
    }

    [Fact]
    public async Task A_bad_cell_is_refused_naming_its_row_and_nothing_is_written()
    {
        _view.EditOffset("G56", 2, "abc");
        _view.EditOffset("G57", 1, "200000");
        await Do(_view.ApplyOffsets);

        _view.TablesMessage.Should().Contain("G56 Y: 'abc' is not a number").And.Contain("G57 X: 200000 is out of range");
        _view.Confirmations.Should().BeEmpty();
        _console.Calls.Should().NotContain(c => c.StartsWith("offset", StringComparison.Ordinal));
    }

    [Fact]
    public async Task The_tools_grid_checks_the_radius_range_and_writes_a_tool()
    {
        _view.ToolRows.Should().HaveCount(ConsolePresenter.ToolRowCount);
        _view.EditTool(3, 2, "-1");
        await Do(_view.ApplyTools);
        _view.TablesMessage.Should().Contain("T3 Radius: -1 is out of range (0 to 500)");

        _view.EditTool(3, 2, "3");
        _view.EditTool(3, 1, "50.2");
        _view.ConfirmAnswer = false;
        await Do(_view.ApplyTools);
        _console.Calls.Should().NotContain(c => c.StartsWith("tool", StringComparison.Ordinal), "the operator declined");

        _view.ConfirmAnswer = true;
        await Do(_view.ApplyTools);
        _console.Calls.Should().Contain("tool 3 50.2 3 0 0");
        _console.Tables.Tool(3).EffectiveRadius.Should().Be(3);
    }

    [Fact]
    public async Task Touch_off_uses_the_active_offset_and_load_library_the_chosen_profile()
    {
        await Do(() => _view.TouchOff("X"));
        await Do(_view.LoadLibrary);

        _console.Calls.Should().Contain("touch G54 X 0");
        _hmi.LibrariesLoaded.Should().Equal(MachineProfile.Default.Name);
    }

    [Fact]
    public async Task Without_a_controller_the_console_is_disabled_and_says_so()
    {
        _console.ConsoleReady = false;
        await TickAsync();
        _view.ConsoleEnabled.Should().BeFalse();
        _view.Dro.Should().BeEmpty();

        await Do(_view.HomeAll);
        _view.ConsoleMessage.Should().Be("Connect to a controller first.");
        _console.Calls.Should().NotContain("home all");
    }

    [Fact]
    public async Task The_job_history_lists_the_backends_jobs()
    {
        _console.Jobs.Add(new HmiJobEntry(7, "/tmp/demo.nc", "chunk", DateTimeOffset.Now, HmiJobState.Completed, 3115));
        await Do(_view.RefreshHistory);

        _view.JobHistory.Should().ContainSingle().Which.Should().Contain("job 7  demo.nc  chunk  Completed  line 3115");
    }
}
