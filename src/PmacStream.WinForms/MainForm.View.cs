using System.Drawing.Imaging;
using System.Globalization;
using PmacStream.Hmi;

namespace PmacStream.WinForms;

/// <summary>The <see cref="IMainView"/> members: what the presenter sets is shown, what the operator does is raised.</summary>
internal sealed partial class MainForm
{
    public event EventHandler? LanguageChanged;
    public event EventHandler? ConnectRequested;
    public event EventHandler? DisconnectRequested;
    public event EventHandler<string>? OpenRequested;
    public event EventHandler? CheckRequested;
    public event EventHandler<int>? DiagnosticActivated;
    public event EventHandler? SplitRequested;
    public event EventHandler<int>? ChunkSelected;
    public event EventHandler<LineRequestEventArgs>? ChunkLineNeeded;
    public event EventHandler<LineRequestEventArgs>? ProgramLineNeeded;
    public event EventHandler? ExecuteRequested;
    public event EventHandler? HoldRequested;
    public event EventHandler? ResumeRequested;
    public event EventHandler? AbortRequested;
    public event EventHandler? StartFromLineRequested;
    public event EventHandler? ResumeInterruptedRequested;
    public event EventHandler? SingleBlockChanged;
    public event EventHandler? OptionalStopChanged;
    public event EventHandler? ProfileChanged;
    public event EventHandler? FeedOverrideChanged;

    private EventHandler? _downloadWindowChanged;

    public event EventHandler? DownloadWindowChanged
    {
        add => _downloadWindowChanged += value;
        remove => _downloadWindowChanged -= value;
    }

    /// <summary>The two percent boxes beside the strategy, as fractions of a chunk.</summary>
    public (double Start, double End) DownloadWindow
    {
        get => ((double)numWindowStart.Value / 100, (double)numWindowEnd.Value / 100);
        set
        {
            _updating = true;
            try
            {
                numWindowStart.Value = Math.Clamp((decimal)Math.Round(value.Start * 100, 1), numWindowStart.Minimum, numWindowStart.Maximum);
                numWindowEnd.Value = Math.Clamp((decimal)Math.Round(value.End * 100, 1), numWindowEnd.Minimum, numWindowEnd.Maximum);
            }
            finally
            {
                _updating = false;
            }
        }
    }

    IReadOnlyDictionary<TextId, string> IMainView.Texts
    {
        set
        {
            _texts = value;
            ApplyTexts();
        }
    }

    public HmiLanguage Language => cboLanguage.SelectedIndex == 1 ? HmiLanguage.Chinese : HmiLanguage.English;

    public ConnectionSettings ConnectionSettings => new(
        (DeviceKind)Math.Max(0, cboDevice.SelectedIndex),
        txtIp.Text.Trim(),
        cboPort.Text.Trim(),
        int.TryParse(cboBaud.Text, NumberStyles.Integer, CultureInfo.InvariantCulture, out var baud) ? baud : 38400,
        (int)numDeviceNumber.Value);

    string IMainView.ConnectionState
    {
        set
        {
            lblConnectionState.Text = value;
            stsConnection.Text = value;
        }
    }

    string IMainView.ProgramPath
    {
        set
        {
            _programFile = Path.GetFileName(value);
            lblPath.Text = _programFile;
            ApplyTitle();
        }
    }

    IReadOnlyList<string> IMainView.Diagnostics
    {
        set
        {
            lstDiagnostics.BeginUpdate();
            lstDiagnostics.Items.Clear();
            foreach (var d in value)
            {
                lstDiagnostics.Items.Add(d);
            }

            lstDiagnostics.EndUpdate();
        }
    }

    public int BlocksPerChunk
    {
        get => (int)numBlocksPerChunk.Value;
        set => numBlocksPerChunk.Value = Math.Clamp(value, numBlocksPerChunk.Minimum, numBlocksPerChunk.Maximum);
    }

