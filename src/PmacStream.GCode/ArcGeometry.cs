namespace PmacStream.GCode;

/// <summary>
/// The one arc geometry: the circle of a G02/G03 block (its centre from R or from I/J/K, incremental from the start or
/// absolute with G90.1, the check that the end lies on it, its length with the helical part), and the arc's sweep and
/// points for whoever draws or samples it (the preview). Planes are numbered as their G code; each is a right-handed
/// pair (a, b) with the third axis as its normal: G17 (X, Y) about +Z, G18 (Z, X) about +Y, G19 (Y, Z) about +X, and
/// G03 turns positively about the normal.
/// </summary>
public static class ArcGeometry
{
    /// <summary>
    /// Solves an arc in <paramref name="plane"/> (17, 18 or 19). With <paramref name="absoluteCentre"/> the centre words
    /// are coordinates of the work system, shifted by <paramref name="offset"/> into machine coordinates. Reports
    /// E113 (no centre) and E115 (end not on the circle) into <paramref name="diags"/>; the centre is null when the
    /// circle cannot be placed (the length is then the chord). Positions are millimetres; <paramref name="scale"/> (25.4
    /// in G20) turns them back into the program's units, in which <paramref name="tolerance"/> is compared.
    /// <paramref name="radii"/> are a centre-format arc's start and end radii (program units) when it runs, for the
    /// rounding warning; (0, 0) otherwise.
    /// </summary>
    public static (Point3? Center, double Length) Solve(bool cw, int plane, Point3 start, Point3 end, double? i, double? j, double? k, double? r,
        bool absoluteCentre, Point3 offset, ArcTolerance tolerance, double scale, List<Diagnostic>? diags, int line, int column, Span<int> col,
        out (double Start, double End) radii)
    {
        radii = default;
        // Map the plane to (first, second, linear) axes; G18 is ZX so that G02/G03 keep the right-hand rule.
        (double s1, double s2, double sl, double e1, double e2, double el, double? o1, double? o2, double b1, double b2, string names) = plane switch
        {
            18 => (start.Z, start.X, start.Y, end.Z, end.X, end.Y, k, i, offset.Z, offset.X, "I/K"),
            19 => (start.Y, start.Z, start.X, end.Y, end.Z, end.X, j, k, offset.Y, offset.Z, "J/K"),
            _ => (start.X, start.Y, start.Z, end.X, end.Y, end.Z, i, j, offset.X, offset.Y, "I/J"),
        };

        double c1, c2;
        if (r is { } radius)
        {
            if (!CentreFromRadius(cw, radius, (s1, s2), (e1, e2), tolerance, scale, diags, line, col['R' - 'A'], out c1, out c2))
            {
                return (null, start.DistanceTo(end));
            }
        }
        else if (o1.HasValue || o2.HasValue)
        {
            // Incremental centres default to the start's coordinate, absolute ones (G90.1) to the work origin's.
            c1 = absoluteCentre ? b1 + (o1 ?? s1 - b1) : s1 + (o1 ?? 0);
            c2 = absoluteCentre ? b2 + (o2 ?? s2 - b2) : s2 + (o2 ?? 0);
            radii = CheckRadii(plane, (s1, s2), (e1, e2), (c1, c2), tolerance, scale, diags, line, col);
        }
        else
        {
            Add(diags, DiagnosticCodes.ArcWithoutCenter, line, column, cw ? "02" : "03", names, plane);
            return (null, start.DistanceTo(end));
        }

        var a0 = Math.Atan2(s2 - c2, s1 - c1);
        var a1 = Math.Atan2(e2 - c2, e1 - c1);
        var sweep = cw ? a0 - a1 : a1 - a0;
        while (sweep <= 1e-12)
        {
            sweep += 2 * Math.PI;
        }

        var rad = Math.Sqrt(((s1 - c1) * (s1 - c1)) + ((s2 - c2) * (s2 - c2)));
        var planar = rad * sweep;
        var helix = el - sl;
        var len = Math.Sqrt((planar * planar) + (helix * helix));
        var centre = plane switch
        {
            18 => new Point3(c2, start.Y, c1),
            19 => new Point3(start.X, c1, c2),
            _ => new Point3(c1, c2, start.Z),
        };
        return (centre, len);
    }

