using System.Globalization;
using PmacStream.Hmi;

namespace PmacStream.WinForms;

/// <summary>
/// The console pages beside the paper's screen (<see cref="ConsoleLayout"/>): the alarm banner over a tab control with
/// Machine (DRO, home, touch-off, jog, MDI, clear alarms), Offsets, Tools and History. A passive
/// <see cref="IConsoleView"/>: the <see cref="ConsolePresenter"/> decides; the form raises events and shows.
/// </summary>
internal sealed partial class MainForm : IConsoleView
{
    private static readonly string[] AxisLetters = ["X", "Y", "Z"];

    // Shown only while an alarm is active, over every tab: the operator must see it whatever page is open.
    private readonly Label lblAlarmBanner = new() { BackColor = Color.Red, ForeColor = Color.White, Font = new Font(SystemFonts.DefaultFont.FontFamily, 10f, FontStyle.Bold), AutoEllipsis = true, Visible = false };
    private readonly TabControl tabConsole = new();
    private readonly TabPage tabMachine = new() { Name = nameof(tabMachine) };
    private readonly TabPage tabOffsets = new() { Name = nameof(tabOffsets) };
    private readonly TabPage tabTools = new() { Name = nameof(tabTools) };
    private readonly TabPage tabHistory = new() { Name = nameof(tabHistory) };

    private readonly Label[] lblDroHeader = new Label[5];
    // One row per axis of the machine (the profile's: X Y Z by default, and A, B ... when it has them), rebuilt when
    // the axes change.
    private readonly List<Label[]> lblDro = [];
    private readonly List<Button> btnHomeAxis = [];
    private readonly List<Button> btnTouchOff = [];
    private bool _consoleEnabled = true;
    private readonly Label lblTouchValue = new();
    private readonly TextBox txtTouchValue = new() { Text = "0" };
    private readonly Button btnHomeAll = new();
    private readonly Button btnLoadLibrary = new();
    private readonly Label lblMachineSummary = new() { AutoEllipsis = true };

    private readonly GroupBox grpJog = new();
    private readonly Label lblJogAxis = new();
    private readonly ComboBox cboJogAxis = new() { DropDownStyle = ComboBoxStyle.DropDownList };
    private readonly Label lblJogStep = new();
    private readonly ComboBox cboJogStep = new() { DropDownStyle = ComboBoxStyle.DropDownList };
    private readonly Label lblJogSpeed = new();
    private readonly NumericUpDown numJogSpeed = new() { Minimum = 1, Maximum = 60_000, Increment = 100, Value = 1000 };
    private readonly Button btnJogMinus = new() { Text = "−", Font = new Font(SystemFonts.DefaultFont.FontFamily, 14f, FontStyle.Bold) };
    private readonly Button btnJogPlus = new() { Text = "+", Font = new Font(SystemFonts.DefaultFont.FontFamily, 14f, FontStyle.Bold) };

    private readonly GroupBox grpMdi = new();
    private readonly TextBox txtMdi = new();
    private readonly Button btnMdiSend = new();
    private readonly ListBox lstMdiHistory = new() { IntegralHeight = false };
    private readonly Button btnClearAlarms = new();
    private readonly Label lblConsoleMessage = new();

    private readonly DataGridView gridOffsets = NewGrid();
    private readonly Button btnOffsetsApply = new();
    private readonly Button btnOffsetsReload = new();
    private readonly Label lblOffsetsMessage = new();
    private readonly DataGridView gridTools = NewGrid();
    private readonly Button btnToolsApply = new();
    private readonly Button btnToolsReload = new();
    private readonly Label lblToolsMessage = new();

    private readonly Label lblJobHistory = new();
    private readonly ListBox lstJobHistory = new() { IntegralHeight = false, HorizontalScrollbar = true };
    private readonly Label lblAlarmHistory = new();
    private readonly ListBox lstAlarmHistory = new() { IntegralHeight = false, HorizontalScrollbar = true };
    private readonly Button btnHistoryRefresh = new();

    private ConsolePresenter? _console;
    private StorePresenter? _store;

    public event EventHandler? HomeAllRequested;
    public event EventHandler<string>? HomeAxisRequested;
    public event EventHandler<JogEventArgs>? JogPressed;
    public event EventHandler<JogEventArgs>? JogReleased;
    public event EventHandler? MdiRequested;
    public event EventHandler<int>? MdiHistoryPicked;
    public event EventHandler? ClearAlarmsRequested;
    public event EventHandler<string>? TouchOffRequested;
    public event EventHandler? OffsetsApplyRequested;
    public event EventHandler? ToolsApplyRequested;
    public event EventHandler? TablesReloadRequested;
    public event EventHandler? LoadLibraryRequested;
    public event EventHandler? HistoryRefreshRequested;

