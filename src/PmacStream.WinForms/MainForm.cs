using System.Globalization;
using PmacStream.Hmi;
using PmacStream.Jobs;

namespace PmacStream.WinForms;

/// <summary>
/// The operator screen as a passive view: it builds its controls from <see cref="HmiLayout"/>, raises
/// <see cref="IMainView"/> events and shows what the <see cref="MainPresenter"/> sets. No logic lives here; the
/// only code is wiring, and <c>timer1_Tick</c> calling the presenter's tick (the chunk method's timer).
/// </summary>
internal sealed partial class MainForm : Form, IMainView
{
    private static readonly Color ExecutingBack = Color.Gold;

    // The chunk method's timer: it drives streaming (read M0, download the next chunk once) and the display.
    private readonly System.Windows.Forms.Timer timer1 = new() { Interval = 50 };

    private readonly GroupBox grpConnection = new();
    private readonly Label lblDevice = new();
    private readonly ComboBox cboDevice = new() { DropDownStyle = ComboBoxStyle.DropDownList };
    private readonly Label lblIp = new();
    private readonly TextBox txtIp = new() { Text = "192.168.0.200" };
    private readonly Label lblPort = new();
    private readonly ComboBox cboPort = new() { DropDownStyle = ComboBoxStyle.DropDown };
    private readonly Label lblBaud = new();
    private readonly ComboBox cboBaud = new() { DropDownStyle = ComboBoxStyle.DropDownList };
    private readonly Label lblDeviceNumber = new();
    private readonly NumericUpDown numDeviceNumber = new() { Minimum = 0, Maximum = 15 };
    private readonly Button btnConnect = new();
    private readonly Button btnDisconnect = new();
    private readonly Label lblConnectionState = new();

    private readonly GroupBox grpProgram = new();
    private readonly Button btnOpen = new();
    private readonly Label lblPath = new() { AutoEllipsis = true };
    private readonly Button btnCheck = new();
    private readonly Button btnSplit = new();
    private readonly Label lblBlocksPerChunk = new();
    private readonly NumericUpDown numBlocksPerChunk = new() { Minimum = 1, Maximum = 100000, Value = RunSettings.DefaultBlocksPerChunk };
    private readonly Label lblStrategy = new();
    private readonly ComboBox cboStrategy = new() { DropDownStyle = ComboBoxStyle.DropDownList };
    private readonly Label lblWindow = new();
    private readonly NumericUpDown numWindowStart = new() { Minimum = 1, Maximum = 99, Increment = 5 };
    private readonly Label lblWindowDash = new() { Text = "–" };
    private readonly NumericUpDown numWindowEnd = new() { Minimum = 1, Maximum = 100, Increment = 5 };
    private readonly Label lblProfile = new();
    private readonly ComboBox cboProfile = new() { DropDownStyle = ComboBoxStyle.DropDownList };
    private readonly Label lblLanguage = new();
    private readonly ComboBox cboLanguage = new() { DropDownStyle = ComboBoxStyle.DropDownList };

    private readonly GroupBox grpFeed = new();
    private readonly Label lblFeed = new() { UseMnemonic = false }; // its text names the command &1 %
    private readonly TrackBar trkFeed = new()
    {
        TickStyle = TickStyle.BottomRight,
        Minimum = (int)FeedOverrides.Minimum,
        Maximum = (int)FeedOverrides.Maximum,
        TickFrequency = 10,
        LargeChange = 10,
        SmallChange = 1,
        Value = (int)FeedOverrides.Default,
    };

    private readonly NumericUpDown numFeed = new()
    {
        DecimalPlaces = 0,
        Minimum = (decimal)FeedOverrides.Minimum,
        Maximum = (decimal)FeedOverrides.Maximum,
        Increment = 5,
        Value = (decimal)FeedOverrides.Default,
    };

    private readonly Label lblFeedUnit = new() { Text = "%" };
    private readonly CheckBox chkSingleBlock = new();
    private readonly CheckBox chkOptionalStop = new() { Checked = true };