    /// <summary>
    /// An R arc's centre (plane coordinates) from its start and end; false, with E115 reported at
    /// <paramref name="rColumn"/>, when R is short of half the chord by more than a rounding's worth.
    /// </summary>
    private static bool CentreFromRadius(bool cw, double radius, (double A, double B) s, (double A, double B) e, ArcTolerance tolerance, double scale,
        List<Diagnostic>? diags, int line, int rColumn, out double c1, out double c2)
    {
        var inch = scale != 1.0;
        var dx = e.A - s.A;
        var dy = e.B - s.B;
        var chord = Math.Sqrt((dx * dx) + (dy * dy));
        var half = chord / 2;
        var rr = Math.Abs(radius);
        // rs274ngc's arc_data_r: R may fall short of half the chord by a rounding's worth; the arc is then the
        // half circle on the chord (the centre at its middle), which the host sends as its centre.
        var slack = tolerance.RadiusSlack(inch);
        if (chord < 1e-12 || ((half - rr) / scale) - slack > 1e-12 * Math.Max(1, half))
        {
            if (diags != null)
            {
                var units = inch ? "in" : "mm";
                diags.Add(new Diagnostic(Severity.Error, DiagnosticCodes.ArcRadiusMismatch, line, rColumn, DiagnosticText.Format(DiagnosticText.ArcRadiusKey,
                    Length(rr / scale, units), Length(half / scale, units), Length(slack, units))));
            }

            (c1, c2) = (0, 0);
            return false;
        }

        var hgt = Math.Sqrt(Math.Max(0, (rr * rr) - (half * half)));
        var sign = (cw ? -1 : 1) * (radius < 0 ? -1 : 1);
        c1 = s.A + (dx / 2) + (-dy / chord * hgt * sign);
        c2 = s.B + (dy / 2) + (dx / chord * hgt * sign);
        return true;
    }

    /// <summary>
    /// A centre-format arc's start and end radii (program units) when it runs as the PMAC's spiral, (0, 0) with E115
    /// reported when they differ by more than <paramref name="tolerance"/> (compared in the program's units, as
    /// rs274ngc compares them: its tolerances are per unit system).
    /// </summary>
    private static (double Start, double End) CheckRadii(int plane, (double A, double B) s, (double A, double B) e, (double A, double B) c,
        ArcTolerance tolerance, double scale, List<Diagnostic>? diags, int line, Span<int> col)
    {
        var inch = scale != 1.0;
        var r0 = Math.Sqrt(((s.A - c.A) * (s.A - c.A)) + ((s.B - c.B) * (s.B - c.B)));
        var r1 = Math.Sqrt(((e.A - c.A) * (e.A - c.A)) + ((e.B - c.B) * (e.B - c.B)));
        if (tolerance.Refuses(r0 / scale, r1 / scale, inch))
        {
            var firstOffset = plane switch { 18 => Min(col['K' - 'A'], col['I' - 'A']), 19 => Min(col['J' - 'A'], col['K' - 'A']), _ => Min(col['I' - 'A'], col['J' - 'A']) };
            var units = inch ? "in" : "mm";
            Add(diags, DiagnosticCodes.ArcRadiusMismatch, line, firstOffset, Length(r0 / scale, units), Length(r1 / scale, units),
                Length(inch ? tolerance.Inch : tolerance.Millimetre, units), ModalState.Num(tolerance.Relative * 100));
            return default;
        }

        // The PMAC runs such an arc as a spiral from the start radius to the end radius, ending exactly at the
        // programmed end point (Turbo SRM, CIRCLE1/CIRCLE2), as LinuxCNC does.
        return (r0 / scale, r1 / scale);
    }

