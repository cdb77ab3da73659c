using System.Globalization;

namespace PmacStream.GCode;

/// <summary>What a decoded block does to the machine.</summary>
public enum MotionKind
{
    /// <summary>No motion (mode changes, spindle, coolant, tool, feed).</summary>
    None,

    /// <summary>G00 rapid positioning.</summary>
    Rapid,

    /// <summary>G01 linear feed move.</summary>
    Linear,

    /// <summary>G02 clockwise arc (helix when the third axis moves).</summary>
    ArcCw,

    /// <summary>G03 counter-clockwise arc.</summary>
    ArcCcw,

    /// <summary>G04 dwell.</summary>
    Dwell,

    /// <summary>The holes of a drilling, tapping or boring cycle (G81 ...): from the start over each hole to the retract level.</summary>
    Cycle,
}

/// <summary>Length units of a program (G20/G21).</summary>
public enum LengthUnits
{
    /// <summary>G21 millimetres.</summary>
    Millimetres,

    /// <summary>G20 inches.</summary>
    Inches,
}

/// <summary>
/// A point in machine (work-offset-applied) coordinates: the one point type of the interpreter, preparation and the
/// preview. Program units where the interpreter keeps it, millimetres in the preview's paths (<see cref="InMillimetres"/>).
/// Doubles, not <c>Vector3</c>: 4 decimals on metre-sized parts need more than float.
/// </summary>
/// <param name="X">X coordinate.</param>
/// <param name="Y">Y coordinate.</param>
/// <param name="Z">Z coordinate.</param>
public readonly record struct Point3(double X, double Y, double Z)
{
    /// <summary>Euclidean distance to another point.</summary>
    // Inlined: called with a point just computed, whose copy to the stack for the call stalled on store forwarding.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    public double DistanceTo(Point3 other)
    {
        var dx = other.X - X;
        var dy = other.Y - Y;
        var dz = other.Z - Z;
        return Math.Sqrt((dx * dx) + (dy * dy) + (dz * dz));
    }

    /// <summary>Component-wise difference.</summary>
    public static Point3 operator -(Point3 a, Point3 b) => new(a.X - b.X, a.Y - b.Y, a.Z - b.Z);

    /// <summary>Component-wise sum.</summary>
    public static Point3 operator +(Point3 a, Point3 b) => new(a.X + b.X, a.Y + b.Y, a.Z + b.Z);

    /// <summary>This point, in program <paramref name="units"/>, in millimetres (an inch program's times 25.4).</summary>
    public Point3 InMillimetres(LengthUnits units) => units == LengthUnits.Inches ? new(X * 25.4, Y * 25.4, Z * 25.4) : this;
}

/// <summary>
/// The modal state after a block: the code in force in each modal group of the profile (<see cref="G"/>, <see cref="M"/>,
/// as code numbers such as 1, 21, 90, in the profile's group order; the first nine G and three M groups are the store's
/// GA-GI and MA-MC columns) and the registers and values motion depends on. What the codes mean (units, plane, distance mode,
/// spindle ...) is read from the codes themselves, so it does not depend on how a profile orders its groups.
/// Immutable; the interpreter shares one instance between consecutive blocks that change nothing. Non-modal groups
/// (G04, G28, M00 ...) hold their code only on the block that carries it and are null otherwise.
/// </summary>
public sealed record ModalState
{
    /// <summary>The G code in force in each G group of the profile.</summary>
    public CodeValues G { get; init; } = CodeValues.Empty;

    /// <summary>The M code in force in each M group of the profile.</summary>
    public CodeValues M { get; init; } = CodeValues.Empty;

    /// <summary>The first G group (GA; the motion group in the built-in profiles).</summary>
    public double? GA => G.At(0);

    /// <summary>The second G group (GB; units in the built-in profiles).</summary>
    public double? GB => G.At(1);

    /// <summary>The third G group (GC; distance mode in the built-in profiles).</summary>
    public double? GC => G.At(2);

    /// <summary>The fourth G group (GD; work offset in the built-in profiles).</summary>
    public double? GD => G.At(3);

    /// <summary>The fifth G group (GE; plane in the built-in profiles).</summary>
    public double? GE => G.At(4);

    /// <summary>The sixth G group (GF; tool length compensation in the built-in profiles).</summary>
    public double? GF => G.At(5);

    /// <summary>The seventh G group (GG; dwell and the other non-modal codes).</summary>
    public double? GG => G.At(6);

    /// <summary>The eighth G group (GH; cutter compensation in the built-in profiles).</summary>
    public double? GH => G.At(7);

    /// <summary>The ninth G group (GI; exact stop in paper-24g7m, canned cycles in fanuc-mill).</summary>
    public double? GI => G.At(8);

    /// <summary>The first M group (MA; program stop and end).</summary>
    public double? MA => M.At(0);

    /// <summary>The second M group (MB; spindle).</summary>
    public double? MB => M.At(1);

    /// <summary>The third M group (MC; coolant).</summary>
    public double? MC => M.At(2);

    /// <summary>Program units (G20/G21).</summary>
    public LengthUnits Units => G.Holds(20) ? LengthUnits.Inches : LengthUnits.Millimetres;

    /// <summary>Arc plane: 17 (XY), 18 (ZX) or 19 (YZ).</summary>
    public int Plane => G.FirstWhere(static v => v is 17 or 18 or 19) is { } p ? (int)p : 17;

    /// <summary>True for G90 absolute, false for G91 incremental.</summary>
    public bool Absolute => !G.Holds(91);