    private readonly Label lblChunkFiles = new();
    private readonly ListBox listBox1 = new() { IntegralHeight = false };
    private readonly Label lblChunkLines = new();
    private readonly ListView lvChunkLines = NewVirtualList();
    private readonly Label lblProgramLines = new();
    // Several lines may be selected: from the first to the last is a selected-block run (Start from line).
    private readonly ListView listBox2 = NewVirtualList(multiSelect: true);

    // Shown only at a program stop: an operator must see at once that the machine waits for Resume.
    private readonly Label lblProgramStop = new() { BackColor = Color.Orange, ForeColor = Color.Black, Font = new Font(SystemFonts.DefaultFont, FontStyle.Bold), AutoEllipsis = true, Visible = false };
    private readonly Button btnExecute = new() { Font = new Font(SystemFonts.DefaultFont.FontFamily, 11f, FontStyle.Bold) };
    private readonly Button btnHold = new();
    private readonly Button btnResume = new();
    private readonly Button btnAbort = new();
    private readonly Button btnStartFromLine = new();
    private readonly Button btnResumeInterrupted = new();

    private readonly GroupBox grpStatus = new();
    private readonly Label[] lblStatusCaptions = new Label[HmiLayout.StatusRows.Count];
    private readonly Label[] lblStatusValues = new Label[HmiLayout.StatusRows.Count];
    private readonly ProgressBar progressBar = new() { Minimum = 0, Maximum = 100 };

    private readonly Label lblDiagnostics = new();
    private readonly ListBox lstDiagnostics = new() { IntegralHeight = false, HorizontalScrollbar = true };
    private readonly Label lblLog = new();
    private readonly TextBox txtLog = new() { Multiline = true, ReadOnly = true, ScrollBars = ScrollBars.Both, WordWrap = false, Font = MonospaceFont(8.5f) };
    private readonly Label lblToolpath = new() { AutoEllipsis = true };
    private readonly PictureBox picToolpath = new() { BorderStyle = BorderStyle.FixedSingle, SizeMode = PictureBoxSizeMode.Normal };

    private readonly StatusStrip statusStrip = new();
    private readonly ToolStripStatusLabel stsConnection = new() { Spring = false };
    private readonly ToolStripStatusLabel stsState = new() { Spring = true, TextAlign = ContentAlignment.MiddleLeft };

    private IReadOnlyDictionary<TextId, string> _texts = HmiText.All(HmiLanguage.English);
    private MainPresenter? _presenter;
    private bool _updating;
    private int _executingLine;
    private int _chunkExecutingLine;
    private int _chunkLineCount;
    private int _programLineCount;
    private Bitmap? _toolpathBitmap;
    private ToolpathFrame? _toolpathFrame;
    private string _programFile = string.Empty;
    private Font? _executingFont;

    public MainForm()
    {
        SuspendLayout();
        AutoScaleMode = AutoScaleMode.Dpi;
        AutoScaleDimensions = new SizeF(96f, 96f);
        ClientSize = new Size(ConsoleLayout.FormWidth, HmiLayout.ClientHeight + HmiLayout.StatusStripHeight);
        MinimumSize = Size;
        StartPosition = FormStartPosition.CenterScreen;

        PlaceConnectionGroup();
        PlaceProgramGroup();
        PlaceRunControls();
        PlaceConsole();
        statusStrip.Items.AddRange(new ToolStripItem[] { stsState, stsConnection });
        Controls.Add(statusStrip);

        AnchorForGrowth();
        FillChoices();
        ApplyTexts();
        cboDevice.SelectedIndex = 0;

        WireEvents();
        ResumeLayout(performLayout: true);
    }