    IReadOnlyList<string> IMainView.Strategies
    {
        set
        {
            cboStrategy.Items.Clear();
            foreach (var s in value)
            {
                cboStrategy.Items.Add(s);
            }

            if (cboStrategy.Items.Count > 0)
            {
                cboStrategy.SelectedIndex = 0;
            }
        }
    }

    public string SelectedStrategy => cboStrategy.SelectedItem as string ?? string.Empty;

    IReadOnlyList<string> IMainView.Profiles
    {
        set
        {
            _updating = true;
            try
            {
                cboProfile.Items.Clear();
                foreach (var p in value)
                {
                    cboProfile.Items.Add(p);
                }
            }
            finally
            {
                _updating = false;
            }
        }
    }

    public string SelectedProfile
    {
        get => cboProfile.SelectedItem as string ?? string.Empty;
        set
        {
            _updating = true;
            try
            {
                cboProfile.SelectedIndex = cboProfile.Items.IndexOf(value);
            }
            finally
            {
                _updating = false;
            }
        }
    }

    public bool OptionalStop
    {
        get => chkOptionalStop.Checked;
        set
        {
            _updating = true;
            try
            {
                chkOptionalStop.Checked = value;
            }
            finally
            {
                _updating = false;
            }
        }
    }

    string IMainView.ProgramStopBanner
    {
        set
        {
            if (lblProgramStop.Text != value)
            {
                lblProgramStop.Text = value;
                lblProgramStop.Visible = value.Length > 0;
            }
        }
    }

    IReadOnlyList<string> IMainView.ChunkFiles
    {
        set
        {
            // Re-filling (a language change) keeps the selection and must not look like the operator's click.
            _updating = true;
            try
            {
                var selected = listBox1.SelectedIndex;
                listBox1.BeginUpdate();
                listBox1.Items.Clear();
                foreach (var row in value)
                {
                    listBox1.Items.Add(row);
                }

                listBox1.EndUpdate();
                if (selected >= 0 && selected < listBox1.Items.Count)
                {
                    listBox1.SelectedIndex = selected;
                }
            }
            finally
            {
                _updating = false;
            }
        }
    }

    int IMainView.SelectedChunk
    {
        set
        {
            // Following execution must not look like the operator's click.
            _updating = true;
            try
            {
                listBox1.SelectedIndex = value >= 0 && value < listBox1.Items.Count ? value : -1;
            }
            finally
            {
                _updating = false;
            }
        }
    }

    int IMainView.ChunkLineCount
    {
        set
        {
            _chunkLineCount = Math.Max(0, value);
            lvChunkLines.VirtualListSize = _chunkLineCount;
            lvChunkLines.Invalidate();
        }
    }

    int IMainView.ChunkExecutingLine
    {
        // Kept in view as in ListBox2: the row of the chunk file whose M0==line is executing.
        set => Highlight(lvChunkLines, ref _chunkExecutingLine, value, _chunkLineCount);
    }

    int IMainView.ProgramLineCount
    {
        set
        {
            _programLineCount = Math.Max(0, value);
            listBox2.VirtualListSize = _programLineCount;
            listBox2.Invalidate();
        }
    }

    int IMainView.ExecutingLine
    {
        // Kept in view: ListBox2's index follows M0, the synchronous assignment of the executing block.
        set => Highlight(listBox2, ref _executingLine, value, _programLineCount);
    }

    int IMainView.FocusedLine
    {
        set
        {
            if (value < 1 || value > _programLineCount)
            {
                return;
            }

            listBox2.SelectedIndices.Clear();
            listBox2.SelectedIndices.Add(value - 1);
            listBox2.EnsureVisible(value - 1);
            listBox2.Focus();
        }
    }

    public int SelectedLine => listBox2.SelectedIndices.Count > 0 ? listBox2.SelectedIndices[0] + 1 : 0;

    /// <inheritdoc />
    /// <remarks>Selected blocks: lines A..B selected together (shift-click) in the program's lines; one line selected
    /// (or none) runs to the end. A virtual list gives its selected indices in ascending order.</remarks>
    public int? ToBlock => listBox2.SelectedIndices.Count > 1 ? listBox2.SelectedIndices[listBox2.SelectedIndices.Count - 1] + 1 : null;

