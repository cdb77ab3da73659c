namespace PmacStream.GCode;

/// <summary>
/// The corner a compensated move goes around first: from the end of the move before it to <see cref="Mid"/>, on a
/// circle of the cutter radius about the programmed corner <see cref="Centre"/> (a feed move), or straight there (a
/// rapid). Machine coordinates; the corner stays at the height of the move before it.
/// </summary>
/// <param name="Mid">Where the corner ends and the move's own line starts.</param>
/// <param name="Centre">The programmed corner, the arc's centre.</param>
/// <param name="Clockwise">The arc's direction: clockwise with the cutter left of the path (G41), else counter-clockwise.</param>
/// <param name="Arc">True for a feed move's arc, false for a rapid's straight way to <see cref="Mid"/>.</param>
public readonly record struct CompensationCorner(Point3 Mid, Point3 Centre, bool Clockwise, bool Arc);

/// <summary>Why a move cannot be compensated as programmed.</summary>
internal enum CompensationFault : byte
{
    /// <summary>The move is compensated.</summary>
    None,

    /// <summary>The first XY move after G41/G42 is not longer than the cutter radius.</summary>
    EntryTooShort,

    /// <summary>
    /// An inside corner the tool cannot fit: the two offset paths do not cross (rs274ngc: "... makes a corner the
    /// compensated tool can't fit in without gouging"), they run back on each other, or the move before is not the
    /// one held (more than <see cref="CutterCompensation.MaxHeldBlocks"/> blocks between).
    /// </summary>
    ConcaveCorner,

    /// <summary>An arc as the first move after G41/G42 (rs274ngc refuses it too).</summary>
    StartOnArc,

    /// <summary>The cutter runs inside an arc whose radius is not larger than the cutter's.</summary>
    ArcTooSmall,

    /// <summary>A full circle: its compensated start and end would be one point only by rounding.</summary>
    FullCircle,
}

/// <summary>
/// Cutter radius compensation of lines and arcs in the XY plane, computed by the host as RS274/NGC does it: the first
/// XY move after G41/G42 (a line) ends one radius off its programmed end, square to the move; each move after it ends
/// one radius off its programmed end, square to itself, on the side G41 (left) or G42 (right) names (an arc keeps its
/// centre); an outside corner first goes around the programmed corner on an arc of the radius. An inside corner moves the
/// end of the move before back to where the two offset paths cross (line and line, line and arc, arc and arc), and
/// the move starts there: rs274ngc's one queued move (<c>move_endpoint_and_flush</c>). The move before is therefore
/// held by whoever sends it until the next move is known (<see cref="Amend"/>). Machine coordinates throughout (work
/// offsets shift, they do not turn, so the geometry is the same).
/// </summary>
internal sealed class CutterCompensation
{
    // Corners turning less than this (radians) need no arc; more than this the other way are inside corners (rs274ngc's
    // TOLERANCE_CONCAVE_CORNER).
    private const double CornerTolerance = 0.05;

    /// <summary>
    /// Blocks queued behind the move held (out-of-plane moves, dwells, codes) at most: an inside corner after more is
    /// refused, so every consumer holds at most this many blocks besides the move.
    /// </summary>
    public const int MaxHeldBlocks = 256;

    private double _programX;
    private double _programY;
    private HeldKind _held;       // the last compensated XY move, whose end an inside corner may move back
    private double _heldCentreX;  // an arc's centre (its offset circle runs through the tool)
    private double _heldCentreY;
    private int _heldBlocks;      // blocks since it
    private int _heldLine;        // its source line (the refusal names it)

    private enum HeldKind : byte
    {
        None,
        Line,
        Arc,
    }

    /// <summary>
    /// The last move's inside corner: where the move before it ends instead of where it was reported to end (the two
    /// offset paths cross there; the move itself starts there); null when the last move had none.
    /// </summary>
    public Point3? Amend { get; private set; }

    /// <summary>41 (cutter left of the path), 42 (right), 0 when off.</summary>
    public int Side { get; private set; }

    /// <summary>The cutter radius in force, millimetres.</summary>
    public double Radius { get; private set; }

    /// <summary>True while compensation is on with a radius above zero.</summary>
    public bool Active => Side != 0 && Radius > 0;

    /// <summary>True once the entry move was made: the programmed XY position is known apart from the tool's.</summary>
    public bool Entered { get; private set; }

    /// <summary>True after a move that could not be compensated: the path is unknown until G40 (the program is refused anyway).</summary>
    public bool Lost { get; private set; }