    /// <summary>Attaches the console pages' presenter; the form's timer ticks it after the job's presenter.</summary>
    public void Attach(ConsolePresenter console) => _console = console;

    /// <summary>Attaches the Store page's presenter.</summary>
    public void Attach(StorePresenter store) => _store = store;

    /// <summary>The alarm banner and the tab control with its four pages.</summary>
    private void PlaceConsole()
    {
        Place(lblAlarmBanner, ConsoleLayout.AlarmBanner, this);
        Place(tabConsole, ConsoleLayout.Tabs, this);
        tabConsole.TabPages.AddRange(new[] { tabMachine, tabOffsets, tabTools, tabHistory });
        PlaceDro();
        PlaceJogAndMdi();
        PlaceTablePage(tabOffsets, gridOffsets, btnOffsetsApply, btnOffsetsReload, lblOffsetsMessage);
        PlaceTablePage(tabTools, gridTools, btnToolsApply, btnToolsReload, lblToolsMessage);
        Place(lblJobHistory, ConsoleLayout.JobHistoryLabel, tabHistory);
        Place(lstJobHistory, ConsoleLayout.JobHistoryList, tabHistory);
        Place(lblAlarmHistory, ConsoleLayout.AlarmHistoryLabel, tabHistory);
        Place(lstAlarmHistory, ConsoleLayout.AlarmHistoryList, tabHistory);
        Place(btnHistoryRefresh, ConsoleLayout.RefreshButton, tabHistory);
        foreach (var c in new[] { "X", "Y", "Z" })
        {
            gridOffsets.Columns.Add(c, c);
        }

        gridOffsets.Columns.Insert(0, new DataGridViewTextBoxColumn { Name = "Table", ReadOnly = true });
        foreach (var c in new[] { "Tool", "Length", "Radius", "LengthWear", "RadiusWear" })
        {
            gridTools.Columns.Add(c, c);
        }

        gridTools.Columns[0].ReadOnly = true;
        cboJogAxis.Items.AddRange(AxisLetters);
        cboJogAxis.SelectedIndex = 0;
        PlaceStore();
        WireConsole();
    }

    private void PlaceDro()
    {
        for (var c = 0; c < lblDroHeader.Length; c++)
        {
            lblDroHeader[c] = new Label { Font = new Font(SystemFonts.DefaultFont, FontStyle.Bold), TextAlign = ContentAlignment.MiddleRight };
            Place(lblDroHeader[c], ConsoleLayout.DroCell(0, c), tabMachine);
        }

        PlaceDroRows(AxisLetters);
        Place(lblTouchValue, ConsoleLayout.TouchValueLabel, tabMachine);
        Place(txtTouchValue, ConsoleLayout.TouchValueBox, tabMachine);
        Place(btnHomeAll, ConsoleLayout.HomeAllButton, tabMachine);
        Place(btnLoadLibrary, ConsoleLayout.LoadLibraryButton, tabMachine);
        Place(lblMachineSummary, ConsoleLayout.SummaryLabel, tabMachine);
    }

    /// <summary>One DRO row per axis, each with its Home and Touch-off buttons, in the DRO's fixed height (<see cref="ConsoleLayout.DroCell(int, int, int)"/>).</summary>
    private void PlaceDroRows(IReadOnlyList<string> axes)
    {
        foreach (var c in lblDro.SelectMany(r => r).Concat<Control>(btnHomeAxis).Concat(btnTouchOff))
        {
            tabMachine.Controls.Remove(c);
            c.Dispose();
        }

        lblDro.Clear();
        btnHomeAxis.Clear();
        btnTouchOff.Clear();
        var size = ConsoleLayout.DroFontSize(axes.Count);
        var mono = MonospaceFont(size);
        for (var r = 0; r < axes.Count; r++)
        {
            var row = new Label[5];
            for (var c = 0; c < 5; c++)
            {
                row[c] = new Label { Font = c == 0 ? new Font(SystemFonts.DefaultFont.FontFamily, size, FontStyle.Bold) : mono, TextAlign = c == 4 ? ContentAlignment.MiddleCenter : ContentAlignment.MiddleRight };
                Place(row[c], ConsoleLayout.DroCell(r + 1, c, axes.Count), tabMachine);
            }

            var axis = axes[r];
            row[0].Text = axis;
            lblDro.Add(row);
            var home = new Button { Name = "btnHome" + axis, Enabled = _consoleEnabled };
            var touch = new Button { Name = "btnTouchOff" + axis, Enabled = _consoleEnabled };
            Place(home, ConsoleLayout.DroCell(r + 1, 5, axes.Count), tabMachine);
            Place(touch, ConsoleLayout.DroCell(r + 1, 6, axes.Count), tabMachine);
            home.Click += (_, _) => HomeAxisRequested?.Invoke(this, axis);
            touch.Click += (_, _) => TouchOffRequested?.Invoke(this, axis);
            btnHomeAxis.Add(home);
            btnTouchOff.Add(touch);
        }

        ApplyDroTexts();
    }

