namespace PmacStream.GCode;

/// <summary>
/// A drilling, tapping or boring cycle in force (G73, G74, G76, G81-G89): what each positioning block does while it
/// is. FANUC and RS274/NGC agree on the shape: rapid to the hole's X/Y, rapid down to the R level, into the hole, back
/// up to the R level (G99) or to the initial level the tool had when the cycle began (G98). Z and R stay in force
/// from block to block until the cycle ends. With G91, R is measured from the initial level and Z from the R level,
/// and a repeat count (K, or L) steps the hole along X/Y. Every hole is written out as its steps (<see cref="Steps"/>),
/// which the host sends to the controller as plain moves: move times come from the same steps.
/// </summary>
internal sealed class CannedCycle
{
    /// <summary>How far G73 backs out after each peck and how far above the last depth G83 comes back down (a machine parameter: FANUC 5114/5115; LinuxCNC's 0.010 in).</summary>
    public const double PeckClearance = 0.254;

    private readonly List<HostMove> _steps = [];
    private double? _bottom; // machine Z of the hole bottom, kept from block to block
    private double? _r;      // machine Z of the R level
    private double _q;       // peck depth (G73, G83) or boring shift (G76, G87), kept like Z and R

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

    /// <summary>The steps of the last <see cref="Run"/>, machine coordinates (reused: read before the next block).</summary>
    public IReadOnlyList<HostMove> Steps => _steps;

    /// <summary>A cycle code takes effect; a new cycle after none starts at the tool's Z.</summary>
    public void Enter(int key, double currentZ)
    {
        if (!Active)
        {
            InitialZ = currentZ;
            _bottom = null;
            _r = null;
            _q = 0;
        }

        Code = key;
    }

    /// <summary>G80 or a motion code: no cycle in force.</summary>
    public void Cancel() => Code = 0;

    /// <summary>
    /// The holes of one positioning block. <paramref name="x"/>..<paramref name="r"/> are the block's words in
    /// millimetres, <paramref name="q"/> the peck depth or boring shift, <paramref name="dwell"/> the bottom dwell in
    /// seconds, <paramref name="offset"/> the work offset; fills <see cref="Steps"/> and returns the end point, the
    /// path length split into rapid and feed parts, and the number of holes (0 for K0/L0, which only stores the data).
    /// </summary>
    public (Point3 End, double RapidLength, double FeedLength, int Holes) Run(Point3 start, double? x, double? y, double? z, double? r,
        double? q, double dwell, int repeats, bool absolute, bool returnToR, Point3 offset)
    {
        _steps.Clear();
        if (r is { } rv)
        {
            _r = absolute ? rv + offset.Z : InitialZ + rv;
        }

        var rLevel = _r ?? InitialZ;
        if (z is { } zv)
        {
            _bottom = absolute ? zv + offset.Z : rLevel + zv;
        }

        if (q is { } qv)
        {
            _q = Math.Abs(qv);
        }

        var bottom = _bottom ?? start.Z;
        LastHoles = new CycleHoles(Math.Max(0, repeats), rLevel, bottom);
        if (repeats <= 0)
        {
            return (start, 0, 0, 0);
        }

        var retract = returnToR && Code != 870 ? rLevel : InitialZ;
        var at = start;
        for (var n = 0; n < repeats; n++)
        {
            var hole = absolute
                ? new Point3(x is { } ax ? ax + offset.X : at.X, y is { } ay ? ay + offset.Y : at.Y, at.Z)
                : new Point3(at.X + (x ?? 0), at.Y + (y ?? 0), at.Z);
            at = Hole(hole, rLevel, bottom, retract, dwell);
        }

        double rapid = 0, feed = 0;
        var from = start;
        foreach (var s in _steps)
        {
            if (s.Kind is HostMoveKind.Rapid or HostMoveKind.Feed)
            {
                var d = from.DistanceTo(s.Target);
                if (s.Kind == HostMoveKind.Rapid)
                {
                    rapid += d;
                }
                else
                {
                    feed += d;
                }

                from = s.Target;
            }
        }

        return (at, rapid, feed, repeats);
    }