    /// <summary>Active work offset code: 54..59 (54 also for the extended offsets G54.1 and G154).</summary>
    public int WorkOffset => G.FirstWhere(static v => v is >= 54 and < 60) is { } w ? (int)w : 54;

    /// <summary>The motion mode in force: 0..3 for G00..G03, null when none (G80 in a LinuxCNC-style motion group).</summary>
    public double? Motion => G.FirstWhere(static v => v is 0 or 1 or 2 or 3);

    /// <summary>The canned cycle in force (G73, G81 ...), null when none.</summary>
    public double? Cycle => G.FirstWhere(static v => CodeRoles.OfG(MachineProfile.Key(v)) == GRole.Cycle);

    /// <summary>The tool length compensation code in force (G43, G44, G43.4 ..., G49), null when the profile has none.</summary>
    public double? LengthCompensation => G.FirstWhere(static v => Math.Floor(v) is 43 or 44 or 49);

    /// <summary>The cutter radius compensation code in force (G40, G41, G42, G41.2 ...), null when the profile has none.</summary>
    public double? RadiusCompensation => G.FirstWhere(static v => Math.Floor(v) is 40 or 41 or 42);

    /// <summary>Tool number (T), 0 before any T.</summary>
    public int Tool { get; init; }

    /// <summary>Length offset register (H), 0 before any H.</summary>
    public int LengthOffset { get; init; }

    /// <summary>Cutter compensation register (D), 0 before any D.</summary>
    public int CutterComp { get; init; }

    /// <summary>Spindle: 3 (clockwise), 4 (counter-clockwise), 5 (stopped, also while M19 orients it).</summary>
    public int Spindle => M.FirstWhere(static v => v is 3 or 4) is { } s ? (int)s : 5;

    /// <summary>Programmed spindle speed (S), 0 before any S.</summary>
    public double SpindleSpeed { get; init; }

    /// <summary>Coolant: 7 (mist), 8 (flood) or 9 (off).</summary>
    public int Coolant => M.FirstWhere(static v => v is 7 or 8) is { } c ? (int)c : 9;

    /// <summary>Programmed feed (F) in units per minute; null before any F.</summary>
    public double? Feed { get; init; }

    /// <summary>The G group value by index (GA is 0); null beyond the profile's groups.</summary>
    public double? GetG(int group) => group >= 0 ? G.At(group) : throw new ArgumentOutOfRangeException(nameof(group));

    /// <summary>The M group value by index (MA is 0); null beyond the profile's groups.</summary>
    public double? GetM(int group) => group >= 0 ? M.At(group) : throw new ArgumentOutOfRangeException(nameof(group));

    /// <summary>
    /// G-code lines that bring a freshly started controller into this state, for "start from any block": units,
    /// plane and work offset, tool and length/cutter compensation, spindle, coolant, then (when
    /// <paramref name="programPosition"/> is given, in program coordinates of the active work offset) a G90 rapid to
    /// X Y and then Z, then the distance mode, motion mode and feed. The caller is responsible for a safe Z before
    /// running it; non-modal codes (G04, G09, M00, M30) are never repeated.
    /// </summary>
    public IReadOnlyList<string> ToPreamble(Point3? programPosition = null) => ToPreamble(programPosition, forController: false);

    /// <summary>
    /// The preamble; <paramref name="forController"/>: as the host sends it to a controller running the generated
    /// library, in millimetres (no units code: the host converts inch programs, and positions are millimetres), feeds
    /// per minute in millimetres, no T word (the host hands the tool to M06).
    /// </summary>
    public IReadOnlyList<string> ToPreamble(Point3? programPosition, bool forController)
    {
        var lines = new List<string>(8)
        {
            forController ? $"G{Plane} G{WorkOffset}" : $"G{(Units == LengthUnits.Inches ? 20 : 21)} G{Plane} G{WorkOffset}",
        };

        if (Tool > 0 && !forController)
        {
            lines.Add($"T{Tool}");
        }

        if (LengthCompensation is { } gf)
        {
            lines.Add(gf is 43 or 44 ? $"G{Num(gf)} H{LengthOffset}" : $"G{Num(gf)}");
        }

        if (RadiusCompensation is { } gh)
        {
            // The controller never runs G41/G42: the host sends compensated positions, so it gets G40 (no PMAC CC).
            lines.Add(forController && gh is 41 or 42 ? "G40" : gh is 41 or 42 ? $"G{Num(gh)} D{CutterComp}" : $"G{Num(gh)}");
        }

        lines.Add(SpindleSpeed > 0 ? $"S{Num(SpindleSpeed)} M0{Spindle}" : $"M0{Spindle}");
        lines.Add($"M0{Coolant}");
        if (programPosition is { } p)
        {
            lines.Add($"G90 G00 X{Num(p.X)} Y{Num(p.Y)}");
            lines.Add($"G00 Z{Num(p.Z)}");
        }

        var motion = Motion is { } ga ? $"G{(ga < 10 ? "0" : string.Empty)}{Num(ga)}" : "G00";
        var scale = forController && Units == LengthUnits.Inches ? 25.4 : 1.0;
        lines.Add($"G{(Absolute ? 90 : 91)} {motion}" + (Feed is { } f ? $" F{Num(f * scale)}" : string.Empty));
        return lines;
    }

    /// <summary>A number as G-code writes it: invariant, no exponent, no trailing zeros.</summary>
    internal static string Num(double v) => v.ToString("0.############", CultureInfo.InvariantCulture);
}
