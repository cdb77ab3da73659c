using PmacStream.GCode;

namespace PmacStream.Preview;

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

    /// <summary>
    /// Widens the box by an arc segment: its ends plus every axis extreme (0, 90, 180, 270 degrees) the sweep passes,
    /// so extents are exact without sampling.
    /// </summary>
    public void AddArc(in PathSegment s)
    {
        var plane = (int)s.Plane;
        Add(s.Start);
        Add(s.End);
        var (a0, sweep, rs, re) = ArcGeometry.Describe(s.Start, s.End, s.Center, plane, s.Motion == PathMotion.ArcCcw);
        var (ca, cb) = ArcGeometry.InPlane(s.Center, plane);
        var r = Math.Max(rs, re);
        var lo = Math.Min(a0, a0 + sweep);
        var hi = Math.Max(a0, a0 + sweep);
        var first = Math.Ceiling(lo / (Math.PI / 2));
        for (var q = first; q * (Math.PI / 2) <= hi; q++)
        {
            var angle = q * (Math.PI / 2);
            var t = (angle - a0) / sweep;
            var n = ArcGeometry.Normal(s.Start, plane) + ((ArcGeometry.Normal(s.End, plane) - ArcGeometry.Normal(s.Start, plane)) * t);
            // Exact unit vectors at the quadrants, so extents read 0 and not 6e-16.
            var quadrant = (((int)q % 4) + 4) % 4;
            var (cos, sin) = quadrant switch { 0 => (1, 0), 1 => (0, 1), 2 => (-1, 0), _ => (0, -1) };
            Add(ArcGeometry.FromPlane(ca + (r * cos), cb + (r * sin), n, plane));
        }
    }

    public void Add(Point3 p)
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
