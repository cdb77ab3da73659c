using System.Globalization;

namespace PmacStream.WinForms;

/// <summary>The console pages in the UI test's snapshot and scripted mode.</summary>
internal sealed partial class MainForm
{
    /// <summary>Injects a simulator fault now (<c>KIND MOTOR</c>), set by the host when the built-in simulator is in use.</summary>
    internal Action<string, int>? InjectFault { get; set; }

    private UiConsole ConsoleSnapshot() => new()
    {
        SelectedTab = tabConsole.SelectedIndex,
        PageX = tabConsole.SelectedTab?.PointToScreen(Point.Empty).X ?? 0,
        PageY = tabConsole.SelectedTab?.PointToScreen(Point.Empty).Y ?? 0,
        Dro = lblDro.Select(r => new UiDroRow(r[0].Text, r[1].Text, r[2].Text, r[3].Text, r[4].Text == "●")).ToList(),
        AlarmBannerVisible = lblAlarmBanner.Visible,
        MdiHistory = lstMdiHistory.Items.Cast<object>().Select(o => o.ToString() ?? string.Empty).ToList(),
        JobHistory = lstJobHistory.Items.Cast<object>().Select(o => o.ToString() ?? string.Empty).ToList(),
        AlarmHistory = lstAlarmHistory.Items.Cast<object>().Select(o => o.ToString() ?? string.Empty).ToList(),
        Offsets = Rows(gridOffsets).Take(12).Select(r => r.ToList()).ToList(),
        Tools = Rows(gridTools).Take(6).Select(r => r.ToList()).ToList(),
        StoreJobs = Rows(gridStoreJobs).Take(10).Select(r => r.ToList()).ToList(),
    };

    /// <summary>
    /// <c>tab N</c> (the console's page), <c>jog-axis X</c>, <c>jog-step N</c> (the step box's index), <c>jog +</c> or
    /// <c>jog -</c> (the button pressed and released), <c>mdi TEXT</c> (typed into the MDI line), <c>cell offsets|tools ROW
    /// COLUMN TEXT</c> (typed into a grid cell), <c>inject KIND MOTOR</c> (a simulator fault now).
    /// </summary>
    private void RunConsoleScripted(string verb, string argument)
    {
        var parts = argument.Split(' ', 4, StringSplitOptions.RemoveEmptyEntries);
        switch (verb)
        {
            case "tab":
                tabConsole.SelectedIndex = int.Parse(argument, CultureInfo.InvariantCulture);
                break;
            case "jog-axis":
                cboJogAxis.SelectedItem = argument;
                break;
            case "jog-step":
                cboJogStep.SelectedIndex = int.Parse(argument, CultureInfo.InvariantCulture);
                break;
            case "jog":
                var button = argument == "+" ? btnJogPlus : btnJogMinus;
                if (!button.Enabled)
                {
                    throw new InvalidOperationException($"jog {argument} is disabled");
                }

                JogPressed?.Invoke(this, new Hmi.JogEventArgs(argument == "+" ? 1 : -1));
                JogReleased?.Invoke(this, new Hmi.JogEventArgs(argument == "+" ? 1 : -1));
                break;
            case "mdi":
                txtMdi.Text = argument;
                break;
            case "cell":
                var grid = parts[0] == "tools" ? gridTools : gridOffsets;
                grid.Rows[int.Parse(parts[1], CultureInfo.InvariantCulture)].Cells[int.Parse(parts[2], CultureInfo.InvariantCulture)].Value = parts.Length > 3 ? parts[3] : string.Empty;
                break;
            case "inject":
                (InjectFault ?? throw new InvalidOperationException("no built-in simulator to inject into"))(parts[0], int.Parse(parts[1], CultureInfo.InvariantCulture));
                break;
        }
    }
}