    CommandStates IMainView.Commands
    {
        set
        {
            btnConnect.Enabled = value.Connect;
            cboDevice.Enabled = txtIp.Enabled = cboPort.Enabled = cboBaud.Enabled = numDeviceNumber.Enabled = value.Connect;
            btnDisconnect.Enabled = value.Disconnect;
            btnOpen.Enabled = value.Open;
            btnCheck.Enabled = value.Check;
            btnSplit.Enabled = value.Split;
            numBlocksPerChunk.Enabled = value.Split;
            btnExecute.Enabled = value.Execute;
            cboStrategy.Enabled = value.Execute;
            btnHold.Enabled = value.Hold;
            btnResume.Enabled = value.Resume;
            btnAbort.Enabled = value.Abort;
            btnStartFromLine.Enabled = value.StartFromLine;
            btnResumeInterrupted.Enabled = value.ResumeInterrupted;
        }
    }

    public bool SingleBlock => chkSingleBlock.Checked;

    double IMainView.FeedOverride
    {
        get => (double)numFeed.Value;
        set
        {
            _updating = true;
            try
            {
                var v = Math.Clamp((decimal)value, numFeed.Minimum, numFeed.Maximum);
                numFeed.Value = v;
                trkFeed.Value = Math.Clamp((int)Math.Round(v), trkFeed.Minimum, trkFeed.Maximum);
            }
            finally
            {
                _updating = false;
            }
        }
    }

    ToolpathFrame IMainView.Toolpath
    {
        set
        {
            // The presenter's frame is pinned and never moves: wrapped once, repainted whenever it changed.
            if (_toolpathBitmap is null || _toolpathFrame != value)
            {
                var old = _toolpathBitmap;
                _toolpathFrame = value;
                _toolpathBitmap = new Bitmap(value.Width, value.Height, value.Stride, PixelFormat.Format32bppPArgb, value.Scan0);
                picToolpath.Image = _toolpathBitmap;
                old?.Dispose();
            }
            else
            {
                picToolpath.Invalidate();
            }
        }
    }

    string IMainView.ToolpathCaption
    {
        set => lblToolpath.Text = value;
    }

    StatusDisplay IMainView.Status
    {
        set
        {
            var values = value.Rows;
            for (var row = 0; row < lblStatusValues.Length && row < values.Count; row++)
            {
                lblStatusValues[row].Text = values[row];
            }

            progressBar.Value = Math.Clamp(value.ProgressPercent, progressBar.Minimum, progressBar.Maximum);
            stsState.Text = $"{value.State}   {value.CurrentLine}   {value.Progress}";
        }
    }

    public void AppendLog(IReadOnlyList<string> lines)
    {
        if (lines.Count == 0)
        {
            return;
        }

        // The pane keeps the recent past only; the full log is Serilog's business.
        if (txtLog.TextLength > 200_000)
        {
            txtLog.Text = txtLog.Text[^100_000..];
        }

        txtLog.AppendText(string.Join(Environment.NewLine, lines) + Environment.NewLine);
    }

    public Task<bool> ConfirmAsync(string title, string text)
    {
        // The message box is modal; what it asks is kept so a UI test can see it (the timers still run meanwhile).
        _dialog = (title, text);
        try
        {
            return Task.FromResult(MessageBox.Show(this, text, title, MessageBoxButtons.YesNo, MessageBoxIcon.Question, MessageBoxDefaultButton.Button2) == DialogResult.Yes);
        }
        finally
        {
            _dialog = null;
        }
    }

    public void ShowError(string message)
    {
        _errorsShown.Add(message);
        _dialog = (_texts[TextId.Title], message);
        try
        {
            MessageBox.Show(this, message, _texts[TextId.Title], MessageBoxButtons.OK, MessageBoxIcon.Error);
        }
        finally
        {
            _dialog = null;
        }
    }
}