    /// <summary>The connection group: device, address, port, baud, device number and the connect buttons.</summary>
    private void PlaceConnectionGroup()
    {
        Place(grpConnection, HmiLayout.ConnectionGroup, this);
        Place(lblDevice, HmiLayout.DeviceLabel, grpConnection);
        Place(cboDevice, HmiLayout.DeviceCombo, grpConnection);
        Place(lblIp, HmiLayout.IpLabel, grpConnection);
        Place(txtIp, HmiLayout.IpText, grpConnection);
        Place(lblPort, HmiLayout.PortLabel, grpConnection);
        Place(cboPort, HmiLayout.PortCombo, grpConnection);
        Place(lblBaud, HmiLayout.BaudLabel, grpConnection);
        Place(cboBaud, HmiLayout.BaudCombo, grpConnection);
        Place(lblDeviceNumber, HmiLayout.DeviceNumberLabel, grpConnection);
        Place(numDeviceNumber, HmiLayout.DeviceNumberBox, grpConnection);
        Place(btnConnect, HmiLayout.ConnectButton, grpConnection);
        Place(btnDisconnect, HmiLayout.DisconnectButton, grpConnection);
        Place(lblConnectionState, HmiLayout.ConnectionStateLabel, grpConnection);
    }

    /// <summary>The program group: open, check, split, the chunk shape, strategy, window, profile and language.</summary>
    private void PlaceProgramGroup()
    {
        Place(grpProgram, HmiLayout.ProgramGroup, this);
        Place(btnOpen, HmiLayout.OpenButton, grpProgram);
        Place(lblPath, HmiLayout.PathLabel, grpProgram);
        Place(btnCheck, HmiLayout.CheckButton, grpProgram);
        Place(btnSplit, HmiLayout.SplitButton, grpProgram);
        Place(lblBlocksPerChunk, HmiLayout.BlocksPerChunkLabel, grpProgram);
        Place(numBlocksPerChunk, HmiLayout.BlocksPerChunkBox, grpProgram);
        Place(lblStrategy, HmiLayout.StrategyLabel, grpProgram);
        Place(cboStrategy, HmiLayout.StrategyCombo, grpProgram);
        Place(lblWindow, HmiLayout.WindowLabel, grpProgram);
        Place(numWindowStart, HmiLayout.WindowStartBox, grpProgram);
        Place(lblWindowDash, HmiLayout.WindowDash, grpProgram);
        Place(numWindowEnd, HmiLayout.WindowEndBox, grpProgram);
        Place(lblProfile, HmiLayout.ProfileLabel, grpProgram);
        Place(cboProfile, HmiLayout.ProfileCombo, grpProgram);
        Place(lblLanguage, HmiLayout.LanguageLabel, grpProgram);
        Place(cboLanguage, HmiLayout.LanguageCombo, grpProgram);
    }

    /// <summary>The feed group, the three lists, the run buttons, the status group, diagnostics, log and toolpath pane.</summary>
    private void PlaceRunControls()
    {
        Place(grpFeed, HmiLayout.FeedGroup, this);
        Place(lblFeed, HmiLayout.FeedLabel, grpFeed);
        Place(trkFeed, HmiLayout.FeedTrackBar, grpFeed);
        Place(numFeed, HmiLayout.FeedBox, grpFeed);
        Place(lblFeedUnit, HmiLayout.FeedUnitLabel, grpFeed);
        Place(chkSingleBlock, HmiLayout.SingleBlockCheck, grpFeed);
        Place(chkOptionalStop, HmiLayout.OptionalStopCheck, grpFeed);

        Place(lblChunkFiles, HmiLayout.ChunkFilesLabel, this);
        Place(listBox1, HmiLayout.ChunkFilesList, this);
        Place(lblChunkLines, HmiLayout.ChunkLinesLabel, this);
        Place(lvChunkLines, HmiLayout.ChunkLinesList, this);
        Place(lblProgramLines, HmiLayout.ProgramLinesLabel, this);
        Place(listBox2, HmiLayout.ProgramLinesList, this);

        Place(lblProgramStop, HmiLayout.ProgramStopBanner, this);
        Place(btnExecute, HmiLayout.ExecuteButton, this);
        Place(btnHold, HmiLayout.HoldButton, this);
        Place(btnResume, HmiLayout.ResumeButton, this);
        Place(btnAbort, HmiLayout.AbortButton, this);
        Place(btnStartFromLine, HmiLayout.StartFromLineButton, this);
        Place(btnResumeInterrupted, HmiLayout.ResumeInterruptedButton, this);

        Place(grpStatus, HmiLayout.StatusGroup, this);
        for (var row = 0; row < HmiLayout.StatusRows.Count; row++)
        {
            lblStatusCaptions[row] = new Label();
            lblStatusValues[row] = new Label { Font = new Font(SystemFonts.DefaultFont, FontStyle.Bold), AutoEllipsis = true };
            Place(lblStatusCaptions[row], HmiLayout.StatusCaption(row), grpStatus);
            Place(lblStatusValues[row], HmiLayout.StatusValue(row), grpStatus);
        }

        Place(progressBar, HmiLayout.ProgressBar, grpStatus);

        Place(lblDiagnostics, HmiLayout.DiagnosticsLabel, this);
        Place(lstDiagnostics, HmiLayout.DiagnosticsList, this);
        Place(lblLog, HmiLayout.LogLabel, this);
        Place(txtLog, HmiLayout.LogText, this);
        Place(lblToolpath, HmiLayout.ToolpathLabel, this);
        Place(picToolpath, HmiLayout.ToolpathPane, this);
    }

