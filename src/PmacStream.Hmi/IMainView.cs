namespace PmacStream.Hmi;

/// <summary>A virtual list asks for one line's text: the presenter fills <see cref="Text"/>.</summary>
public sealed class LineRequestEventArgs(int line) : EventArgs
{
    /// <summary>1-based line number asked for.</summary>
    public int Line { get; } = line;

    /// <summary>The text to show (empty when the line is not available).</summary>
    public string Text { get; set; } = string.Empty;
}

/// <summary>Which commands the screen offers now (buttons enabled or disabled).</summary>
public sealed record CommandStates(
    bool Connect,
    bool Disconnect,
    bool Open,
    bool Check,
    bool Split,
    bool Execute,
    bool Hold,
    bool Resume,
    bool Abort,
    bool StartFromLine,
    bool ResumeInterrupted)
{
    /// <summary>Everything disabled (while an operation runs).</summary>
    public static CommandStates None { get; } = new(false, false, false, false, false, false, false, false, false, false, false);
}

/// <summary>The status panel's texts, formatted by the presenter in the chosen language.</summary>
/// <param name="State">Job state.</param>
/// <param name="TotalFiles">Chunk files of the split.</param>
/// <param name="ProgramLines">Lines of the program (or the indexing progress).</param>
/// <param name="CurrentFile">The chunk file executing.</param>
/// <param name="CurrentLine">The source line executing.</param>
/// <param name="ProgressPercent">Progress bar value.</param>
/// <param name="Progress">Progress text.</param>
/// <param name="FeedOverride">The feed override in force (and the setting it slews to).</param>
/// <param name="Feed">Programmed feed x override = resulting feed.</param>
/// <param name="DownloadWindow">The chunk strategy's download window, and the lines it spans in the executing chunk.</param>
/// <param name="Elapsed">Time since the start.</param>
/// <param name="Eta">Time remaining.</param>
public sealed record StatusDisplay(
    string State,
    string TotalFiles,
    string ProgramLines,
    string CurrentFile,
    string CurrentLine,
    int ProgressPercent,
    string Progress,
    string FeedOverride,
    string Feed,
    string DownloadWindow,
    string Elapsed,
    string Eta)
{
    /// <summary>The values in <see cref="HmiLayout.StatusRows"/> order (what the panel's value labels show).</summary>
    public IReadOnlyList<string> Rows =>
        [State, TotalFiles, ProgramLines, CurrentFile, CurrentLine, Progress, FeedOverride, Feed, DownloadWindow, Elapsed, Eta];
}

/// <summary>
/// The HMI screen as a passive view: the form raises events and shows what the presenter
/// sets; it holds no logic. Two lists are virtual: they raise <see cref="ProgramLineNeeded"/> and
/// <see cref="ChunkLineNeeded"/> for the rows on screen, so a 10,000,000-line program is never loaded.
/// Everything is called on the UI thread.
/// </summary>
public interface IMainView
{
    // ---- language

    /// <summary>All control texts in the chosen language.</summary>
    IReadOnlyDictionary<TextId, string> Texts { set; }

    /// <summary>The language selector.</summary>
    HmiLanguage Language { get; }

    /// <summary>The operator picked another language.</summary>
    event EventHandler? LanguageChanged;

    // ---- connection panel

    /// <summary>Device type, IP, serial port and baud, PComm32 device number as entered.</summary>
    ConnectionSettings ConnectionSettings { get; }

    /// <summary>Connection state text.</summary>
    string ConnectionState { set; }

    /// <summary>Connect clicked.</summary>
    event EventHandler? ConnectRequested;

    /// <summary>Disconnect clicked.</summary>
    event EventHandler? DisconnectRequested;

    // ---- program

    /// <summary>A program file was chosen in the open dialog (the argument is its path).</summary>
    event EventHandler<string>? OpenRequested;

    /// <summary>The open program's path (title bar / label).</summary>
    string ProgramPath { set; }

    /// <summary>Check clicked.</summary>
    event EventHandler? CheckRequested;

    /// <summary>Diagnostics list rows.</summary>
    IReadOnlyList<string> Diagnostics { set; }

    /// <summary>A diagnostic row was double-clicked (its index).</summary>
    event EventHandler<int>? DiagnosticActivated;

    /// <summary>Blocks per chunk file (numeric box); the presenter shows the run settings' value first.</summary>
    int BlocksPerChunk { get; set; }

    /// <summary>
    /// The download window of the chunk strategy: start and end as fractions of the executing chunk (lines 600-700
    /// of a 1000-line chunk are 0.6 and 0.7). The presenter shows the run settings' window; setting it raises no event.
    /// </summary>
    (double Start, double End) DownloadWindow { get; set; }

    /// <summary>The operator changed the download window (it applies to the next job started).</summary>
    event EventHandler? DownloadWindowChanged;

    /// <summary>Split clicked.</summary>
    event EventHandler? SplitRequested;

    /// <summary>Strategy selector items.</summary>
    IReadOnlyList<string> Strategies { set; }

    /// <summary>The selected strategy.</summary>
    string SelectedStrategy { get; }