    /// <summary>
    /// The last block's part in the hold: the move whose end an inside corner may still move (<see cref="CompensationHold.Held"/>),
    /// a block queued behind it (<see cref="CompensationHold.Queued"/>), or none (what came before is final).
    /// </summary>
    public CompensationHold HoldOfBlock =>
        _held == HeldKind.None || Lost || _heldBlocks > MaxHeldBlocks ? CompensationHold.None
        : _heldBlocks == 0 ? CompensationHold.Held : CompensationHold.Queued;

    /// <summary>When the last inside corner was refused because the move it ends lay more than <see cref="MaxHeldBlocks"/> blocks back: that move's line; else null.</summary>
    public int? HeldTooFar { get; private set; }

    /// <summary>Turns compensation on (or off with side 0); the next XY move is the entry move.</summary>
    public void Set(int side, double radius)
    {
        (Side, Radius, Entered, Lost) = (side, side == 0 ? 0 : radius, false, false);
        (_held, Amend) = (HeldKind.None, null);
    }

    /// <summary>A block was taken: the move held is one block further back (and an amendment is the last block's only).</summary>
    public void NextBlock()
    {
        Amend = null;
        _heldBlocks++;
    }

    /// <summary>A move was refused: the moves after it are not judged again (one fault, one report) until G40.</summary>
    public void Lose() => Lost = true;

    /// <summary>The programmed position on the XY plane with <paramref name="tool"/>'s Z: where incremental words count from.</summary>
    public Point3 Programmed(Point3 tool) => Entered ? new Point3(_programX, _programY, tool.Z) : tool;

    /// <summary>
    /// The compensated end of a straight move from the tool at <paramref name="tool"/> to the programmed
    /// <paramref name="target"/>, with the corner before it, if any.
    /// </summary>
    public (Point3 End, CompensationCorner? Corner, CompensationFault Fault) Line(Point3 tool, Point3 target, bool rapid, int line)
    {
        HeldTooFar = null;
        if (!Entered)
        {
            var sign = Side == 41 ? 1.0 : -1.0; // the normal to the left of the move, or to its right
            var (dx, dy) = (target.X - tool.X, target.Y - tool.Y);
            var distance = Math.Sqrt((dx * dx) + (dy * dy));
            if (distance <= Radius)
            {
                // Refused; the moves after it are judged from its programmed end, so one fault is reported once.
                Remember(target);
                return (target, null, CompensationFault.EntryTooShort);
            }

            var end = new Point3(target.X - (sign * Radius * dy / distance), target.Y + (sign * Radius * dx / distance), target.Z);
            Remember(target);
            Hold(HeldKind.Line, 0, 0, line);
            return (end, null, CompensationFault.None);
        }

        if (target.X == _programX && target.Y == _programY)
        {
            // No XY motion (a plunge, a retract): the tool stays off the programmed point where it is. The move held
            // stays held, this one queued behind it: an inside corner at the next XY move moves both to the crossing
            // (rs274ngc queues it the same way, move_endpoint_and_flush).
            return (new Point3(tool.X, tool.Y, target.Z), null, CompensationFault.None);
        }

        var alpha = Math.Atan2(target.Y - _programY, target.X - _programX); // the new move's direction
        var (nx, ny) = Normal(alpha);
        var lineEnd = new Point3(target.X + nx, target.Y + ny, target.Z);
        var (corner, concave) = Corner(tool, alpha, rapid);
        var fault = CompensationFault.None;
        if (concave)
        {
            // The offset line of this move: through the programmed corner's offset point, in its direction.
            var meet = Meet(tool, new Offset(false, _programX + nx, _programY + ny, Math.Cos(alpha), Math.Sin(alpha), 0));
            fault = meet is { } ? CompensationFault.None : CompensationFault.ConcaveCorner;
            Amend = meet is { } q ? new Point3(q.X, q.Y, tool.Z) : null;
        }

        Remember(target);
        Hold(HeldKind.Line, 0, 0, line);
        return (lineEnd, corner, fault);
    }