    private void PlaceJogAndMdi()
    {
        Place(grpJog, ConsoleLayout.JogGroup, tabMachine);
        Place(lblJogAxis, ConsoleLayout.JogAxisLabel, grpJog);
        Place(cboJogAxis, ConsoleLayout.JogAxisCombo, grpJog);
        Place(lblJogStep, ConsoleLayout.JogStepLabel, grpJog);
        Place(cboJogStep, ConsoleLayout.JogStepCombo, grpJog);
        Place(lblJogSpeed, ConsoleLayout.JogSpeedLabel, grpJog);
        Place(numJogSpeed, ConsoleLayout.JogSpeedBox, grpJog);
        Place(btnJogMinus, ConsoleLayout.JogMinusButton, grpJog);
        Place(btnJogPlus, ConsoleLayout.JogPlusButton, grpJog);
        Place(grpMdi, ConsoleLayout.MdiGroup, tabMachine);
        Place(txtMdi, ConsoleLayout.MdiText, grpMdi);
        Place(btnMdiSend, ConsoleLayout.MdiSendButton, grpMdi);
        Place(lstMdiHistory, ConsoleLayout.MdiHistoryList, grpMdi);
        Place(btnClearAlarms, ConsoleLayout.ClearAlarmsButton, tabMachine);
        Place(lblConsoleMessage, ConsoleLayout.ConsoleMessageLabel, tabMachine);
    }

    private static void PlaceTablePage(TabPage page, DataGridView grid, Button apply, Button reload, Label message)
    {
        Place(grid, ConsoleLayout.TableGrid, page);
        Place(apply, ConsoleLayout.ApplyButton, page);
        Place(reload, ConsoleLayout.ReloadButton, page);
        Place(message, ConsoleLayout.TableMessageLabel, page);
    }

    private void WireConsole()
    {
        btnHomeAll.Click += (_, _) => HomeAllRequested?.Invoke(this, EventArgs.Empty);
        btnLoadLibrary.Click += (_, _) => LoadLibraryRequested?.Invoke(this, EventArgs.Empty);

        // A jog button acts while held: pressed starts (one step, or a continuous jog), released ends a continuous jog.
        btnJogPlus.MouseDown += (_, e) => Jog(e, JogPressed, +1);
        btnJogPlus.MouseUp += (_, e) => Jog(e, JogReleased, +1);
        btnJogMinus.MouseDown += (_, e) => Jog(e, JogPressed, -1);
        btnJogMinus.MouseUp += (_, e) => Jog(e, JogReleased, -1);
        btnMdiSend.Click += (_, _) => MdiRequested?.Invoke(this, EventArgs.Empty);
        txtMdi.KeyDown += (_, e) =>
        {
            if (e.KeyCode == Keys.Return)
            {
                e.SuppressKeyPress = true;
                MdiRequested?.Invoke(this, EventArgs.Empty);
            }
        };
        lstMdiHistory.DoubleClick += (_, _) => MdiHistoryPicked?.Invoke(this, lstMdiHistory.SelectedIndex);
        btnClearAlarms.Click += (_, _) => ClearAlarmsRequested?.Invoke(this, EventArgs.Empty);
        btnOffsetsApply.Click += (_, _) => OffsetsApplyRequested?.Invoke(this, EventArgs.Empty);
        btnToolsApply.Click += (_, _) => ToolsApplyRequested?.Invoke(this, EventArgs.Empty);
        btnOffsetsReload.Click += (_, _) => TablesReloadRequested?.Invoke(this, EventArgs.Empty);
        btnToolsReload.Click += (_, _) => TablesReloadRequested?.Invoke(this, EventArgs.Empty);
        btnHistoryRefresh.Click += (_, _) => HistoryRefreshRequested?.Invoke(this, EventArgs.Empty);
        tabConsole.SelectedIndexChanged += (_, _) =>
        {
            if (tabConsole.SelectedTab == tabHistory)
            {
                HistoryRefreshRequested?.Invoke(this, EventArgs.Empty);
            }
        };
    }

