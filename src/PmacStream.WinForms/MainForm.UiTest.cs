using System.Globalization;
using PmacStream.Hmi;

namespace PmacStream.WinForms;

/// <summary>
/// What the automated UI test needs from the form beyond real input: a snapshot of what the screen shows, and a
/// scripted mode that presses the real controls (<see cref="Button.PerformClick"/>, the selection an operator's
/// click makes). Nothing here decides anything: the presenter still does all the work through the view's events.
/// </summary>
internal sealed partial class MainForm
{
    private const int LogTailLines = 40;

    private readonly List<string> _errorsShown = [];
    private (string Title, string Text)? _dialog;
    private int _ticks;

    /// <summary>The controls a test may read or press, by their field names.</summary>
    private IEnumerable<(string Name, Control Control)> NamedControls() =>
    [
        (nameof(cboDevice), cboDevice), (nameof(btnConnect), btnConnect), (nameof(btnDisconnect), btnDisconnect),
        (nameof(lblConnectionState), lblConnectionState), (nameof(btnOpen), btnOpen), (nameof(lblPath), lblPath),
        (nameof(btnCheck), btnCheck), (nameof(btnSplit), btnSplit), (nameof(numBlocksPerChunk), numBlocksPerChunk),
        (nameof(cboStrategy), cboStrategy), (nameof(cboLanguage), cboLanguage), (nameof(numFeed), numFeed),
        (nameof(lblFeedUnit), lblFeedUnit), (nameof(grpFeed), grpFeed), (nameof(lblFeed), lblFeed),
        (nameof(numWindowStart), numWindowStart), (nameof(numWindowEnd), numWindowEnd), (nameof(lblWindow), lblWindow),
        (nameof(lblToolpath), lblToolpath), (nameof(chkSingleBlock), chkSingleBlock), (nameof(btnExecute), btnExecute),
        (nameof(btnHold), btnHold), (nameof(btnResume), btnResume), (nameof(btnAbort), btnAbort),
        (nameof(btnStartFromLine), btnStartFromLine), (nameof(btnResumeInterrupted), btnResumeInterrupted),
        (nameof(grpStatus), grpStatus), (nameof(lblProgramLines), lblProgramLines), (nameof(cboProfile), cboProfile),
        (nameof(chkOptionalStop), chkOptionalStop), (nameof(lblProgramStop), lblProgramStop),
        .. ConsoleControls(),
    ];

    /// <summary>The console pages' controls a test may read or press.</summary>
    private IEnumerable<(string Name, Control Control)> ConsoleControls() =>
    [
        (nameof(lblAlarmBanner), lblAlarmBanner), (nameof(tabConsole), tabConsole), (nameof(btnHomeAll), btnHomeAll),
        (nameof(btnLoadLibrary), btnLoadLibrary), (nameof(lblMachineSummary), lblMachineSummary), (nameof(cboJogAxis), cboJogAxis),
        (nameof(cboJogStep), cboJogStep), (nameof(numJogSpeed), numJogSpeed), (nameof(btnJogPlus), btnJogPlus), (nameof(btnJogMinus), btnJogMinus),
        (nameof(txtMdi), txtMdi), (nameof(btnMdiSend), btnMdiSend), (nameof(btnClearAlarms), btnClearAlarms),
        (nameof(lblConsoleMessage), lblConsoleMessage), (nameof(txtTouchValue), txtTouchValue), (nameof(btnOffsetsApply), btnOffsetsApply),
        (nameof(btnOffsetsReload), btnOffsetsReload), (nameof(lblOffsetsMessage), lblOffsetsMessage), (nameof(btnToolsApply), btnToolsApply),
        (nameof(lblToolsMessage), lblToolsMessage), (nameof(btnHistoryRefresh), btnHistoryRefresh),
        .. btnHomeAxis.Concat(btnTouchOff).Select(b => (b.Name, (Control)b)),
    ];