    /// <summary>Machine profile selector items (the built-in profiles' names).</summary>
    IReadOnlyList<string> Profiles { set; }

    /// <summary>The selected machine profile's name (setting it raises no <see cref="ProfileChanged"/>).</summary>
    string SelectedProfile { get; set; }

    /// <summary>The operator chose another machine profile: the check and the split are dropped, the toolpath drawn anew.</summary>
    event EventHandler? ProfileChanged;

    // ---- ListBox1: chunk files and their lines

    /// <summary>Chunk file rows (file name and source line range).</summary>
    IReadOnlyList<string> ChunkFiles { set; }

    /// <summary>A chunk file row was selected by the operator (its index, -1 for none).</summary>
    event EventHandler<int>? ChunkSelected;

    /// <summary>Selects a chunk file row (-1 for none) as the chunk lines follow execution; raises no <see cref="ChunkSelected"/>.</summary>
    int SelectedChunk { set; }

    /// <summary>Lines of the selected chunk file (virtual list size).</summary>
    int ChunkLineCount { set; }

    /// <summary>The row of the selected chunk file that holds the executing block (its <c>M0==line</c>), highlighted and kept in view; 0 for none.</summary>
    int ChunkExecutingLine { set; }

    /// <summary>The chunk-lines list needs a row's text.</summary>
    event EventHandler<LineRequestEventArgs>? ChunkLineNeeded;

    // ---- ListBox2: program lines

    /// <summary>Program lines (virtual list size); grows while a large file is being indexed.</summary>
    int ProgramLineCount { set; }

    /// <summary>The program list needs a row's text.</summary>
    event EventHandler<LineRequestEventArgs>? ProgramLineNeeded;

    /// <summary>The executing line (from M0), highlighted and kept in view; 0 for none.</summary>
    int ExecutingLine { set; }

    /// <summary>Selects a line and scrolls it into view (diagnostic double-click, chunk selection).</summary>
    int FocusedLine { set; }

    /// <summary>The line the operator selected, 0 for none.</summary>
    int SelectedLine { get; }

    /// <summary>
    /// The start-from-block's optional "to block": selected blocks, the job ends after this line's block (a move);
    /// null (left empty): the job runs to the program's end. A view without the field says null.
    /// </summary>
    int? ToBlock => null;

    // ---- commands

    /// <summary>Which buttons are enabled.</summary>
    CommandStates Commands { set; }

    /// <summary>Execute (程序段执行) clicked.</summary>
    event EventHandler? ExecuteRequested;

    /// <summary>Hold clicked.</summary>
    event EventHandler? HoldRequested;

    /// <summary>Resume clicked.</summary>
    event EventHandler? ResumeRequested;

    /// <summary>Abort clicked.</summary>
    event EventHandler? AbortRequested;

    /// <summary>Start from selected line clicked.</summary>
    event EventHandler? StartFromLineRequested;

    /// <summary>Resume after interruption clicked.</summary>
    event EventHandler? ResumeInterruptedRequested;

    /// <summary>Single-block check box state.</summary>
    bool SingleBlock { get; }

    /// <summary>Single-block check box changed.</summary>
    event EventHandler? SingleBlockChanged;

    /// <summary>Optional-stop check box: M01 stops while it is ticked (setting it raises no <see cref="OptionalStopChanged"/>).</summary>
    bool OptionalStop { get; set; }

    /// <summary>Optional-stop check box changed (applies at once to a running job).</summary>
    event EventHandler? OptionalStopChanged;

    /// <summary>
    /// The program-stop banner above Execute (<see cref="HmiLayout.ProgramStopBanner"/>): "Program stop (M00) at line n:
    /// Resume continues" while the job waits at a stop, empty (hidden) otherwise.
    /// </summary>
    string ProgramStopBanner { set; }

    // ---- feed override

    /// <summary>
    /// The feed override in percent, <see cref="Jobs.FeedOverrides.Minimum"/>..<see cref="Jobs.FeedOverrides.Maximum"/>
    /// (slider and box; setting it raises no <see cref="FeedOverrideChanged"/>).
    /// </summary>
    double FeedOverride { get; set; }

    /// <summary>The operator changed the feed override (slider or box).</summary>
    event EventHandler? FeedOverrideChanged;

    // ---- toolpath pane

    /// <summary>
    /// The toolpath pane's picture: the same frame each time it is set, set again whenever its pixels changed (the
    /// executed part grew, the marker moved); the view shows its pixels as they are, at
    /// <see cref="HmiLayout.ToolpathPane"/>'s size.
    /// </summary>
    ToolpathFrame Toolpath { set; }

    /// <summary>The line above the toolpath pane: program, drawing progress, what the colours mean.</summary>
    string ToolpathCaption { set; }

    // ---- status, log, dialogs

    /// <summary>Status strip texts and progress bar.</summary>
    StatusDisplay Status { set; }

    /// <summary>Appends lines to the live log pane.</summary>
    void AppendLog(IReadOnlyList<string> lines);

    /// <summary>Asks the operator (Yes/No); the presenter awaits the answer.</summary>
    Task<bool> ConfirmAsync(string title, string text);

    /// <summary>Shows an error the operator must read.</summary>
    void ShowError(string message);
}