    /// <summary>The point's coordinates on the first and second axes of <paramref name="plane"/> (17, 18 or 19).</summary>
    public static (double A, double B) InPlane(Point3 p, int plane) => plane switch
    {
        18 => (p.Z, p.X),
        19 => (p.Y, p.Z),
        _ => (p.X, p.Y),
    };

    /// <summary>The point's coordinate along the normal of <paramref name="plane"/> (the helix axis).</summary>
    public static double Normal(Point3 p, int plane) => plane switch
    {
        18 => p.Y,
        19 => p.X,
        _ => p.Z,
    };

    /// <summary>The point of plane coordinates <paramref name="a"/>, <paramref name="b"/> and normal coordinate <paramref name="normal"/>.</summary>
    public static Point3 FromPlane(double a, double b, double normal, int plane) => plane switch
    {
        18 => new Point3(b, normal, a),
        19 => new Point3(normal, a, b),
        _ => new Point3(a, b, normal),
    };

    /// <summary>
    /// Start angle, signed sweep (negative for G02, <paramref name="ccw"/> false) and start and end radius of an arc
    /// about <paramref name="center"/>. Equal start and end points mean a full turn.
    /// </summary>
    public static (double StartAngle, double Sweep, double StartRadius, double EndRadius) Describe(Point3 start, Point3 end, Point3 center, int plane, bool ccw)
    {
        var (sa, sb) = InPlane(start, plane);
        var (ea, eb) = InPlane(end, plane);
        var (ca, cb) = InPlane(center, plane);
        var a0 = Math.Atan2(sb - cb, sa - ca);
        var a1 = Math.Atan2(eb - cb, ea - ca);
        var rs = Math.Sqrt(((sa - ca) * (sa - ca)) + ((sb - cb) * (sb - cb)));
        var re = Math.Sqrt(((ea - ca) * (ea - ca)) + ((eb - cb) * (eb - cb)));
        var sweep = a1 - a0;
        // Points closer than this on the circle count as the same point: a full circle.
        const double eps = 1e-9;
        if (ccw)
        {
            while (sweep <= eps)
            {
                sweep += 2 * Math.PI;
            }
        }
        else
        {
            while (sweep >= -eps)
            {
                sweep -= 2 * Math.PI;
            }
        }

        return (a0, sweep, rs, re);
    }

    /// <summary>
    /// The point at fraction <paramref name="t"/> (0..1) along an arc described by <see cref="Describe"/>: angle and
    /// radius vary linearly (so a slightly inconsistent end radius becomes a smooth spiral), and so does the normal
    /// axis (a helix).
    /// </summary>
    public static Point3 PointAt(Point3 start, Point3 end, Point3 center, int plane, double startAngle, double sweep, double startRadius, double endRadius, double t)
    {
        var (ca, cb) = InPlane(center, plane);
        var angle = startAngle + (sweep * t);
        var radius = startRadius + ((endRadius - startRadius) * t);
        var n0 = Normal(start, plane);
        var n1 = Normal(end, plane);
        return FromPlane(ca + (radius * Math.Cos(angle)), cb + (radius * Math.Sin(angle)), n0 + ((n1 - n0) * t), plane);
    }
    /// <summary>A length for a message: six decimals at most, and its unit.</summary>
    internal static string Length(double value, string units) => ModalState.Num(Math.Round(value, 6)) + " " + units;

    private static int Min(int a, int b) => a == 0 ? b : b == 0 ? a : Math.Min(a, b);

    private static void Add(List<Diagnostic>? diags, string code, int line, int column, params object[] args) =>
        diags?.Add(new Diagnostic(DiagnosticCodes.SeverityOf(code), code, line, column, DiagnosticText.Format(code, args)));
}