    /// <summary>What the screen shows now.</summary>
    internal UiSnapshot Snapshot(long sequence, int lastCommand, string? commandError)
    {
        var origin = PointToScreen(Point.Empty);
        var top = listBox2.VirtualListSize > 0 ? listBox2.TopItem?.Index ?? -1 : -1;
        var rowHeight = top >= 0 ? listBox2.GetItemRect(top).Height : 0;
        var executingText = RowText(ProgramLineNeeded, _executingLine, _programLineCount);
        var chunkTop = lvChunkLines.VirtualListSize > 0 ? lvChunkLines.TopItem?.Index ?? -1 : -1;
        var chunkRowHeight = chunkTop >= 0 ? lvChunkLines.GetItemRect(chunkTop).Height : 0;

        return new UiSnapshot
        {
            Sequence = sequence,
            Ticks = _ticks,
            Title = Text,
            ClientX = origin.X,
            ClientY = origin.Y,
            ClientWidth = ClientSize.Width,
            ClientHeight = ClientSize.Height,
            Controls = NamedControls().ToDictionary(c => c.Name, c => new UiControl(ShownText(c.Control), c.Control.Enabled)),
            ChunkFiles = listBox1.Items.Cast<object>().Select(o => o.ToString() ?? string.Empty).ToList(),
            ChunkLineCount = lvChunkLines.VirtualListSize,
            ProgramLineCount = _programLineCount,
            ExecutingLine = _executingLine,
            ExecutingRowText = executingText,
            SelectedChunk = listBox1.SelectedIndex,
            ChunkExecutingLine = _chunkExecutingLine,
            ChunkExecutingRowText = RowText(ChunkLineNeeded, _chunkExecutingLine, _chunkLineCount),
            ChunkTopLine = chunkTop + 1,
            ChunkVisibleLines = chunkRowHeight > 0 ? (lvChunkLines.ClientSize.Height / chunkRowHeight) - 1 : 0,
            SelectedLine = SelectedLine,
            ToBlock = ToBlock,
            TopLine = top + 1,
            VisibleLines = rowHeight > 0 ? (listBox2.ClientSize.Height / rowHeight) - 1 : 0,
            Status = lblStatusValues.Select(l => l.Text).ToList(),
            ProgressPercent = progressBar.Value,
            Diagnostics = lstDiagnostics.Items.Cast<object>().Select(o => o.ToString() ?? string.Empty).ToList(),
            LogTail = txtLog.Lines.Where(l => l.Length > 0).TakeLast(LogTailLines).ToList(),
            DialogTitle = _dialog?.Title,
            DialogText = _dialog?.Text,
            Errors = [.. _errorsShown],
            Console = ConsoleSnapshot(),
            LastCommand = lastCommand,
            CommandError = commandError,
        };
    }

    /// <summary>
    /// Carries out one scripted command the way the operator's input would: <c>click NAME</c>, <c>select-chunk INDEX</c>, <c>select-line N</c>, <c>select-lines A B</c>,
    /// <c>language N</c> (the selector's index), <c>feed VALUE</c> (the override box), <c>window START END</c> (percent),
    /// <c>open PATH</c> (as chosen in the open dialog), <c>close</c>.
    /// </summary>
    internal void RunScripted(string command)
    {
        var space = command.IndexOf(' ', StringComparison.Ordinal);
        var verb = space < 0 ? command : command[..space];
        var argument = space < 0 ? string.Empty : command[(space + 1)..].Trim();
        switch (verb)
        {
            case "click":
                var control = NamedControls().FirstOrDefault(c => c.Name == argument).Control
                    ?? throw new ArgumentException($"no control named {argument}");
                if (!control.Enabled)
                {
                    throw new InvalidOperationException($"{argument} is disabled");
                }

                if (control is Button button)
                {
                    button.PerformClick();
                }
                else if (control is CheckBox check)
                {
                    check.Checked = !check.Checked;
                }
                else
                {
                    throw new ArgumentException($"{argument} cannot be clicked");
                }

                break;
            case "select-chunk":
                listBox1.SelectedIndex = int.Parse(argument, CultureInfo.InvariantCulture);
                break;
            case "select-line":
                ((IMainView)this).FocusedLine = int.Parse(argument, CultureInfo.InvariantCulture);
                break;
            case "select-lines":
                // A..B as a Shift+click leaves it: A focused and selected, every line to B selected with it.
                var range = argument.Split(' ', StringSplitOptions.RemoveEmptyEntries);
                var (from, to) = (int.Parse(range[0], CultureInfo.InvariantCulture), int.Parse(range[1], CultureInfo.InvariantCulture));
                ((IMainView)this).FocusedLine = from;
                for (var index = from; index < to; index++)
                {
                    listBox2.SelectedIndices.Add(index);
                }

                break;
            case "language":
                cboLanguage.SelectedIndex = int.Parse(argument, CultureInfo.InvariantCulture);
                break;
            case "feed":
                numFeed.Value = decimal.Parse(argument, CultureInfo.InvariantCulture);
                break;
            case "window":
                var parts = argument.Split(' ', StringSplitOptions.RemoveEmptyEntries);
                numWindowEnd.Value = decimal.Parse(parts[1], CultureInfo.InvariantCulture);
                numWindowStart.Value = decimal.Parse(parts[0], CultureInfo.InvariantCulture);
                break;
            case "open":
                OpenRequested?.Invoke(this, argument);
                break;
            case "close":
                Close();
                break;
            case "tab" or "jog-step" or "jog-axis" or "jog" or "mdi" or "cell" or "inject":
                RunConsoleScripted(verb, argument);
                break;
            default:
                throw new ArgumentException($"unknown command '{command}'");
        }
    }

    private string RowText(EventHandler<LineRequestEventArgs>? source, int line, int count)
    {
        if (line < 1 || line > count)
        {
            return string.Empty;
        }

        var request = new LineRequestEventArgs(line);
        source?.Invoke(this, request);
        return request.Text;
    }

    private static string ShownText(Control control) => control switch
    {
        // The box's text as shown: reading Value would commit a half-typed number (and send it).
        NumericUpDown n => n.Text,
        CheckBox c => c.Checked ? "checked" : "unchecked",
        _ => control.Text,
    };
}
