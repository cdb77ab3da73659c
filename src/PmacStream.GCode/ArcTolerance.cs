using System.Text.Json;

namespace PmacStream.GCode;

/// <summary>
/// How far a G02/G03 block's end may be off its circle and still run, in the program's own units (a profile's
/// <c>arcTolerance</c>). Posts round arcs to the program's last decimal, so a real program's start and end radii
/// differ a little; a controller that refuses every such arc refuses the shop's programs. The default is LinuxCNC's
/// rule (rs274ngc <c>arc_data_ijk</c>, <c>arc_data_r</c>; constants in <c>interp_internal.hh</c>):
/// <list type="bullet">
/// <item>centre format (I/J/K): refused when the radii differ by more than <see cref="Inch"/>/<see cref="Millimetre"/>
/// (2 x 0.001 x sqrt 2 in, 2 x 0.01 x sqrt 2 mm: the most rounding start, end and centre to 0.001 in or 0.01 mm
/// can make) and also by more than <see cref="Relative"/> (0.1 %) of the larger radius, or by more than
/// <see cref="LimitInch"/>/<see cref="LimitMillimetre"/> (100 times the first) whatever the radius;</item>
/// <item>radius format (R): refused when R is shorter than half the chord by more than
/// <see cref="RadiusInch"/>/<see cref="RadiusMillimetre"/> (0.00005 in, 0.00127 mm); such an arc runs as the half
/// circle on the chord.</item>
/// </list>
/// Immutable; one instance is shared by every interpreter of its profile.
/// </summary>
public sealed class ArcTolerance
{
    /// <summary>2 x sqrt 2: how much rounding to one unit of the last decimal can change the difference of two radii.</summary>
    private const double RoundingFactor = 2 * 1.4142135623730951;

    /// <summary>LinuxCNC's rule (rs274ngc's defaults).</summary>
    public static readonly ArcTolerance LinuxCnc = new(RoundingFactor * 0.001, RoundingFactor * 0.01, 0.001, 100 * RoundingFactor * 0.001, 100 * RoundingFactor * 0.01, 0.00005, 0.00005 * 25.4);

    /// <summary>Creates a rule; every value is 0 or more (see the properties).</summary>
    public ArcTolerance(double inch, double millimetre, double relative, double limitInch, double limitMillimetre, double radiusInch, double radiusMillimetre)
    {
        Inch = inch;
        Millimetre = millimetre;
        Relative = relative;
        LimitInch = limitInch;
        LimitMillimetre = limitMillimetre;
        RadiusInch = radiusInch;
        RadiusMillimetre = radiusMillimetre;
    }

    /// <summary>Inch programs (G20): a centre-format arc's radii may differ by this much (inches) whatever the radius.</summary>
    public double Inch { get; }

    /// <summary>Metric programs (G21): a centre-format arc's radii may differ by this much (millimetres) whatever the radius.</summary>
    public double Millimetre { get; }

    /// <summary>Beyond <see cref="Inch"/>/<see cref="Millimetre"/>, the radii may still differ by this fraction of the larger one (0.001 = 0.1 %).</summary>
    public double Relative { get; }

    /// <summary>Inch programs: the radii never differ by more than this, however large the circle.</summary>
    public double LimitInch { get; }

    /// <summary>Metric programs: the radii never differ by more than this, however large the circle.</summary>
    public double LimitMillimetre { get; }

    /// <summary>Inch programs: how much shorter than half the chord an R may be (the arc is then the half circle on the chord).</summary>
    public double RadiusInch { get; }

    /// <summary>Metric programs: how much shorter than half the chord an R may be.</summary>
    public double RadiusMillimetre { get; }

    /// <summary>
    /// The format before units: one number, millimetres compared whatever the program's units, with LinuxCNC's 0.1 %
    /// and no upper limit; R may be short by the same number.
    /// </summary>
    public static ArcTolerance FromMillimetres(double mm) => new(mm / 25.4, mm, 0.001, double.PositiveInfinity, double.PositiveInfinity, mm / 25.4, mm);

    /// <summary>
    /// True when a centre-format arc whose radii are <paramref name="r0"/> and <paramref name="r1"/> (program units)
    /// cannot run: off by more than the absolute tolerance and by more than the relative one, or by more than the limit.
    /// </summary>
    public bool Refuses(double r0, double r1, bool inch)
    {
        var off = Math.Abs(r0 - r1);
        var (abs, limit) = inch ? (Inch, LimitInch) : (Millimetre, LimitMillimetre);
        return off > limit || (off > abs && off > Relative * Math.Max(r0, r1));
    }

