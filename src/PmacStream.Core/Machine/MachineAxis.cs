using System.Globalization;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;

namespace PmacStream.Machine;

/// <summary>An axis of the machine and the motor that drives it.</summary>
/// <param name="Name">The axis letter.</param>
/// <param name="Motor">The motor number (<c>#n</c>).</param>
/// <param name="CountsPerMm">Motor counts per millimetre (per degree on a rotary axis): the scale of its axis definition (<c>#1->1000X</c> is 1000; the simulator's power-on definition is 1).</param>
/// <param name="Rotary">A rotary axis: its positions are degrees (<paramref name="CountsPerMm"/> is then counts per degree).</param>
public sealed record MachineAxis(string Name, int Motor, double CountsPerMm = 1, bool Rotary = false)
{
    /// <summary>X, Y, Z on motors 1, 2, 3 at scale 1: the simulator's power-on definition.</summary>
    public static IReadOnlyList<MachineAxis> Default { get; } = [new("X", 1), new("Y", 2), new("Z", 3)];

    /// <summary>The axes a machine profile lists (<c>"axes"</c>), or <see cref="Default"/> when it lists none.</summary>
    public static IReadOnlyList<MachineAxis> Of(MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return profile.Axes.Count == 0 ? Default : profile.Axes.Select(a => new MachineAxis(a.Name, a.Motor, a.CountsPerUnit, a.Rotary)).ToList();
    }

    /// <summary>The unit of its positions: <c>mm</c>, or <c>deg</c> for a rotary axis.</summary>
    public string Unit => Rotary ? "deg" : "mm";

    /// <summary>The library's axis index (X 0, Y 1, Z 2), or -1 for an axis without work offsets.</summary>
    public int TableAxis => Name switch { "X" => 0, "Y" => 1, "Z" => 2, _ => -1 };
}

/// <summary>
/// The rules a job service applies before and during a job on a real machine (the command line's stream and resume):
/// refuse to start on an unhomed machine or with an alarm, and hold the job when an alarm stops the program.
/// </summary>
/// <param name="Axes">The machine's axes.</param>
/// <param name="HomeCheck">Refuse a job while an axis is not homed (off: absolute encoders, or <c>--no-home-check</c>).</param>
public sealed record MachineRules(IReadOnlyList<MachineAxis> Axes, bool HomeCheck = true);

/// <summary>What the console is set up with.</summary>
public sealed record MachineConsoleOptions
{
    /// <summary>The machine's axes.</summary>
    public IReadOnlyList<MachineAxis> Axes { get; init; } = MachineAxis.Default;

    /// <summary>The coordinate system the programs run in.</summary>
    public int CoordinateSystem { get; init; } = 1;

    /// <summary>Where the library keeps its tables and modal state.</summary>
    public LibraryMap Map { get; init; } = new();

    /// <summary>Language of the alarm texts: <c>en</c> or <c>zh-CN</c>.</summary>
    public string Language { get; init; } = "en";

    /// <summary>The alarm history; null: none kept.</summary>
    public IAlarmHistory? History { get; init; }

    /// <summary>The host's copy of the tables; null: none kept.</summary>
    public string? TablesPath { get; init; }

    /// <summary>The file keeping MDI's modal state between calls (per controller); null: not carried.</summary>
    public string? StatePath { get; init; }

    /// <summary>The machine profile MDI blocks are checked and converted under.</summary>
    public MachineProfile Profile { get; init; } = MachineProfile.Default;

    /// <summary>Run settings of MDI's little jobs.</summary>
    public RunSettings Settings { get; init; } = RunSettings.Default;

    /// <summary>
    /// The folder of the console's own files (alarm history, MDI modal state): beside an SQLite store; with a shop
    /// database, this station's default folder (they belong to the station, not the shop).
    /// </summary>
    public static string StateFolder(JobService jobs) =>
        Path.GetDirectoryName(jobs.Store.Engine == Preparation.Store.StoreEngine.Sqlite ? Path.GetFullPath(jobs.Store.Target) : Preparation.Store.StoreLocation.DefaultSqlitePath)!;

