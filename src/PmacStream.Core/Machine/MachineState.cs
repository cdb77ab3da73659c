namespace PmacStream.Machine;

/// <summary>What the machine is doing, as the operator's console shows it.</summary>
public enum MachineMode
{
    /// <summary>No program runs and no job waits; no alarm.</summary>
    Idle,

    /// <summary>A program runs on the coordinate system.</summary>
    Running,

    /// <summary>A job waits to be resumed: feed hold, or stopped by an alarm that is cleared now.</summary>
    Held,

    /// <summary>A job stands at a program stop (M00, M01) or was aborted.</summary>
    Stopped,

    /// <summary>An alarm is active (a limit, a fault kill): motion is refused until it is cleared.</summary>
    Alarm,
}

/// <summary>How serious an alarm is.</summary>
public enum AlarmSeverity
{
    /// <summary>Motion goes on (a warning following error).</summary>
    Warning,

    /// <summary>Motion stopped; the operator must clear it (or move off a limit).</summary>
    Alarm,
}

/// <summary>One axis on the DRO.</summary>
/// <param name="Name">The axis letter (X, Y, Z).</param>
/// <param name="Motor">The motor that drives it.</param>
/// <param name="Machine">Actual position in machine coordinates, mm.</param>
/// <param name="Work">Actual position in work coordinates, mm: machine minus the active work offset, G52/G92 shift and (Z) tool length.</param>
/// <param name="ToGo">Distance to go of the move the motor makes (a job's block, a jog), mm: its target (end) position register less its commanded position; 0 in position.</param>
/// <param name="Homed">The motor's Home Complete bit.</param>
public sealed record AxisState(string Name, int Motor, double Machine, double Work, double ToGo, bool Homed);

/// <summary>An alarm decoded from a motor's status word.</summary>
/// <param name="Code">Stable code: <c>limit+</c>, <c>limit-</c>, <c>software-limit</c>, <c>fatal-following-error</c>, <c>amp-fault</c>, <c>warning-following-error</c>, <c>motor-killed</c>.</param>
/// <param name="Motor">The motor number.</param>
/// <param name="Axis">The axis letter of the motor.</param>
/// <param name="Text">Clear text in the console's language.</param>
/// <param name="Severity">Whether motion is stopped by it.</param>
public sealed record MachineAlarm(string Code, int Motor, string Axis, string Text, AlarmSeverity Severity);

/// <summary>The spindle as the controller reports it.</summary>
/// <param name="Programmed">The programmed speed (S), rpm: the coordinate system's Q127.</param>
/// <param name="Actual">The actual speed, rpm: a spindle motor's velocity, else the programmed speed while the spindle-on output is set and 0 when it is off.</param>
/// <param name="On">The library's spindle-on output is set (M03/M04).</param>
/// <param name="Reverse">The spindle-reverse output is set (M04).</param>
public sealed record SpindleReadout(double Programmed, double Actual, bool On, bool Reverse);

/// <summary>
/// One sample of the machine, for a presenter to poll (<see cref="MachineConsole.ReadStateAsync"/>) and the command
/// line's <c>status</c> to print.
/// </summary>
/// <param name="Mode">What the machine is doing.</param>
/// <param name="Axes">Every axis of the console, in order.</param>
/// <param name="Alarms">Active alarms (warnings included).</param>
/// <param name="WorkOffset">The active work offset (<c>G54</c>, <c>G54.1P3</c>).</param>
/// <param name="FeedOverride">Feed override of the coordinate system, percent.</param>
/// <param name="ProgrammedFeed">The feed the executing block programmed, mm/min (P500 in paper mode), or null.</param>
/// <param name="ActualFeed">Vector speed of the axes now, mm/min.</param>
/// <param name="SpindleSpeed">Programmed spindle speed (S, the coordinate system's Q127), or null when the controller does not say; <see cref="Spindle"/> has the actual speed too.</param>
/// <param name="ExecutingLine">Source line the tracking variable names (M0), 0 before a program.</param>
/// <param name="Job">The newest job on this controller and its state, or null.</param>
public sealed record MachineState(
    MachineMode Mode,
    IReadOnlyList<AxisState> Axes,
    IReadOnlyList<MachineAlarm> Alarms,
    string WorkOffset,
    double FeedOverride,
    double? ProgrammedFeed,
    double ActualFeed,
    double? SpindleSpeed,
    int ExecutingLine,
    string? Job)
{
    /// <summary>The spindle's programmed and actual speed, or null when the controller was not asked.</summary>
    public SpindleReadout? Spindle { get; init; }

    /// <summary>True when every axis is homed.</summary>
    public bool AllHomed => Axes.All(a => a.Homed);

    /// <summary>Alarms that stop motion (not warnings).</summary>
    public IEnumerable<MachineAlarm> Stopping => Alarms.Where(a => a.Severity == AlarmSeverity.Alarm);

    /// <summary>The mode as the command line's JSON writes it (<c>idle</c>, <c>running</c>, <c>held</c>, <c>stopped</c>, <c>alarm</c>).</summary>
    public string ModeName => Mode.ToString().ToLowerInvariant();
}

/// <summary>Whether a console command was done, and why not.</summary>
public enum ConsoleRefusal
{
    /// <summary>Done.</summary>
    None,

    /// <summary>The machine (or the axis) is not homed.</summary>
    NotHomed,

    /// <summary>A program runs (or is held) on the coordinate system.</summary>
    ProgramRuns,

    /// <summary>An alarm is active.</summary>
    AlarmActive,

    /// <summary>A value is out of range or the request is malformed.</summary>
    BadValue,

    /// <summary>The program was refused by the check gate.</summary>
    CheckFailed,

    /// <summary>The controller refused or the motion did not end in position in time.</summary>
    Failed,
}

/// <summary>What a console command did: done, or refused with the reason (in words for the operator).</summary>
/// <param name="Refusal">Why it was refused; <see cref="ConsoleRefusal.None"/> when done.</param>
/// <param name="Message">What was done, or why not.</param>
public sealed record ConsoleResult(ConsoleRefusal Refusal, string Message)
{
    /// <summary>True when done.</summary>
    public bool Done => Refusal == ConsoleRefusal.None;

    /// <summary>A done result.</summary>
    public static ConsoleResult Ok(string message) => new(ConsoleRefusal.None, message);

    /// <summary>A refusal.</summary>
    public static ConsoleResult Refused(ConsoleRefusal why, string message) => new(why, message);
}