    /// <summary>What grows with the window and what stays put, and the window defaults.</summary>
    private void AnchorForGrowth()
    {
        // Growing the window grows the lists and the log, not the buttons; the toolpath pane keeps the size it is drawn at.
        listBox2.Anchor = AnchorStyles.Top | AnchorStyles.Bottom | AnchorStyles.Left | AnchorStyles.Right;
        lvChunkLines.Anchor = AnchorStyles.Top | AnchorStyles.Bottom | AnchorStyles.Left;
        foreach (Control c in new Control[] { lblProgramStop, btnExecute, btnHold, btnResume, btnAbort, btnStartFromLine, btnResumeInterrupted, grpStatus, grpFeed })
        {
            c.Anchor = AnchorStyles.Top | AnchorStyles.Right;
        }

        foreach (Control c in new Control[] { lblDiagnostics, lstDiagnostics })
        {
            c.Anchor = AnchorStyles.Bottom | AnchorStyles.Left;
        }

        foreach (Control c in new Control[] { lblToolpath, picToolpath })
        {
            c.Anchor = AnchorStyles.Bottom | AnchorStyles.Right;
        }

        lblLog.Anchor = AnchorStyles.Bottom | AnchorStyles.Left | AnchorStyles.Right;
        txtLog.Anchor = AnchorStyles.Bottom | AnchorStyles.Left | AnchorStyles.Right;
        numWindowStart.Value = (decimal)(RunSettings.DefaultWindowStart * 100);
        numWindowEnd.Value = (decimal)(RunSettings.DefaultWindowEnd * 100);
    }

    /// <summary>The fixed choices of the port, baud and language boxes.</summary>
    private void FillChoices()
    {
        cboPort.Items.AddRange(new object[] { "COM1", "COM2", "COM3", "COM4", "COM5", "COM6", "COM7", "COM8" });
        cboPort.SelectedIndex = 0;
        cboBaud.Items.AddRange(new object[] { "9600", "19200", "38400", "57600", "115200" });
        cboBaud.SelectedIndex = 2;
        cboLanguage.Items.AddRange(new object[] { "English", "简体中文" });
        cboLanguage.SelectedIndex = CultureInfo.CurrentUICulture.Name.StartsWith("zh", StringComparison.OrdinalIgnoreCase) ? 1 : 0;
    }

    /// <summary>Attaches the presenter whose tick the timer drives; the timer starts when the window shows.</summary>
    public void Attach(MainPresenter presenter)
    {
        _presenter = presenter;
        timer1.Interval = (int)Math.Max(1, presenter.TickPeriod.TotalMilliseconds); // the run settings' tick period
    }