    /// <summary>How long a motion may take before the console gives up waiting for it to end in position.</summary>
    public TimeSpan MotionTimeout { get; init; } = TimeSpan.FromMinutes(10);

    /// <summary>How often the console polls the controller while it waits for motion.</summary>
    public TimeSpan Poll { get; init; } = TimeSpan.FromMilliseconds(20);

    /// <summary>
    /// Jog speed when a jog gives none, mm/min (set as the motor's Ixx22 for the move, then restored); null: the motor's
    /// own Ixx22. 1000 by default: the simulator's power-on Ixx22 (32 counts/ms at 1 count per mm) is 1.9 m/s.
    /// </summary>
    public double? DefaultJogFeed { get; init; } = 1000;

    /// <summary>
    /// The suffix of the M-variable that points at each motor's target (end) position register: 63 reads M163 for motor 1
    /// (Delta Tau's suggested definitions, <c>M163-&gt;D:$0000C7</c>); its commanded position is read from Mxx61. An axis
    /// whose variables are not defined on the controller (<c>*</c>) shows distance to go of the console's own moves
    /// only; null: never read them.
    /// </summary>
    public int? TargetVariable { get; init; } = 63;

    /// <summary>
    /// The coordinate-system Q-variable the programmed spindle speed is in: <c>Q127</c>, where a motion program's
    /// <c>S{data}</c> puts it (Turbo SRM p. 469); the host sends each block's S as such a line.
    /// </summary>
    public string SpindleSpeedVariable { get; init; } = "Q127";

    /// <summary>The library's spindle-on output (M03/M04 set it, M05 clears it): <see cref="Preparation.Prog1000Options.SpindleOn"/>.</summary>
    public string SpindleOnVariable { get; init; } = new Preparation.Prog1000Options().SpindleOn;

    /// <summary>The library's spindle-reverse output (M04 sets it, M03 clears it).</summary>
    public string SpindleReverseVariable { get; init; } = new Preparation.Prog1000Options().SpindleReverse;

    /// <summary>
    /// A motor whose velocity is the spindle's (a spindle with an encoder, or its drive's speed read back as a motor);
    /// null (the default): the library drives the spindle open loop, so the actual speed shown is the programmed one
    /// while the spindle-on output is set, 0 when it is off (*assumed*: no feedback to read).
    /// </summary>
    public int? SpindleMotor { get; init; }

    /// <summary>Counts per spindle revolution of <see cref="SpindleMotor"/>.</summary>
    public double SpindleCountsPerRev { get; init; } = 1;

    /// <summary>Tools the <c>tools</c> list reads from the controller (1..this).</summary>
    public int ToolCount { get; init; } = 24;

    /// <summary>Refuse MDI (and jobs) while an axis is not homed; off for absolute encoders.</summary>
    public bool HomeCheck { get; init; } = true;
}

/// <summary>The tool table in the machine profile the check and the host's cutter compensation read.</summary>
public static class ToolTableProfile
{
    /// <summary>
    /// <paramref name="profile"/> with the tool table's lengths and radii (plus wear) over its own, so a program's
    /// <c>G41 D1</c> reads tool 1's radius as set at the machine. The profile itself when the table has no tools.
    /// </summary>
    public static MachineProfile Apply(MachineProfile profile, MachineTables tables)
    {
        ArgumentNullException.ThrowIfNull(profile);
        ArgumentNullException.ThrowIfNull(tables);
        if (tables.Tools.Count == 0)
        {
            return profile;
        }

        var json = JsonNode.Parse(profile.ToJson())!.AsObject();
        var lengths = (json["toolLengths"] as JsonObject)?.DeepClone().AsObject() ?? new JsonObject();
        var radii = (json["toolRadii"] as JsonObject)?.DeepClone().AsObject() ?? new JsonObject();
        foreach (var t in tables.Tools)
        {
            var key = t.Number.ToString(CultureInfo.InvariantCulture);
            lengths[key] = t.EffectiveLength;
            radii[key] = t.EffectiveRadius;
        }

        json["toolLengths"] = lengths;
        json["toolRadii"] = radii;
        return MachineProfile.Parse(json.ToJsonString(), profile.Source);
    }
}
