namespace PmacStream.Hmi;

/// <summary>A control's place on the form, in pixels of the client area (or of its group box for children).</summary>
/// <param name="X">Left.</param>
/// <param name="Y">Top.</param>
/// <param name="Width">Width.</param>
/// <param name="Height">Height.</param>
public readonly record struct LayoutBox(int X, int Y, int Width, int Height);

/// <summary>
/// The screen's geometry: the WinForms form places its controls here, and its UI test clicks at these places, so
/// the two cannot drift apart. Settings across the top (connection; program, strategy and download window; feed
/// override), the chunk files (ListBox1) and their lines and the program lines (ListBox2) in the middle, commands
/// and status on the right, diagnostics, the log and the toolpath pane at the bottom; the machine profile selector in the
/// program group (<see cref="ProfileCombo"/>) and the program-stop banner above Execute (<see cref="ProgramStopBanner"/>).
/// </summary>
public static class HmiLayout
{
    /// <summary>Client area width.</summary>
    public const int ClientWidth = 1280;

    /// <summary>Client area height above the status strip.</summary>
    public const int ClientHeight = 960;

    /// <summary>Status strip height (docked at the bottom).</summary>
    public const int StatusStripHeight = 22;

    // ---- top row: group boxes and their children (child boxes are relative to the group)

    /// <summary>Connection group box.</summary>
    public static readonly LayoutBox ConnectionGroup = new(8, 8, 430, 160);
    /// <summary>Device type label.</summary>
    public static readonly LayoutBox DeviceLabel = new(12, 26, 80, 20);
    /// <summary>Device type combo.</summary>
    public static readonly LayoutBox DeviceCombo = new(96, 22, 160, 23);
    /// <summary>IP label.</summary>
    public static readonly LayoutBox IpLabel = new(12, 54, 80, 20);
    /// <summary>IP text box.</summary>
    public static readonly LayoutBox IpText = new(96, 50, 160, 23);
    /// <summary>Serial port label.</summary>
    public static readonly LayoutBox PortLabel = new(12, 82, 80, 20);
    /// <summary>Serial port combo.</summary>
    public static readonly LayoutBox PortCombo = new(96, 78, 80, 23);
    /// <summary>Baud label.</summary>
    public static readonly LayoutBox BaudLabel = new(182, 82, 60, 20);
    /// <summary>Baud combo.</summary>
    public static readonly LayoutBox BaudCombo = new(246, 78, 80, 23);
    /// <summary>PComm32 device number label.</summary>
    public static readonly LayoutBox DeviceNumberLabel = new(12, 110, 80, 20);
    /// <summary>PComm32 device number box.</summary>
    public static readonly LayoutBox DeviceNumberBox = new(96, 106, 60, 23);
    /// <summary>Connect button.</summary>
    public static readonly LayoutBox ConnectButton = new(336, 20, 84, 28);
    /// <summary>Disconnect button.</summary>
    public static readonly LayoutBox DisconnectButton = new(336, 52, 84, 28);
    /// <summary>Connection state label.</summary>
    public static readonly LayoutBox ConnectionStateLabel = new(170, 110, 250, 40);

    /// <summary>Program group box.</summary>
    public static readonly LayoutBox ProgramGroup = new(446, 8, 420, 160);
    /// <summary>Open button.</summary>
    public static readonly LayoutBox OpenButton = new(12, 20, 90, 28);
    /// <summary>Program path label.</summary>
    public static readonly LayoutBox PathLabel = new(108, 26, 300, 20);
    /// <summary>Check button.</summary>
    public static readonly LayoutBox CheckButton = new(12, 54, 90, 28);
    /// <summary>Split button.</summary>
    public static readonly LayoutBox SplitButton = new(108, 54, 90, 28);
    /// <summary>Blocks per chunk label.</summary>
    public static readonly LayoutBox BlocksPerChunkLabel = new(206, 60, 100, 20);
    /// <summary>Blocks per chunk box.</summary>
    public static readonly LayoutBox BlocksPerChunkBox = new(310, 56, 96, 23);
    /// <summary>Strategy label.</summary>
    public static readonly LayoutBox StrategyLabel = new(12, 92, 90, 20);
    /// <summary>Strategy combo.</summary>
    public static readonly LayoutBox StrategyCombo = new(108, 88, 110, 23);
    /// <summary>Download window label (percent of a chunk).</summary>
    public static readonly LayoutBox WindowLabel = new(226, 92, 80, 20);
    /// <summary>Download window start box (percent).</summary>
    public static readonly LayoutBox WindowStartBox = new(310, 88, 44, 23);
    /// <summary>The dash between the window's boxes.</summary>
    public static readonly LayoutBox WindowDash = new(354, 92, 10, 20);
    /// <summary>Download window end box (percent).</summary>
    public static readonly LayoutBox WindowEndBox = new(364, 88, 44, 23);
    /// <summary>Machine profile label.</summary>
    public static readonly LayoutBox ProfileLabel = new(12, 128, 90, 20);
    /// <summary>Machine profile combo box (the built-in profiles).</summary>
    public static readonly LayoutBox ProfileCombo = new(108, 124, 110, 23);
    /// <summary>Language label.</summary>
    public static readonly LayoutBox LanguageLabel = new(226, 128, 80, 20);
    /// <summary>Language combo.</summary>
    public static readonly LayoutBox LanguageCombo = new(310, 124, 96, 23);