    // ------------------------------------------------------------------ timer1, the chunk method's timer

    private async void timer1_Tick(object? sender, EventArgs e)
    {
        if (_presenter is null)
        {
            return;
        }

        try
        {
            _ticks++;
            await _presenter.TickAsync();
            if (_console is not null)
            {
                await _console.TickAsync();
            }
        }
        catch (Exception ex)
        {
            // An async void handler must not throw into the message loop; the presenter already logged it.
            stsState.Text = ex.Message;
        }
    }

    protected override void OnShown(EventArgs e)
    {
        base.OnShown(e);
        timer1.Start();
    }

    protected override void OnFormClosing(FormClosingEventArgs e)
    {
        if (_presenter is { JobActive: true } &&
            MessageBox.Show(this, _texts[TextId.ConfirmCloseRunning], _texts[TextId.Title], MessageBoxButtons.YesNo, MessageBoxIcon.Warning, MessageBoxDefaultButton.Button2) != DialogResult.Yes)
        {
            e.Cancel = true;
            return;
        }

        timer1.Stop();
        base.OnFormClosing(e);
    }

    protected override void Dispose(bool disposing)
    {
        if (disposing)
        {
            timer1.Dispose();
            _executingFont?.Dispose();
            _toolpathBitmap?.Dispose();
        }

        base.Dispose(disposing);
    }

    // ------------------------------------------------------------------ wiring

    private void WireEvents()
    {
        timer1.Tick += timer1_Tick;

        cboLanguage.SelectedIndexChanged += (_, _) => LanguageChanged?.Invoke(this, EventArgs.Empty);
        btnConnect.Click += (_, _) => ConnectRequested?.Invoke(this, EventArgs.Empty);
        btnDisconnect.Click += (_, _) => DisconnectRequested?.Invoke(this, EventArgs.Empty);
        btnOpen.Click += (_, _) => ChooseProgram();
        btnCheck.Click += (_, _) => CheckRequested?.Invoke(this, EventArgs.Empty);
        btnSplit.Click += (_, _) => SplitRequested?.Invoke(this, EventArgs.Empty);
        lstDiagnostics.DoubleClick += (_, _) =>
        {
            if (lstDiagnostics.SelectedIndex >= 0)
            {
                DiagnosticActivated?.Invoke(this, lstDiagnostics.SelectedIndex);
            }
        };
        listBox1.SelectedIndexChanged += (_, _) =>
        {
            if (!_updating)
            {
                ChunkSelected?.Invoke(this, listBox1.SelectedIndex);
            }
        };

        lvChunkLines.RetrieveVirtualItem += (_, e) => e.Item = LineItem(e.ItemIndex, ChunkLineNeeded, executing: e.ItemIndex + 1 == _chunkExecutingLine);
        listBox2.RetrieveVirtualItem += (_, e) => e.Item = LineItem(e.ItemIndex, ProgramLineNeeded, executing: e.ItemIndex + 1 == _executingLine);

        btnExecute.Click += (_, _) => ExecuteRequested?.Invoke(this, EventArgs.Empty);
        btnHold.Click += (_, _) => HoldRequested?.Invoke(this, EventArgs.Empty);
        btnResume.Click += (_, _) => ResumeRequested?.Invoke(this, EventArgs.Empty);
        btnAbort.Click += (_, _) => AbortRequested?.Invoke(this, EventArgs.Empty);
        btnStartFromLine.Click += (_, _) => StartFromLineRequested?.Invoke(this, EventArgs.Empty);
        btnResumeInterrupted.Click += (_, _) => ResumeInterruptedRequested?.Invoke(this, EventArgs.Empty);
        chkSingleBlock.CheckedChanged += (_, _) => SingleBlockChanged?.Invoke(this, EventArgs.Empty);
        chkOptionalStop.CheckedChanged += (_, _) =>
        {
            if (!_updating)
            {
                OptionalStopChanged?.Invoke(this, EventArgs.Empty);
            }
        };
        cboProfile.SelectedIndexChanged += (_, _) =>
        {
            if (!_updating)
            {
                ProfileChanged?.Invoke(this, EventArgs.Empty);
            }
        };

        WireFeed();
        numWindowStart.ValueChanged += (_, _) => WindowChanged();
        numWindowEnd.ValueChanged += (_, _) => WindowChanged();
    }

