using System.Text.Json.Serialization;

namespace PmacStream.WinForms;

/// <summary>One control as the screen shows it.</summary>
/// <param name="Text">Its text (a button's caption, a combo's selected item, a box's value).</param>
/// <param name="Enabled">Whether the operator can use it.</param>
internal sealed record UiControl(string Text, bool Enabled);

/// <summary>
/// What the form shows at one moment, written by <c>UiTestChannel</c> for the automated UI test (which links
/// this file, so both sides read the same shape). Screen coordinates are the desktop's, in pixels.
/// </summary>
internal sealed record UiSnapshot
{
    /// <summary>Increases with every snapshot written.</summary>
    public long Sequence { get; init; }

    /// <summary>How often <c>timer1</c> (the streaming timer) has ticked: proof that the real message loop runs.</summary>
    public int Ticks { get; init; }

    /// <summary>Window title.</summary>
    public string Title { get; init; } = string.Empty;

    /// <summary>Client area's top-left corner on the screen, X.</summary>
    public int ClientX { get; init; }

    /// <summary>Client area's top-left corner on the screen, Y.</summary>
    public int ClientY { get; init; }

    /// <summary>Client area width.</summary>
    public int ClientWidth { get; init; }

    /// <summary>Client area height (status strip included).</summary>
    public int ClientHeight { get; init; }

    /// <summary>Named controls (buttons, combos, boxes, labels) by their field name in the form.</summary>
    public Dictionary<string, UiControl> Controls { get; init; } = [];

    /// <summary>Rows of the chunk-file list (ListBox1).</summary>
    public List<string> ChunkFiles { get; init; } = [];

    /// <summary>Lines in the chunk-lines list.</summary>
    public int ChunkLineCount { get; init; }

    /// <summary>Rows of the program list (ListBox2).</summary>
    public int ProgramLineCount { get; init; }

    /// <summary>The highlighted executing line, 0 for none.</summary>
    public int ExecutingLine { get; init; }

    /// <summary>The text shown in the executing line's row.</summary>
    public string ExecutingRowText { get; init; } = string.Empty;

    /// <summary>The selected chunk file row of ListBox1, -1 for none.</summary>
    public int SelectedChunk { get; init; }

    /// <summary>The highlighted row of the chunk lines (the executing block's <c>M0==line</c>), 0 for none.</summary>
    public int ChunkExecutingLine { get; init; }

    /// <summary>The text shown in that row.</summary>
    public string ChunkExecutingRowText { get; init; } = string.Empty;

    /// <summary>First chunk line in view (1-based), 0 when the list is empty.</summary>
    public int ChunkTopLine { get; init; }

    /// <summary>Chunk lines that fit in the list.</summary>
    public int ChunkVisibleLines { get; init; }

    /// <summary>The selected program line, 0 for none.</summary>
    public int SelectedLine { get; init; }

    /// <summary>The last program line of a selection of several (selected blocks' "to"), null for one line or none.</summary>
    public int? ToBlock { get; init; }

    /// <summary>First program line in view (1-based), 0 when the list is empty.</summary>
    public int TopLine { get; init; }

    /// <summary>Program lines that fit in the list.</summary>
    public int VisibleLines { get; init; }

    /// <summary>The status panel's values in <c>HmiLayout.StatusRows</c> order.</summary>
    public List<string> Status { get; init; } = [];

    /// <summary>The progress bar's value (percent).</summary>
    public int ProgressPercent { get; init; }

    /// <summary>Rows of the diagnostics list.</summary>
    public List<string> Diagnostics { get; init; } = [];

    /// <summary>The last lines of the log pane.</summary>
    public List<string> LogTail { get; init; } = [];

    /// <summary>Title of the open message box, null when none is open.</summary>
    public string? DialogTitle { get; init; }

    /// <summary>Text of the open message box.</summary>
    public string? DialogText { get; init; }

    /// <summary>Every error the form has shown.</summary>
    public List<string> Errors { get; init; } = [];

    /// <summary>The console pages.</summary>
    public UiConsole Console { get; init; } = new();

    /// <summary>Number of the last scripted command carried out (0 before any).</summary>
    public int LastCommand { get; init; }

    /// <summary>Why the last scripted command failed, null when it worked.</summary>
    public string? CommandError { get; init; }
}

/// <summary>One DRO row as shown.</summary>
/// <param name="Axis">Axis letter.</param>
/// <param name="Machine">Machine position text.</param>
/// <param name="Work">Work position text.</param>
/// <param name="ToGo">Distance to go text.</param>
/// <param name="Homed">The homed mark is on.</param>
internal sealed record UiDroRow(string Axis, string Machine, string Work, string ToGo, bool Homed);

/// <summary>What the console pages show.</summary>
internal sealed record UiConsole
{
    /// <summary>The console tab chosen (0 Machine, 1 Offsets, 2 Tools, 3 History).</summary>
    public int SelectedTab { get; init; }

    /// <summary>The chosen page's client origin on the screen, X (the console layout's page boxes are relative to it).</summary>
    public int PageX { get; init; }

    /// <summary>The chosen page's client origin on the screen, Y.</summary>
    public int PageY { get; init; }

    /// <summary>The DRO rows.</summary>
    public List<UiDroRow> Dro { get; init; } = [];

    /// <summary>Whether the alarm banner shows.</summary>
    public bool AlarmBannerVisible { get; init; }

    /// <summary>The MDI history rows.</summary>
    public List<string> MdiHistory { get; init; } = [];

    /// <summary>The job history rows.</summary>
    public List<string> JobHistory { get; init; } = [];

    /// <summary>The alarm history rows.</summary>
    public List<string> AlarmHistory { get; init; } = [];

    /// <summary>The first rows of the offsets grid (G54..G59.3).</summary>
    public List<List<string>> Offsets { get; init; } = [];

    /// <summary>The first rows of the tools grid.</summary>
    public List<List<string>> Tools { get; init; } = [];

    /// <summary>The Store page's job rows (job, program, station, machine, started, ended, outcome, blocks).</summary>
    public List<List<string>> StoreJobs { get; init; } = [];
}

/// <summary>
/// Generated (de)serialization of <see cref="UiSnapshot"/>: no code is emitted at run time, which under Wine once
/// ended the process from the finalizer of a dynamic method.
/// </summary>
[JsonSourceGenerationOptions(WriteIndented = true)]
[JsonSerializable(typeof(UiSnapshot))]
internal sealed partial class UiSnapshotJson : JsonSerializerContext;
