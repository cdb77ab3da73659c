namespace PmacStream.Preview;

/// <summary>
/// Arc and helix geometry in the three planes. Each plane is a right-handed pair (a, b) with the third axis as its
/// normal: G17 (X, Y) about +Z, G18 (Z, X) about +Y, G19 (Y, Z) about +X. G03 turns positively about the normal.
/// </summary>
public static class ArcGeometry
{
    /// <summary>The point's coordinates on the plane's first and second axes.</summary>
    public static (double A, double B) InPlane(Point3D p, ArcPlane plane) => plane switch
    {
        ArcPlane.XY => (p.X, p.Y),
        ArcPlane.ZX => (p.Z, p.X),
        _ => (p.Y, p.Z),
    };

    /// <summary>The point's coordinate along the plane's normal (the helix axis).</summary>
    public static double Normal(Point3D p, ArcPlane plane) => plane switch
    {
        ArcPlane.XY => p.Z,
        ArcPlane.ZX => p.Y,
        _ => p.X,
    };

    /// <summary>Builds a point from plane coordinates and the normal coordinate.</summary>
    public static Point3D FromPlane(double a, double b, double normal, ArcPlane plane) => plane switch
    {
        ArcPlane.XY => new Point3D(a, b, normal),
        ArcPlane.ZX => new Point3D(b, normal, a),
        _ => new Point3D(normal, a, b),
    };

    /// <summary>
    /// Start angle, signed sweep (negative for G02) and start/end radius of an arc segment. Equal start and end
    /// points mean a full turn.
    /// </summary>
    public static (double StartAngle, double Sweep, double StartRadius, double EndRadius) Describe(in PathSegment s)
    {
        var (sa, sb) = InPlane(s.Start, s.Plane);
        var (ea, eb) = InPlane(s.End, s.Plane);
        var (ca, cb) = InPlane(s.Center, s.Plane);
        var a0 = Math.Atan2(sb - cb, sa - ca);
        var a1 = Math.Atan2(eb - cb, ea - ca);
        var rs = Math.Sqrt(((sa - ca) * (sa - ca)) + ((sb - cb) * (sb - cb)));
        var re = Math.Sqrt(((ea - ca) * (ea - ca)) + ((eb - cb) * (eb - cb)));
        var sweep = a1 - a0;
        // Points closer than this on the circle count as the same point: a full circle.
        const double eps = 1e-9;
        if (s.Motion == PathMotion.ArcCcw)
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
    public static Point3D PointAt(in PathSegment s, double startAngle, double sweep, double rs, double re, double t)
    {
        var (ca, cb) = InPlane(s.Center, s.Plane);
        var angle = startAngle + (sweep * t);
        var radius = rs + ((re - rs) * t);
        var n0 = Normal(s.Start, s.Plane);
        var n1 = Normal(s.End, s.Plane);
        return FromPlane(ca + (radius * Math.Cos(angle)), cb + (radius * Math.Sin(angle)), n0 + ((n1 - n0) * t), s.Plane);
    }

    /// <summary>
    /// Widens <paramref name="box"/> by the arc: its ends plus every axis extreme (0, 90, 180, 270 degrees) the
    /// sweep passes, so extents are exact without sampling.
    /// </summary>
    internal static void Extend(in PathSegment s, ref Box3 box)
    {
        box.Add(s.Start);
        box.Add(s.End);
        var (a0, sweep, rs, re) = Describe(s);
        var (ca, cb) = InPlane(s.Center, s.Plane);
        var r = Math.Max(rs, re);
        var lo = Math.Min(a0, a0 + sweep);
        var hi = Math.Max(a0, a0 + sweep);
        var first = Math.Ceiling(lo / (Math.PI / 2));
        for (var q = first; q * (Math.PI / 2) <= hi; q++)
        {
            var angle = q * (Math.PI / 2);
            var t = (angle - a0) / sweep;
            var n = Normal(s.Start, s.Plane) + ((Normal(s.End, s.Plane) - Normal(s.Start, s.Plane)) * t);
            // Exact unit vectors at the quadrants, so extents read 0 and not 6e-16.
            var quadrant = (((int)q % 4) + 4) % 4;
            var (cos, sin) = quadrant switch { 0 => (1, 0), 1 => (0, 1), 2 => (-1, 0), _ => (0, -1) };
            box.Add(FromPlane(ca + (r * cos), cb + (r * sin), n, s.Plane));
        }
    }
}

/// <summary>An axis-aligned box that grows by points (empty until the first).</summary>
internal struct Box3
{
    public double MinX, MinY, MinZ, MaxX, MaxY, MaxZ;
    public bool IsEmpty;

    public static Box3 Empty => new()
    {
        IsEmpty = true,
        MinX = double.PositiveInfinity, MinY = double.PositiveInfinity, MinZ = double.PositiveInfinity,
        MaxX = double.NegativeInfinity, MaxY = double.NegativeInfinity, MaxZ = double.NegativeInfinity,
    };

    public void Add(Point3D p)
    {
        IsEmpty = false;
        MinX = Math.Min(MinX, p.X);
        MinY = Math.Min(MinY, p.Y);
        MinZ = Math.Min(MinZ, p.Z);
        MaxX = Math.Max(MaxX, p.X);
        MaxY = Math.Max(MaxY, p.Y);
        MaxZ = Math.Max(MaxZ, p.Z);
    }
}