    /// <summary>The slider moves the box as it is dragged; the feed is sent once the operator lets go.</summary>
    private void WireFeed()
    {
        trkFeed.ValueChanged += (_, _) =>
        {
            if (_updating)
            {
                return;
            }

            _updating = true;
            try
            {
                numFeed.Value = Math.Clamp(trkFeed.Value, numFeed.Minimum, numFeed.Maximum);
            }
            finally
            {
                _updating = false;
            }
        };
        trkFeed.MouseUp += (_, _) => FeedOverrideChanged?.Invoke(this, EventArgs.Empty);
        trkFeed.KeyUp += (_, _) => FeedOverrideChanged?.Invoke(this, EventArgs.Empty);
        numFeed.ValueChanged += (_, _) =>
        {
            if (_updating)
            {
                return;
            }

            _updating = true;
            try
            {
                trkFeed.Value = Math.Clamp((int)Math.Round(numFeed.Value), trkFeed.Minimum, trkFeed.Maximum);
            }
            finally
            {
                _updating = false;
            }

            FeedOverrideChanged?.Invoke(this, EventArgs.Empty);
        };
    }

    private void WindowChanged()
    {
        if (!_updating)
        {
            _downloadWindowChanged?.Invoke(this, EventArgs.Empty);
        }
    }

    private void ChooseProgram()
    {
        using var dialog = new OpenFileDialog
        {
            Filter = "G-code (*.nc;*.ngc;*.gcode;*.tap;*.cnc;*.txt)|*.nc;*.ngc;*.gcode;*.tap;*.cnc;*.txt|All files (*.*)|*.*",
            CheckFileExists = true,
            Title = _texts[TextId.Open].TrimEnd('…'),
        };
        _dialog = (dialog.Title, string.Empty);
        DialogResult answer;
        try
        {
            answer = dialog.ShowDialog(this);
        }
        finally
        {
            _dialog = null;
        }

        if (answer == DialogResult.OK)
        {
            OpenRequested?.Invoke(this, dialog.FileName);
        }
    }

    private ListViewItem LineItem(int index, EventHandler<LineRequestEventArgs>? source, bool executing)
    {
        var request = new LineRequestEventArgs(index + 1);
        source?.Invoke(this, request);
        var item = new ListViewItem((index + 1).ToString(CultureInfo.InvariantCulture));
        item.SubItems.Add(request.Text);
        if (executing)
        {
            item.BackColor = ExecutingBack;
            item.Font = _executingFont ??= new Font(listBox2.Font, FontStyle.Bold);
        }

        return item;
    }

    /// <summary>Moves a virtual list's highlighted row to <paramref name="line"/> (0: none) and scrolls it into view.</summary>
    private static void Highlight(ListView list, ref int shown, int line, int count)
    {
        var old = shown;
        shown = line;
        RedrawLine(list, old, count);
        if (line >= 1 && line <= count)
        {
            list.EnsureVisible(line - 1);
            RedrawLine(list, line, count);
        }
    }

    private static void RedrawLine(ListView list, int line, int count)
    {
        if (line >= 1 && line <= count)
        {
            list.RedrawItems(line - 1, line - 1, invalidateOnly: true);
        }
    }