    /// <summary>Feed override group box.</summary>
    public static readonly LayoutBox FeedGroup = new(874, 8, 398, 160);
    /// <summary>What the feed override does (two lines).</summary>
    public static readonly LayoutBox FeedLabel = new(12, 20, 374, 32);
    /// <summary>Feed override slider.</summary>
    public static readonly LayoutBox FeedTrackBar = new(12, 56, 280, 45);
    /// <summary>Feed override numeric box.</summary>
    public static readonly LayoutBox FeedBox = new(300, 58, 84, 23);
    /// <summary>Feed override unit label (%).</summary>
    public static readonly LayoutBox FeedUnitLabel = new(300, 86, 84, 20);
    /// <summary>Single-block check box.</summary>
    public static readonly LayoutBox SingleBlockCheck = new(12, 126, 150, 24);
    /// <summary>Optional-stop check box (M01 stops while ticked).</summary>
    public static readonly LayoutBox OptionalStopCheck = new(170, 126, 216, 24);

    // ---- middle: ListBox1 (chunk files and their lines), ListBox2 (program lines), commands and status

    /// <summary>Chunk files label.</summary>
    public static readonly LayoutBox ChunkFilesLabel = new(8, 176, 360, 18);
    /// <summary>ListBox1: chunk files.</summary>
    public static readonly LayoutBox ChunkFilesList = new(8, 196, 360, 140);
    /// <summary>Chunk lines label.</summary>
    public static readonly LayoutBox ChunkLinesLabel = new(8, 344, 360, 18);
    /// <summary>Lines of the selected chunk file (virtual).</summary>
    public static readonly LayoutBox ChunkLinesList = new(8, 364, 360, 252);
    /// <summary>Program lines label.</summary>
    public static readonly LayoutBox ProgramLinesLabel = new(376, 176, 420, 18);
    /// <summary>ListBox2: program lines (virtual).</summary>
    public static readonly LayoutBox ProgramLinesList = new(376, 196, 420, 420);

    /// <summary>The program-stop banner (M00/M01: stopped at line n, Resume continues); empty while the job runs.</summary>
    public static readonly LayoutBox ProgramStopBanner = new(804, 176, 468, 18);
    /// <summary>Execute button.</summary>
    public static readonly LayoutBox ExecuteButton = new(804, 196, 114, 44);
    /// <summary>Hold button.</summary>
    public static readonly LayoutBox HoldButton = new(922, 196, 114, 44);
    /// <summary>Resume button.</summary>
    public static readonly LayoutBox ResumeButton = new(1040, 196, 114, 44);
    /// <summary>Abort button.</summary>
    public static readonly LayoutBox AbortButton = new(1158, 196, 114, 44);
    /// <summary>Start from selected line button.</summary>
    public static readonly LayoutBox StartFromLineButton = new(804, 248, 232, 34);
    /// <summary>Resume after interruption button.</summary>
    public static readonly LayoutBox ResumeInterruptedButton = new(1040, 248, 232, 34);

    /// <summary>Status group box.</summary>
    public static readonly LayoutBox StatusGroup = new(804, 290, 468, 326);

    /// <summary>Status rows inside the status group, in display order (caption left, value right).</summary>
    public static IReadOnlyList<TextId> StatusRows { get; } =
    [
        TextId.JobState, TextId.TotalFiles, TextId.TotalLines, TextId.CurrentFile, TextId.CurrentLine,
        TextId.Progress, TextId.FeedOverride, TextId.Feed, TextId.DownloadWindow, TextId.Elapsed, TextId.Eta,
    ];

    /// <summary>Caption box of status row <paramref name="row"/> (relative to the status group).</summary>
    public static LayoutBox StatusCaption(int row) => new(10, 20 + (row * 24), 150, 20);

    /// <summary>Value box of status row <paramref name="row"/> (relative to the status group).</summary>
    public static LayoutBox StatusValue(int row) => new(164, 20 + (row * 24), 294, 20);

    /// <summary>Progress bar (relative to the status group).</summary>
    public static readonly LayoutBox ProgressBar = new(10, 290, 448, 16);

    // ---- bottom: diagnostics, log and the toolpath pane

    /// <summary>Diagnostics label.</summary>
    public static readonly LayoutBox DiagnosticsLabel = new(8, 624, 360, 18);
    /// <summary>Diagnostics list.</summary>
    public static readonly LayoutBox DiagnosticsList = new(8, 644, 360, 308);
    /// <summary>Log label.</summary>
    public static readonly LayoutBox LogLabel = new(376, 624, 420, 18);
    /// <summary>Log pane.</summary>
    public static readonly LayoutBox LogText = new(376, 644, 420, 308);
    /// <summary>Toolpath pane caption.</summary>
    public static readonly LayoutBox ToolpathLabel = new(804, 624, 468, 18);
    /// <summary>Toolpath pane: the planned path with the executed part over it (the presenter draws it at this size).</summary>
    public static readonly LayoutBox ToolpathPane = new(804, 644, 468, 308);

    /// <summary>Width of the line-number column of the program and chunk-line lists.</summary>
    public const int LineNumberColumnWidth = 80;
}
