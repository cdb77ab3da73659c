namespace PmacStream.Hmi;

/// <summary>One axis row of the DRO as shown: positions formatted to the micron, the homed mark.</summary>
/// <param name="Axis">The axis letter.</param>
/// <param name="Machine">Machine position, mm.</param>
/// <param name="Work">Work position, mm.</param>
/// <param name="ToGo">Distance to go, mm.</param>
/// <param name="Homed">True when the axis is homed.</param>
public sealed record DroRow(string Axis, string Machine, string Work, string ToGo, bool Homed);

/// <summary>A jog direction button pressed or released.</summary>
/// <param name="direction">+1 or -1.</param>
public sealed class JogEventArgs(int direction) : EventArgs
{
    /// <summary>+1 or -1.</summary>
    public int Direction { get; } = direction;
}

/// <summary>
/// The console pages (Machine: DRO, jog, home, MDI, alarms; Offsets; Tools; History) and the alarm banner as a
/// passive view: the form raises these events and shows what <see cref="ConsolePresenter"/> sets. The members that
/// <see cref="IMainView"/> has too (<see cref="Language"/>, <see cref="ConfirmAsync"/>) are the same on one form.
/// </summary>
public interface IConsoleView
{
    /// <summary>The language the operator chose.</summary>
    HmiLanguage Language { get; }

    /// <summary>The operator chose another language.</summary>
    event EventHandler? LanguageChanged;

    /// <summary>Home all axes.</summary>
    event EventHandler? HomeAllRequested;

    /// <summary>Home one axis (its letter).</summary>
    event EventHandler<string>? HomeAxisRequested;

    /// <summary>A jog button pressed: one increment, or the start of a continuous jog.</summary>
    event EventHandler<JogEventArgs>? JogPressed;

    /// <summary>A jog button released: the end of a continuous jog.</summary>
    event EventHandler<JogEventArgs>? JogReleased;

    /// <summary>The MDI line sent (Return or the Send button).</summary>
    event EventHandler? MdiRequested;

    /// <summary>A block of the MDI history picked: it goes back into the MDI line.</summary>
    event EventHandler<int>? MdiHistoryPicked;

    /// <summary>Clear alarms.</summary>
    event EventHandler? ClearAlarmsRequested;

    /// <summary>Touch off an axis (its letter) in the active work offset at <see cref="TouchValue"/>.</summary>
    event EventHandler<string>? TouchOffRequested;

    /// <summary>Write the edited work offsets to the controller.</summary>
    event EventHandler? OffsetsApplyRequested;

    /// <summary>Write the edited tool table to the controller.</summary>
    event EventHandler? ToolsApplyRequested;

    /// <summary>Read the tables from the controller again (dropping edits).</summary>
    event EventHandler? TablesReloadRequested;

    /// <summary>Download the profile's library (and tables) to the built-in simulator.</summary>
    event EventHandler? LoadLibraryRequested;

    /// <summary>Read the job and alarm histories again.</summary>
    event EventHandler? HistoryRefreshRequested;

    /// <summary>The jog axis chosen (X, Y, Z).</summary>
    string JogAxis { get; set; }

    /// <summary>The jog increment chosen, mm; null for continuous.</summary>
    double? JogIncrement { get; set; }

    /// <summary>The jog speed, mm/min.</summary>
    double JogFeed { get; set; }

    /// <summary>The MDI line's text.</summary>
    string MdiText { get; set; }

    /// <summary>The value a touch-off sets, mm.</summary>
    double TouchValue { get; }

    /// <summary>The axes the jog and home controls offer.</summary>
    IReadOnlyList<string> ConsoleAxes { set; }

    /// <summary>The DRO rows.</summary>
    IReadOnlyList<DroRow> Dro { set; }

    /// <summary>Mode, active work offset, feeds, spindle and override, one line.</summary>
    string MachineSummary { set; }

    /// <summary>The alarm banner's text; empty hides it (it shows on every page).</summary>
    string AlarmBanner { set; }

    /// <summary>What the last console command did, or why it was refused.</summary>
    string ConsoleMessage { set; }

    /// <summary>Blocks sent by MDI, newest last.</summary>
    IReadOnlyList<string> MdiHistory { set; }

    /// <summary>The alarm history, newest first.</summary>
    IReadOnlyList<string> AlarmHistory { set; }

    /// <summary>The job history, newest first.</summary>
    IReadOnlyList<string> JobHistory { set; }

    /// <summary>Work offset rows: name, X, Y, Z (the cells as the operator edited them).</summary>
    IReadOnlyList<IReadOnlyList<string>> OffsetRows { get; set; }

    /// <summary>Tool rows: number, length, radius, length wear, radius wear.</summary>
    IReadOnlyList<IReadOnlyList<string>> ToolRows { get; set; }

    /// <summary>Validation errors or the last write's result, under the grids.</summary>
    string TablesMessage { set; }

    /// <summary>Whether the console's commands can be used (a controller is open, no console command under way).</summary>
    bool ConsoleEnabled { set; }

    /// <summary>Whether the jog buttons can be used (a controller is open; a held button stays usable while its jog runs).</summary>
    bool JogEnabled { set; }

    /// <summary>Asks the operator to confirm; true to go on.</summary>
    Task<bool> ConfirmAsync(string title, string text);
}