    /// <summary>
    /// The compensated end of an arc about the programmed <paramref name="centre"/> from the programmed point to
    /// <paramref name="target"/>: the same centre, the radius one cutter radius larger (the cutter outside the arc) or
    /// smaller (inside: G41 with G03, G42 with G02); with the corner before it, if any.
    /// </summary>
    public (Point3 End, CompensationCorner? Corner, CompensationFault Fault) Arc(Point3 tool, Point3 target, Point3 centre, bool clockwise, int line)
    {
        HeldTooFar = null;
        if (!Entered)
        {
            return (target, null, CompensationFault.StartOnArc);
        }

        if (target.X == _programX && target.Y == _programY)
        {
            return (target, null, CompensationFault.FullCircle);
        }

        var arcRadius = Math.Sqrt(((target.X - centre.X) * (target.X - centre.X)) + ((target.Y - centre.Y) * (target.Y - centre.Y)));
        var inside = (Side == 41) != clockwise;
        if (inside && arcRadius <= Radius)
        {
            Remember(target);
            return (target, null, CompensationFault.ArcTooSmall);
        }

        // The arc's direction where it starts: square to the radius, ahead in the arc's sense.
        var toCentre = Math.Atan2(centre.Y - _programY, centre.X - _programX);
        var alpha = toCentre + (clockwise ? Math.PI / 2 : -Math.PI / 2);
        var offsetRadius = arcRadius + (inside ? -Radius : Radius);
        var scale = offsetRadius / arcRadius;
        var end = new Point3(centre.X + ((target.X - centre.X) * scale), centre.Y + ((target.Y - centre.Y) * scale), target.Z);
        var (corner, concave) = Corner(tool, alpha, rapid: false);
        var fault = CompensationFault.None;
        if (concave)
        {
            var meet = Meet(tool, new Offset(true, centre.X, centre.Y, 0, 0, offsetRadius));
            fault = meet is { } ? CompensationFault.None : CompensationFault.ConcaveCorner;
            Amend = meet is { } q ? new Point3(q.X, q.Y, tool.Z) : null;
        }

        Remember(target);
        Hold(HeldKind.Arc, centre.X, centre.Y, line);
        return (end, corner, fault);
    }

    /// <summary>The next move's offset path: a line through (X, Y) in direction (Dx, Dy), or a circle about (X, Y) of radius R.</summary>
    private readonly record struct Offset(bool Circle, double X, double Y, double Dx, double Dy, double R);

    /// <summary>
    /// Where the held move's offset path (a line through the tool square to the programmed corner, or its arc's
    /// circle through the tool) crosses <paramref name="next"/>'s, the crossing nearest the tool; null when they do not
    /// cross, or when no move is held.
    /// </summary>
    private (double X, double Y)? Meet(Point3 tool, Offset next)
    {
        // The corner's own block is one more than the blocks queued between.
        if (_held == HeldKind.None || _heldBlocks > MaxHeldBlocks + 1)
        {
            HeldTooFar = _held != HeldKind.None ? _heldLine : null;
            return null;
        }

        if (_held == HeldKind.Line)
        {
            // The held line's direction: square to the way from the programmed corner to the tool (rs274ngc's theta).
            var theta = Math.Atan2(tool.Y - _programY, tool.X - _programX);
            var gamma = theta + (Side == 41 ? -Math.PI / 2 : Math.PI / 2);
            var (dx, dy) = (Math.Cos(gamma), Math.Sin(gamma));
            return next.Circle ? LineCircle(tool.X, tool.Y, dx, dy, next, tool) : LineLine(tool.X, tool.Y, dx, dy, next);
        }

        var radius = Math.Sqrt(((tool.X - _heldCentreX) * (tool.X - _heldCentreX)) + ((tool.Y - _heldCentreY) * (tool.Y - _heldCentreY)));
        var held = new Offset(true, _heldCentreX, _heldCentreY, 0, 0, radius);
        if (!next.Circle)
        {
            return LineCircle(next.X, next.Y, next.Dx, next.Dy, held, tool);
        }

        return CircleCircle(held, next, tool);
    }

    private static (double X, double Y)? LineLine(double x, double y, double dx, double dy, Offset b)
    {
        var cross = (dx * b.Dy) - (dy * b.Dx);
        if (Math.Abs(cross) < 1e-12)
        {
            return null; // parallel: a zero-degree corner
        }

        var t = (((b.X - x) * b.Dy) - ((b.Y - y) * b.Dx)) / cross;
        return (x + (t * dx), y + (t * dy));
    }

