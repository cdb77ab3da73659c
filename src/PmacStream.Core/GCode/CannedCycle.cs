namespace PmacStream.GCode;

/// <summary>
/// A drilling, tapping or boring cycle in force (G73, G74, G76, G81-G89): what each positioning block does while it
/// is. FANUC and RS274/NGC agree on the shape: rapid to the hole's X/Y, rapid down to the R level, feed to the bottom Z,
/// back up to the R level (G99) or to the initial level the tool had when the cycle began (G98). Z and R stay in force
/// from block to block until the cycle ends. With G91, R is measured from the initial level and Z from the R level,
/// and a repeat count (K, or L) steps the hole along X/Y.
/// </summary>
internal sealed class CannedCycle
{
    private double? _bottom; // machine Z of the hole bottom, kept from block to block
    private double? _r;      // machine Z of the R level

    /// <summary>The cycle code's key (810 for G81), 0 when no cycle is in force.</summary>
    public int Code { get; private set; }

    /// <summary>True while a cycle is in force.</summary>
    public bool Active => Code != 0;

    /// <summary>The Z the tool had when the cycle began (machine coordinates).</summary>
    public double InitialZ { get; private set; }

    /// <summary>The holes of the last <see cref="Run"/>: how many, and the R level and bottom they used (machine Z).</summary>
    public CycleHoles LastHoles { get; private set; }

    /// <summary>Whether a bottom Z is known (from this block or an earlier one of the cycle).</summary>
    public bool HasBottom => _bottom.HasValue;

    /// <summary>A cycle code takes effect; a new cycle after none starts at the tool's Z.</summary>
    public void Enter(int key, double currentZ)
    {
        if (!Active)
        {
            InitialZ = currentZ;
            _bottom = null;
            _r = null;
        }

        Code = key;
    }

    /// <summary>G80 or a motion code: no cycle in force.</summary>
    public void Cancel() => Code = 0;

    /// <summary>
    /// The holes of one positioning block. <paramref name="x"/>..<paramref name="r"/> are the block's words,
    /// <paramref name="offset"/> the work offset; returns the end point, the path length split into rapid and feed
    /// parts, and the number of holes (0 for K0/L0, which only stores the data).
    /// </summary>
    public (Point3 End, double RapidLength, double FeedLength, int Holes) Run(Point3 start, double? x, double? y, double? z, double? r,
        int repeats, bool absolute, bool returnToR, Point3 offset)
    {
        if (r is { } rv)
        {
            _r = absolute ? rv + offset.Z : InitialZ + rv;
        }

        var rLevel = _r ?? InitialZ;
        if (z is { } zv)
        {
            _bottom = absolute ? zv + offset.Z : rLevel + zv;
        }

        var bottom = _bottom ?? start.Z;
        LastHoles = new CycleHoles(Math.Max(0, repeats), rLevel, bottom);
        if (repeats <= 0)
        {
            return (start, 0, 0, 0);
        }

        var retract = returnToR ? rLevel : InitialZ;
        var rapid = 0.0;
        var feed = 0.0;
        var at = start;
        for (var n = 0; n < repeats; n++)
        {
            var hole = absolute
                ? new Point3(x is { } ax ? ax + offset.X : at.X, y is { } ay ? ay + offset.Y : at.Y, at.Z)
                : new Point3(at.X + (x ?? 0), at.Y + (y ?? 0), at.Z);
            rapid += Math.Sqrt(((hole.X - at.X) * (hole.X - at.X)) + ((hole.Y - at.Y) * (hole.Y - at.Y)));
            // Down to R and back up at rapid, into the hole at feed (most cycles leave it at rapid; boring ones feed out).
            rapid += Math.Abs(at.Z - rLevel) + Math.Abs(rLevel - bottom) + Math.Abs(rLevel - retract);
            feed += Math.Abs(rLevel - bottom);
            at = hole with { Z = retract };
        }

        return (at, rapid, feed, repeats);
    }
}