    private void ApplyTexts()
    {
        var t = _texts;
        grpConnection.Text = t[TextId.ConnectionGroup];
        lblDevice.Text = t[TextId.DeviceType];
        lblIp.Text = t[TextId.IpAddress];
        lblPort.Text = t[TextId.SerialPort];
        lblBaud.Text = t[TextId.Baud];
        lblDeviceNumber.Text = t[TextId.DeviceNumber];
        btnConnect.Text = t[TextId.Connect];
        btnDisconnect.Text = t[TextId.Disconnect];

        var device = cboDevice.SelectedIndex;
        cboDevice.Items.Clear();
        cboDevice.Items.AddRange(new object[] { t[TextId.DeviceSimulator], t[TextId.DeviceEthernet], t[TextId.DeviceSerial], t[TextId.DevicePcomm] });
        cboDevice.SelectedIndex = device >= 0 ? device : 0;

        grpProgram.Text = t[TextId.ProgramGroup];
        btnOpen.Text = t[TextId.Open];
        btnCheck.Text = t[TextId.Check];
        btnSplit.Text = t[TextId.Split];
        lblBlocksPerChunk.Text = t[TextId.BlocksPerChunk];
        lblStrategy.Text = t[TextId.Strategy];
        lblWindow.Text = t[TextId.WindowControl];
        lblLanguage.Text = t[TextId.Language];
        lblProfile.Text = t[TextId.Profile];

        grpFeed.Text = t[TextId.FeedOverride];
        lblFeed.Text = t[TextId.FeedOverrideHint];
        chkSingleBlock.Text = t[TextId.SingleBlock];
        chkOptionalStop.Text = t[TextId.OptionalStop];

        lblChunkFiles.Text = t[TextId.ChunkFiles];
        lblChunkLines.Text = t[TextId.ChunkLines];
        lblProgramLines.Text = t[TextId.ProgramLines];
        foreach (var list in new[] { lvChunkLines, listBox2 })
        {
            list.Columns[0].Text = t[TextId.LineColumn];
            list.Columns[1].Text = t[TextId.TextColumn];
        }

        btnExecute.Text = t[TextId.Execute];
        btnHold.Text = t[TextId.Hold];
        btnResume.Text = t[TextId.Resume];
        btnAbort.Text = t[TextId.Abort];
        btnStartFromLine.Text = t[TextId.StartFromLine];
        btnResumeInterrupted.Text = t[TextId.ResumeInterrupted];

        grpStatus.Text = t[TextId.JobState];
        for (var row = 0; row < lblStatusCaptions.Length; row++)
        {
            lblStatusCaptions[row].Text = t[HmiLayout.StatusRows[row]];
        }

        lblDiagnostics.Text = t[TextId.Diagnostics];
        lblLog.Text = t[TextId.Log];
        ApplyConsoleTexts();
        ApplyTitle();
    }

    private void ApplyTitle() =>
        Text = _programFile.Length == 0 ? _texts[TextId.Title] : $"{_texts[TextId.Title]} – {_programFile}";

    private static ListView NewVirtualList(bool multiSelect = false)
    {
        // ListBox has no virtual mode; a one-line-per-row ListView in VirtualMode asks only for the rows on screen.
        var list = new ListView
        {
            View = View.Details,
            VirtualMode = true,
            VirtualListSize = 0,
            FullRowSelect = true,
            MultiSelect = multiSelect,
            HideSelection = false,
            HeaderStyle = ColumnHeaderStyle.Nonclickable,
            Font = MonospaceFont(9f),
        };
        list.Columns.Add("Line", HmiLayout.LineNumberColumnWidth, HorizontalAlignment.Right);
        list.Columns.Add("Block", 2000);
        return list;
    }

    /// <summary>
    /// GDI+'s generic monospace family (Courier New on Windows, Liberation Mono under Wine); the default font where
    /// neither is installed, rather than no screen at all.
    /// </summary>
    private static Font MonospaceFont(float size)
    {
        try
        {
            return new Font(FontFamily.GenericMonospace, size);
        }
        catch (ArgumentException)
        {
            return new Font(SystemFonts.DefaultFont.FontFamily, size);
        }
    }

    private static void Place(Control control, LayoutBox box, Control parent)
    {
        control.Bounds = new Rectangle(box.X, box.Y, box.Width, box.Height);
        parent.Controls.Add(control);
    }
}