    private void Jog(MouseEventArgs e, EventHandler<JogEventArgs>? handler, int direction)
    {
        if (e.Button == MouseButtons.Left)
        {
            handler?.Invoke(this, new JogEventArgs(direction));
        }
    }

    private void ApplyDroTexts()
    {
        for (var r = 0; r < lblDro.Count; r++)
        {
            var axis = lblDro[r][0].Text;
            btnHomeAxis[r].Text = string.Format(CultureInfo.InvariantCulture, _texts[TextId.HomeAxis], axis);
            btnTouchOff[r].Text = string.Format(CultureInfo.InvariantCulture, _texts[TextId.TouchOffAxis], axis);
        }
    }

    private void ApplyConsoleTexts()
    {
        var t = _texts;
        tabMachine.Text = t[TextId.TabMachine];
        tabOffsets.Text = t[TextId.TabOffsets];
        tabTools.Text = t[TextId.TabTools];
        tabHistory.Text = t[TextId.TabHistory];
        TextId[] headers = [TextId.DroAxis, TextId.DroMachine, TextId.DroWork, TextId.DroToGo, TextId.DroHomed];
        for (var c = 0; c < headers.Length; c++)
        {
            lblDroHeader[c].Text = t[headers[c]];
        }

        ApplyDroTexts();
        ApplyStoreTexts();
        (lblTouchValue.Text, btnHomeAll.Text, btnLoadLibrary.Text) = (t[TextId.TouchValue], t[TextId.HomeAll], t[TextId.LoadLibrary]);
        (grpJog.Text, lblJogAxis.Text, lblJogStep.Text, lblJogSpeed.Text) = (t[TextId.JogGroup], t[TextId.DroAxis], t[TextId.JogStep], t[TextId.JogSpeed]);
        var step = cboJogStep.SelectedIndex;
        cboJogStep.Items.Clear();
        cboJogStep.Items.AddRange(ConsolePresenter.JogIncrements.Select(i => (object)(i.ToString(CultureInfo.InvariantCulture) + " mm")).Append(t[TextId.JogContinuous]).ToArray());
        cboJogStep.SelectedIndex = step >= 0 ? step : ConsolePresenter.JogIncrements.Count - 1;
        (grpMdi.Text, btnMdiSend.Text, btnClearAlarms.Text) = (t[TextId.MdiGroup], t[TextId.MdiSend], t[TextId.ClearAlarms]);
        (btnOffsetsApply.Text, btnToolsApply.Text, btnOffsetsReload.Text, btnToolsReload.Text) = (t[TextId.TablesApply], t[TextId.TablesApply], t[TextId.TablesReload], t[TextId.TablesReload]);
        (lblJobHistory.Text, lblAlarmHistory.Text, btnHistoryRefresh.Text) = (t[TextId.JobHistoryLabel], t[TextId.AlarmHistoryLabel], t[TextId.HistoryRefresh]);
        gridOffsets.Columns[0].HeaderText = t[TextId.ColTable];
        TextId[] toolColumns = [TextId.ColTool, TextId.ColLength, TextId.ColRadius, TextId.ColLengthWear, TextId.ColRadiusWear];
        for (var c = 0; c < toolColumns.Length; c++)
        {
            gridTools.Columns[c].HeaderText = t[toolColumns[c]];
        }
    }

    // ------------------------------------------------------------------ IConsoleView

    public string JogAxis
    {
        get => cboJogAxis.SelectedItem as string ?? "X";
        set => cboJogAxis.SelectedItem = value;
    }

    public double? JogIncrement
    {
        get => cboJogStep.SelectedIndex >= 0 && cboJogStep.SelectedIndex < ConsolePresenter.JogIncrements.Count ? ConsolePresenter.JogIncrements[cboJogStep.SelectedIndex] : null;
        set => cboJogStep.SelectedIndex = value is { } v ? Math.Max(0, ConsolePresenter.JogIncrements.ToList().IndexOf(v)) : ConsolePresenter.JogIncrements.Count;
    }

    public double JogFeed
    {
        get => (double)numJogSpeed.Value;
        set => numJogSpeed.Value = Math.Clamp((decimal)value, numJogSpeed.Minimum, numJogSpeed.Maximum);
    }

