namespace PmacStream.GCode;

/// <summary>
/// A compensated move whose end a G41/G42 inside corner moved back to where the offset paths cross
/// (<see cref="CanonBlock.AmendedEnd"/>): what is left of it, for whoever keeps the move's length or time (the ETA,
/// the program store's block records).
/// </summary>
public static class AmendedMove
{
    /// <summary>
    /// The part of the move from <paramref name="start"/> to <paramref name="end"/> that runs when it ends at
    /// <paramref name="amended"/> instead (0..1): a line by its length, an arc about <paramref name="centre"/> by the
    /// angle it still sweeps (XY), so its time at the same feed is that part of the time.
    /// </summary>
    public static double Fraction(MotionKind kind, Point3 start, Point3 end, Point3? centre, Point3 amended)
    {
        double fraction;
        if (kind is MotionKind.ArcCw or MotionKind.ArcCcw && centre is { } c)
        {
            var full = Sweep(start, end, c, kind == MotionKind.ArcCw);
            fraction = full > 1e-12 ? Sweep(start, amended, c, kind == MotionKind.ArcCw) / full : 1;
        }
        else
        {
            var length = start.DistanceTo(end);
            fraction = length > 1e-12 ? start.DistanceTo(amended) / length : 1;
        }

        return Math.Clamp(fraction, 0, 1);
    }

    /// <summary>
    /// <paramref name="point"/> moved to the crossing of an inside corner (<see cref="CanonBlock.AmendedEnd"/>) on X and Y,
    /// its own Z kept: the end of the move held, or both ends of a move queued behind it.
    /// </summary>
    public static Point3 MovedTo(Point3 point, Point3 crossing) => new(crossing.X, crossing.Y, point.Z);

    /// <summary>The angle an arc about <paramref name="c"/> sweeps from <paramref name="from"/> to <paramref name="to"/> in its direction (0..2π, XY).</summary>
    private static double Sweep(Point3 from, Point3 to, Point3 c, bool clockwise)
    {
        var a = Math.Atan2(to.Y - c.Y, to.X - c.X) - Math.Atan2(from.Y - c.Y, from.X - c.X);
        a = clockwise ? -a : a;
        return a < 0 ? a + (2 * Math.PI) : a;
    }
}