    private static (double X, double Y)? LineCircle(double x, double y, double dx, double dy, Offset c, Point3 near)
    {
        // |(x, y) + t (dx, dy) - centre| = R, (dx, dy) a unit vector.
        var (fx, fy) = (x - c.X, y - c.Y);
        var b = (fx * dx) + (fy * dy);
        var disc = (b * b) - ((fx * fx) + (fy * fy) - (c.R * c.R));
        if (disc < 0)
        {
            return null;
        }

        var root = Math.Sqrt(disc);
        var (t1, t2) = (-b - root, -b + root);
        var p1 = (X: x + (t1 * dx), Y: y + (t1 * dy));
        var p2 = (X: x + (t2 * dx), Y: y + (t2 * dy));
        return Nearer(p1, p2, near);
    }

    private static (double X, double Y)? CircleCircle(Offset a, Offset b, Point3 near)
    {
        var (dx, dy) = (b.X - a.X, b.Y - a.Y);
        var d = Math.Sqrt((dx * dx) + (dy * dy));
        if (d < 1e-12 || d > a.R + b.R || d < Math.Abs(a.R - b.R))
        {
            return null;
        }

        var along = ((a.R * a.R) - (b.R * b.R) + (d * d)) / (2 * d);
        var h = Math.Sqrt(Math.Max(0, (a.R * a.R) - (along * along)));
        var (mx, my) = (a.X + (along * dx / d), a.Y + (along * dy / d));
        return Nearer((mx - (h * dy / d), my + (h * dx / d)), (mx + (h * dy / d), my - (h * dx / d)), near);
    }

    private static (double X, double Y) Nearer((double X, double Y) p1, (double X, double Y) p2, Point3 near) =>
        ((p1.X - near.X) * (p1.X - near.X)) + ((p1.Y - near.Y) * (p1.Y - near.Y)) <= ((p2.X - near.X) * (p2.X - near.X)) + ((p2.Y - near.Y) * (p2.Y - near.Y)) ? p1 : p2;

    private void Hold(HeldKind kind, double centreX, double centreY, int line)
    {
        (_held, _heldCentreX, _heldCentreY, _heldBlocks, _heldLine) = (kind, centreX, centreY, 0, line);
    }

    // One radius square to direction alpha, on the compensation's side.
    private (double X, double Y) Normal(double alpha)
    {
        var normal = alpha + ((Side == 41 ? 1.0 : -1.0) * Math.PI / 2);
        return (Radius * Math.Cos(normal), Radius * Math.Sin(normal));
    }

    /// <summary>
    /// The corner between the move before (the tool is one radius off its programmed end, square to it) and a move
    /// leaving the programmed point in direction <paramref name="alpha"/>: an arc about the programmed point for an
    /// outside corner, none when going straight on, and whether it is an inside corner.
    /// </summary>
    private (CompensationCorner? Corner, bool Concave) Corner(Point3 tool, double alpha, bool rapid)
    {
        var theta = Math.Atan2(tool.Y - _programY, tool.X - _programX); // from the programmed corner to the tool
        alpha = Math.Atan2(Math.Sin(alpha), Math.Cos(alpha));
        double beta;
        if (Side == 41)
        {
            theta += theta < alpha ? 2 * Math.PI : 0;
            beta = theta - alpha - (Math.PI / 2);
        }
        else
        {
            alpha += alpha < theta ? 2 * Math.PI : 0;
            beta = alpha - theta - (Math.PI / 2);
        }

        if (beta < -CornerTolerance || beta > Math.PI + CornerTolerance)
        {
            return (null, true);
        }

        if (beta <= CornerTolerance)
        {
            return (null, false);
        }

        var (nx, ny) = Normal(alpha);
        return (new CompensationCorner(new Point3(_programX + nx, _programY + ny, tool.Z), new Point3(_programX, _programY, tool.Z), Side == 41, !rapid), false);
    }

    /// <summary>The length of a corner's way from <paramref name="tool"/> to its end: along the arc, or straight for a rapid.</summary>
    public double CornerLength(Point3 tool, CompensationCorner corner)
    {
        if (!corner.Arc)
        {
            return tool.DistanceTo(corner.Mid);
        }

        var a0 = Math.Atan2(tool.Y - corner.Centre.Y, tool.X - corner.Centre.X);
        var a1 = Math.Atan2(corner.Mid.Y - corner.Centre.Y, corner.Mid.X - corner.Centre.X);
        var sweep = corner.Clockwise ? a0 - a1 : a1 - a0;
        sweep += sweep < 0 ? 2 * Math.PI : 0;
        return sweep * Radius;
    }

    private void Remember(Point3 target)
    {
        (_programX, _programY, Entered) = (target.X, target.Y, true);
    }
}