    /// <summary>How much shorter than half the chord an R may be, in the program's units.</summary>
    public double RadiusSlack(bool inch) => inch ? RadiusInch : RadiusMillimetre;

    /// <summary>
    /// The most by which rounding start, end and centre to <paramref name="decimals"/> decimals can make two radii
    /// differ (2 x sqrt 2 units of the last decimal): an arc off by more was not merely rounded by its post.
    /// </summary>
    public static double RoundingBound(int decimals) => RoundingFactor * Math.Pow(10, -Math.Clamp(decimals, 0, 12));

    /// <summary>The rule as the profile file says it, for the documentation: "0.0028 in or 0.0283 mm and 0.1 % ...".</summary>
    public string Describe() =>
        $"a centre-format arc is refused when its radii differ by more than {ModalState.Num(Math.Round(Inch, 6))} in (G20) or {ModalState.Num(Math.Round(Millimetre, 5))} mm (G21) " +
        $"and by more than {ModalState.Num(Relative * 100)} % of the radius" +
        (double.IsPositiveInfinity(LimitMillimetre) ? string.Empty : $", or by more than {ModalState.Num(Math.Round(LimitInch, 5))} in or {ModalState.Num(Math.Round(LimitMillimetre, 4))} mm") +
        $"; an R shorter than half the chord by more than {ModalState.Num(Math.Round(RadiusInch, 6))} in or {ModalState.Num(Math.Round(RadiusMillimetre, 5))} mm";

    /// <summary>Reads the profile's <c>arcTolerance</c>: a number (the older millimetre format) or an object whose missing members are LinuxCNC's.</summary>
    internal static ArcTolerance Read(JsonElement v, string source)
    {
        if (v.ValueKind == JsonValueKind.Number)
        {
            return FromMillimetres(Positive(v.GetDouble(), "arcTolerance", source));
        }

        if (v.ValueKind != JsonValueKind.Object)
        {
            throw MachineProfile.Bad(source, "arcTolerance: expected a number (millimetres) or an object { \"inch\", \"mm\", \"relative\", \"limitInch\", \"limitMm\", \"radiusInch\", \"radiusMm\" }");
        }

        var d = LinuxCnc;
        double inch = d.Inch, mm = d.Millimetre, rel = d.Relative, limitInch = d.LimitInch, limitMm = d.LimitMillimetre, radiusInch = d.RadiusInch, radiusMm = d.RadiusMillimetre;
        foreach (var p in v.EnumerateObject())
        {
            var x = p.Value.ValueKind == JsonValueKind.Null ? double.PositiveInfinity : p.Value.GetDouble();
            switch (p.Name.ToLowerInvariant())
            {
                case "inch": inch = Positive(x, "arcTolerance.inch", source); break;
                case "mm": mm = Positive(x, "arcTolerance.mm", source); break;
                case "relative": rel = Positive(x, "arcTolerance.relative", source); break;
                case "limitinch": limitInch = Positive(x, "arcTolerance.limitInch", source); break;
                case "limitmm": limitMm = Positive(x, "arcTolerance.limitMm", source); break;
                case "radiusinch": radiusInch = Positive(x, "arcTolerance.radiusInch", source); break;
                case "radiusmm": radiusMm = Positive(x, "arcTolerance.radiusMm", source); break;
                default: throw MachineProfile.Bad(source, $"arcTolerance: unknown setting '{p.Name}'");
            }
        }

        return new ArcTolerance(inch, mm, rel, limitInch, limitMm, radiusInch, radiusMm);
    }

    /// <summary>Writes the rule as the object <see cref="Read"/> takes (no limit is written as null).</summary>
    internal void Write(Utf8JsonWriter w)
    {
        w.WriteStartObject("arcTolerance");
        Number(w, "inch", Inch);
        Number(w, "mm", Millimetre);
        Number(w, "relative", Relative);
        Number(w, "limitInch", LimitInch);
        Number(w, "limitMm", LimitMillimetre);
        Number(w, "radiusInch", RadiusInch);
        Number(w, "radiusMm", RadiusMillimetre);
        w.WriteEndObject();
    }

    private static void Number(Utf8JsonWriter w, string name, double value)
    {
        if (double.IsPositiveInfinity(value))
        {
            w.WriteNull(name);
        }
        else
        {
            w.WriteNumber(name, value);
        }
    }

    private static double Positive(double x, string name, string source) =>
        x >= 0 && !double.IsNaN(x) ? x : throw MachineProfile.Bad(source, $"{name} must be 0 or more");
}