    public string MdiText
    {
        get => txtMdi.Text;
        set => txtMdi.Text = value;
    }

    public double TouchValue => double.TryParse(txtTouchValue.Text, NumberStyles.Float, CultureInfo.InvariantCulture, out var v) ? v : 0;

    public IReadOnlyList<string> ConsoleAxes
    {
        set
        {
            cboJogAxis.Items.Clear();
            cboJogAxis.Items.AddRange(value.Cast<object>().ToArray());
            cboJogAxis.SelectedIndex = value.Count > 0 ? 0 : -1;
        }
    }

    public IReadOnlyList<DroRow> Dro
    {
        set
        {
            if (value.Count > 0 && !value.Select(r => r.Axis).SequenceEqual(lblDro.Select(r => r[0].Text)))
            {
                PlaceDroRows(value.Select(r => r.Axis).ToList()); // the machine's axes (the profile's), every one a row
            }

            for (var r = 0; r < lblDro.Count; r++)
            {
                var row = r < value.Count ? value[r] : null;
                lblDro[r][1].Text = row?.Machine ?? string.Empty;
                lblDro[r][2].Text = row?.Work ?? string.Empty;
                lblDro[r][3].Text = row?.ToGo ?? string.Empty;
                lblDro[r][4].Text = row is null ? string.Empty : row.Homed ? "●" : "○";
                lblDro[r][4].ForeColor = row is { Homed: true } ? Color.Green : Color.Gray;
            }
        }
    }

    public string MachineSummary
    {
        set => lblMachineSummary.Text = value;
    }

    public string AlarmBanner
    {
        set
        {
            lblAlarmBanner.Text = value;
            lblAlarmBanner.Visible = value.Length > 0;
        }
    }

    public string ConsoleMessage
    {
        set => lblConsoleMessage.Text = value;
    }

    public IReadOnlyList<string> MdiHistory
    {
        set => Fill(lstMdiHistory, value);
    }

    public IReadOnlyList<string> AlarmHistory
    {
        set => Fill(lstAlarmHistory, value);
    }

    public IReadOnlyList<string> JobHistory
    {
        set => Fill(lstJobHistory, value);
    }

    public IReadOnlyList<IReadOnlyList<string>> OffsetRows
    {
        get => Rows(gridOffsets);
        set => Fill(gridOffsets, value);
    }

    public IReadOnlyList<IReadOnlyList<string>> ToolRows
    {
        get => Rows(gridTools);
        set => Fill(gridTools, value);
    }

    public string TablesMessage
    {
        set => lblOffsetsMessage.Text = lblToolsMessage.Text = value;
    }

    public bool ConsoleEnabled
    {
        set
        {
            foreach (Control c in new Control[] { btnHomeAll, btnLoadLibrary, btnMdiSend, btnClearAlarms, btnOffsetsApply, btnToolsApply, btnOffsetsReload, btnToolsReload })
            {
                c.Enabled = value;
            }

            _consoleEnabled = value;
            foreach (var b in btnHomeAxis.Concat(btnTouchOff))
            {
                b.Enabled = value;
            }
        }
    }

    public bool JogEnabled
    {
        set => btnJogPlus.Enabled = btnJogMinus.Enabled = value;
    }

    private static void Fill(ListBox list, IReadOnlyList<string> rows)
    {
        list.BeginUpdate();
        list.Items.Clear();
        list.Items.AddRange(rows.Cast<object>().ToArray());
        list.EndUpdate();
    }

    private static void Fill(DataGridView grid, IReadOnlyList<IReadOnlyList<string>> rows)
    {
        grid.Rows.Clear();
        foreach (var row in rows)
        {
            grid.Rows.Add(row.Cast<object>().ToArray());
        }
    }

    private static List<IReadOnlyList<string>> Rows(DataGridView grid)
    {
        grid.EndEdit();
        return grid.Rows.Cast<DataGridViewRow>().Where(r => !r.IsNewRow)
            .Select(r => (IReadOnlyList<string>)r.Cells.Cast<DataGridViewCell>().Select(c => Convert.ToString(c.Value, CultureInfo.InvariantCulture) ?? string.Empty).ToList()).ToList();
    }

    private static DataGridView NewGrid() => new()
    {
        AllowUserToAddRows = false,
        AllowUserToDeleteRows = false,
        RowHeadersVisible = false,
        AutoSizeColumnsMode = DataGridViewAutoSizeColumnsMode.Fill,
        SelectionMode = DataGridViewSelectionMode.CellSelect,
    };
}
