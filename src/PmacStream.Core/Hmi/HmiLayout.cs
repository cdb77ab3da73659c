namespace PmacStream.Hmi;

/// <summary>A control's place on the form, in pixels of the client area (or of its group box for children).</summary>
/// <param name="X">Left.</param>
/// <param name="Y">Top.</param>
/// <param name="Width">Width.</param>
/// <param name="Height">Height.</param>
public readonly record struct LayoutBox(int X, int Y, int Width, int Height);

/// <summary>
/// The screen's geometry: the WinForms form places its controls here, and its UI test clicks at these places, so
/// the two cannot drift apart. Settings across the top, the chunk files
/// (ListBox1) and the program lines (ListBox2) in the middle, commands and status on the right, diagnostics and the
/// log at the bottom.
/// </summary>
public static class HmiLayout
{
    /// <summary>Client area width.</summary>
    public const int ClientWidth = 1280;

    /// <summary>Client area height above the status strip.</summary>
    public const int ClientHeight = 780;

    /// <summary>Status strip height (docked at the bottom).</summary>
    public const int StatusStripHeight = 22;

    // ---- top row: group boxes and their children (child boxes are relative to the group)

    /// <summary>Connection group box.</summary>
    public static readonly LayoutBox ConnectionGroup = new(8, 8, 430, 152);
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
    public static readonly LayoutBox ConnectionStateLabel = new(170, 110, 250, 36);

    /// <summary>Program group box.</summary>
    public static readonly LayoutBox ProgramGroup = new(446, 8, 420, 152);
    /// <summary>Open button.</summary>
    public static readonly LayoutBox OpenButton = new(12, 20, 90, 30);
    /// <summary>Program path label.</summary>
    public static readonly LayoutBox PathLabel = new(108, 27, 300, 20);
    /// <summary>Check button.</summary>
    public static readonly LayoutBox CheckButton = new(12, 56, 90, 30);
    /// <summary>Split button.</summary>
    public static readonly LayoutBox SplitButton = new(108, 56, 90, 30);
    /// <summary>Lines per chunk label.</summary>
    public static readonly LayoutBox LinesPerChunkLabel = new(206, 63, 100, 20);
    /// <summary>Lines per chunk box.</summary>
    public static readonly LayoutBox LinesPerChunkBox = new(310, 59, 96, 23);
    /// <summary>Strategy label.</summary>
    public static readonly LayoutBox StrategyLabel = new(12, 100, 90, 20);
    /// <summary>Strategy combo.</summary>
    public static readonly LayoutBox StrategyCombo = new(108, 96, 110, 23);
    /// <summary>Language label.</summary>
    public static readonly LayoutBox LanguageLabel = new(226, 100, 80, 20);
    /// <summary>Language combo.</summary>
    public static readonly LayoutBox LanguageCombo = new(310, 96, 96, 23);

    /// <summary>Feed group box.</summary>
    public static readonly LayoutBox FeedGroup = new(874, 8, 398, 152);
    /// <summary>Feed label.</summary>
    public static readonly LayoutBox FeedLabel = new(12, 24, 120, 20);
    /// <summary>Feed slider.</summary>
    public static readonly LayoutBox FeedTrackBar = new(12, 46, 280, 45);
    /// <summary>Feed numeric box.</summary>
    public static readonly LayoutBox FeedBox = new(300, 48, 84, 23);
    /// <summary>Feed unit label (P500 or %).</summary>
    public static readonly LayoutBox FeedUnitLabel = new(300, 76, 84, 20);
    /// <summary>Single-block check box.</summary>
    public static readonly LayoutBox SingleBlockCheck = new(12, 110, 200, 24);

    // ---- middle: ListBox1 (chunk files and their lines), ListBox2 (program lines), commands and status

    /// <summary>Chunk files label.</summary>
    public static readonly LayoutBox ChunkFilesLabel = new(8, 168, 360, 18);
    /// <summary>ListBox1: chunk files.</summary>
    public static readonly LayoutBox ChunkFilesList = new(8, 188, 360, 170);
    /// <summary>Chunk lines label.</summary>
    public static readonly LayoutBox ChunkLinesLabel = new(8, 366, 360, 18);
    /// <summary>Lines of the selected chunk file (virtual).</summary>
    public static readonly LayoutBox ChunkLinesList = new(8, 386, 360, 222);
    /// <summary>Program lines label.</summary>
    public static readonly LayoutBox ProgramLinesLabel = new(376, 168, 496, 18);
    /// <summary>ListBox2: program lines (virtual).</summary>
    public static readonly LayoutBox ProgramLinesList = new(376, 188, 496, 420);

    /// <summary>Execute button.</summary>
    public static readonly LayoutBox ExecuteButton = new(880, 188, 190, 48);
    /// <summary>Hold button.</summary>
    public static readonly LayoutBox HoldButton = new(1082, 188, 190, 48);
    /// <summary>Resume button.</summary>
    public static readonly LayoutBox ResumeButton = new(880, 244, 190, 40);
    /// <summary>Abort button.</summary>
    public static readonly LayoutBox AbortButton = new(1082, 244, 190, 40);
    /// <summary>Start from selected line button.</summary>
    public static readonly LayoutBox StartFromLineButton = new(880, 292, 392, 36);
    /// <summary>Resume after interruption button.</summary>
    public static readonly LayoutBox ResumeInterruptedButton = new(880, 336, 392, 36);

    /// <summary>Status group box.</summary>
    public static readonly LayoutBox StatusGroup = new(880, 380, 392, 228);

    /// <summary>Status rows inside the status group, in display order (caption left, value right).</summary>
    public static IReadOnlyList<TextId> StatusRows { get; } =
    [
        TextId.JobState, TextId.TotalFiles, TextId.TotalLines, TextId.CurrentFile, TextId.CurrentLine,
        TextId.Progress, TextId.Feed, TextId.Elapsed, TextId.Eta,
    ];

    /// <summary>Caption box of status row <paramref name="row"/> (relative to the status group).</summary>
    public static LayoutBox StatusCaption(int row) => new(10, 20 + (row * 21), 130, 19);

    /// <summary>Value box of status row <paramref name="row"/> (relative to the status group).</summary>
    public static LayoutBox StatusValue(int row) => new(144, 20 + (row * 21), 238, 19);

    /// <summary>Progress bar (relative to the status group).</summary>
    public static readonly LayoutBox ProgressBar = new(10, 210, 372, 12);

    // ---- bottom: diagnostics and log

    /// <summary>Diagnostics label.</summary>
    public static readonly LayoutBox DiagnosticsLabel = new(8, 616, 430, 18);
    /// <summary>Diagnostics list.</summary>
    public static readonly LayoutBox DiagnosticsList = new(8, 636, 430, 136);
    /// <summary>Log label.</summary>
    public static readonly LayoutBox LogLabel = new(446, 616, 826, 18);
    /// <summary>Log pane.</summary>
    public static readonly LayoutBox LogText = new(446, 636, 826, 136);

    /// <summary>Width of the line-number column of the program and chunk-line lists.</summary>
    public const int LineNumberColumnWidth = 80;
}