    /// <summary>One hole from <paramref name="above"/> (its X/Y at the tool's Z): the steps of the cycle in force; returns where the tool ends.</summary>
    private Point3 Hole(Point3 above, double rLevel, double bottom, double retract, double dwell)
    {
        Point3 At(double z) => above with { Z = z };
        void Rapid(Point3 p) => _steps.Add(new HostMove(HostMoveKind.Rapid, p));
        void Feed(Point3 p) => _steps.Add(new HostMove(HostMoveKind.Feed, p));
        void Do(HostMoveKind kind, double seconds = 0) => _steps.Add(new HostMove(kind, At(0), seconds));

        // G76/G87 at the bottom: the spindle stops oriented, the tool leaves the hole shifted off the wall by Q and
        // comes back over its centre at the retract level, turning again.
        Point3 LeaveShifted(Point3 shift)
        {
            Do(HostMoveKind.SpindleOrient);
            Rapid(At(bottom) + shift);
            Rapid(At(retract) + shift);
            Rapid(At(retract));
            Do(HostMoveKind.SpindleForward);
            return At(retract);
        }

        Rapid(above);
        if (Code == 870)
        {
            // Back boring (G87): the tool goes down past the hole with the spindle oriented and shifted, bores upward to Z.
            var shift = new Point3(_q, 0, 0);
            Do(HostMoveKind.SpindleOrient);
            Rapid(above + shift);
            Rapid(At(rLevel) + shift);
            Rapid(At(rLevel));
            Do(HostMoveKind.SpindleForward);
            Feed(At(bottom));
            return LeaveShifted(shift);
        }

        Rapid(At(rLevel));
        var down = bottom < rLevel ? -1.0 : 1.0;
        switch (Code)
        {
            case 730 or 830 when _q > 0:
                Pecks(above, rLevel, bottom, down);
                break;
            default:
                Feed(At(bottom));
                break;
        }

        if (dwell > 0 && Code is 820 or 890 or 740 or 840 or 760 or 880)
        {
            Do(HostMoveKind.Dwell, dwell);
        }

        switch (Code)
        {
            case 840 or 740:
                // Tapping: the spindle reverses at the bottom and the tap feeds out to R, then turns its own way again.
                Do(Code == 840 ? HostMoveKind.SpindleReverse : HostMoveKind.SpindleForward);
                Feed(At(rLevel));
                Do(Code == 840 ? HostMoveKind.SpindleForward : HostMoveKind.SpindleReverse);
                break;
            case 850 or 890:
                Feed(At(rLevel));
                break;
            case 860 or 880:
                Do(HostMoveKind.SpindleStop);
                Rapid(At(retract));
                Do(HostMoveKind.SpindleForward);
                return At(retract);
            case 760:
                // Fine boring: the spindle stops oriented and the tool shifts off the wall by Q before it comes out.
                return LeaveShifted(new Point3(_q, 0, 0));
        }

        if (Math.Abs(LastZ() - retract) > 1e-12)
        {
            Rapid(At(retract));
        }

        return At(retract);
    }

    /// <summary>
    /// Pecks of Q from R down to the bottom: G73 backs out a little after each, G83 goes back to R and comes down again
    /// near the last depth.
    /// </summary>
    private void Pecks(Point3 above, double rLevel, double bottom, double down)
    {
        Point3 At(double z) => above with { Z = z };
        void Rapid(Point3 p) => _steps.Add(new HostMove(HostMoveKind.Rapid, p));
        var depth = rLevel;
        while ((bottom - depth) * down > 1e-9)
        {
            var next = (bottom - (depth + (down * _q))) * down > 0 ? depth + (down * _q) : bottom;
            _steps.Add(new HostMove(HostMoveKind.Feed, At(next)));
            depth = next;
            if ((bottom - depth) * down > 1e-9)
            {
                if (Code == 730)
                {
                    Rapid(At(depth - (down * PeckClearance)));
                }
                else
                {
                    Rapid(At(rLevel));
                    Rapid(At(depth - (down * PeckClearance)));
                }
            }
        }
    }

    private double LastZ()
    {
        for (var i = _steps.Count - 1; i >= 0; i--)
        {
            if (_steps[i].Kind is HostMoveKind.Rapid or HostMoveKind.Feed)
            {
                return _steps[i].Target.Z;
            }
        }

        return double.NaN;
    }
}
