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
}

/// <summary>Length units of a program (G20/G21).</summary>
public enum LengthUnits
{
    /// <summary>G21 millimetres.</summary>
    Millimetres,

    /// <summary>G20 inches.</summary>
    Inches,
}

/// <summary>A point in machine (work-offset-applied) coordinates, program units. Doubles, not <c>Vector3</c>: 4 decimals on metre-sized parts need more than float.</summary>
/// <param name="X">X coordinate.</param>
/// <param name="Y">Y coordinate.</param>
/// <param name="Z">Z coordinate.</param>
public readonly record struct Point3(double X, double Y, double Z)
{
    /// <summary>Euclidean distance to another point.</summary>
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
}

/// <summary>
/// The modal state after a block: the code in force in each group (GA-GI, MA-MC, as code numbers such as
/// 1, 21, 90) and the decoded meaning of the ones motion depends on. Immutable; the interpreter shares one instance
/// between consecutive blocks that change nothing. Non-modal groups (the default profile's GG = G04, GI = G09 and
/// MA = M00/M30) hold the code only on the block that carries it and are null otherwise.
/// </summary>
public sealed record ModalState
{
    /// <summary>Group GA (motion: 0, 1, 2, 3).</summary>
    public double? GA { get; init; }

    /// <summary>Group GB (units: 20, 21).</summary>
    public double? GB { get; init; }

    /// <summary>Group GC (distance mode: 90, 91).</summary>
    public double? GC { get; init; }

    /// <summary>Group GD (work offset: 54..59).</summary>
    public double? GD { get; init; }

    /// <summary>Group GE (plane: 17, 18, 19).</summary>
    public double? GE { get; init; }

    /// <summary>Group GF (tool length compensation: 43, 49).</summary>
    public double? GF { get; init; }

    /// <summary>Group GG (dwell 4, non-modal).</summary>
    public double? GG { get; init; }

    /// <summary>Group GH (cutter compensation: 40, 41, 42).</summary>
    public double? GH { get; init; }

    /// <summary>Group GI (exact stop 9, non-modal).</summary>
    public double? GI { get; init; }

    /// <summary>Group MA (program stop/end: 0, 30; non-modal).</summary>
    public double? MA { get; init; }

    /// <summary>Group MB (spindle: 3, 4, 5).</summary>
    public double? MB { get; init; }

    /// <summary>Group MC (coolant: 8, 9).</summary>
    public double? MC { get; init; }

    /// <summary>Program units (G20/G21).</summary>
    public LengthUnits Units { get; init; } = LengthUnits.Millimetres;

    /// <summary>Arc plane: 17 (XY), 18 (ZX) or 19 (YZ).</summary>
    public int Plane { get; init; } = 17;

    /// <summary>True for G90 absolute, false for G91 incremental.</summary>
    public bool Absolute { get; init; } = true;

    /// <summary>Active work offset code: 54..59.</summary>
    public int WorkOffset { get; init; } = 54;

    /// <summary>Tool number (T), 0 before any T.</summary>
    public int Tool { get; init; }

    /// <summary>Length offset register (H), 0 before any H.</summary>
    public int LengthOffset { get; init; }

    /// <summary>Cutter compensation register (D), 0 before any D.</summary>
    public int CutterComp { get; init; }

    /// <summary>Spindle: 3 (clockwise), 4 (counter-clockwise), 5 (stopped).</summary>
    public int Spindle { get; init; } = 5;

    /// <summary>Programmed spindle speed (S), 0 before any S.</summary>
    public double SpindleSpeed { get; init; }

    /// <summary>Coolant: 8 (on) or 9 (off).</summary>
    public int Coolant { get; init; } = 9;

    /// <summary>Programmed feed (F) in units per minute; null before any F.</summary>
    public double? Feed { get; init; }

    /// <summary>The G group value by index 0..8 (GA..GI).</summary>
    public double? GetG(int group) => group switch
    {
        0 => GA, 1 => GB, 2 => GC, 3 => GD, 4 => GE, 5 => GF, 6 => GG, 7 => GH, 8 => GI,
        _ => throw new ArgumentOutOfRangeException(nameof(group)),
    };

    /// <summary>The M group value by index 0..2 (MA..MC).</summary>
    public double? GetM(int group) => group switch
    {
        0 => MA, 1 => MB, 2 => MC,
        _ => throw new ArgumentOutOfRangeException(nameof(group)),
    };

    /// <summary>
    /// G-code lines that bring a freshly started controller into this state, for "start from any block": units,
    /// plane and work offset, tool and length/cutter compensation, spindle, coolant, then (when
    /// <paramref name="programPosition"/> is given, in program coordinates of the active work offset) a G90 rapid to
    /// X Y and then Z, then the distance mode, motion mode and feed. The caller is responsible for a safe Z before
    /// running it; non-modal codes (G04, G09, M00, M30) are never repeated.
    /// </summary>
    public IReadOnlyList<string> ToPreamble(Point3? programPosition = null)
    {
        var lines = new List<string>(8)
        {
            $"G{(Units == LengthUnits.Inches ? 20 : 21)} G{Plane} G{WorkOffset}",
        };

        if (Tool > 0)
        {
            lines.Add($"T{Tool}");
        }

        if (GF is { } gf)
        {
            lines.Add(gf is 43 or 44 ? $"G{Num(gf)} H{LengthOffset}" : $"G{Num(gf)}");
        }

        if (GH is { } gh)
        {
            lines.Add(gh is 41 or 42 ? $"G{Num(gh)} D{CutterComp}" : $"G{Num(gh)}");
        }

        lines.Add(SpindleSpeed > 0 ? $"S{Num(SpindleSpeed)} M0{Spindle}" : $"M0{Spindle}");
        lines.Add(Coolant == 9 ? "M09" : $"M0{Coolant}");
        if (programPosition is { } p)
        {
            lines.Add($"G90 G00 X{Num(p.X)} Y{Num(p.Y)}");
            lines.Add($"G00 Z{Num(p.Z)}");
        }

        var motion = GA is { } ga ? $"G{(ga < 10 ? "0" : string.Empty)}{Num(ga)}" : "G00";
        lines.Add($"G{(Absolute ? 90 : 91)} {motion}" + (Feed is { } f ? $" F{Num(f)}" : string.Empty));
        return lines;
    }

    /// <summary>A number as G-code writes it: invariant, no exponent, no trailing zeros.</summary>
    internal static string Num(double v) => v.ToString("0.############", CultureInfo.InvariantCulture);
}
