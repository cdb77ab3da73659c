using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>
/// What the preview draws of one block, as the interpreter decided it: its motion (kind, start, end, centre, machine
/// millimetres), the plane and distance mode it left, which of X/Y/Z the line named, the units it left and a cycle's
/// holes. A file's preview takes it from the canonical calls (<see cref="CanonToolpath"/>), a stored revision's from
/// its stored rows (<see cref="Of(DecodedBlock, CycleHoles?)"/>), so both draw the same.
/// </summary>
/// <param name="Line">The block's source line.</param>
/// <param name="Kind">What moved (<see cref="MotionKind.None"/>: nothing).</param>
/// <param name="Start">Where the move starts.</param>
/// <param name="End">Where it ends.</param>
/// <param name="Centre">An arc's centre (null: the interpreter could not place it).</param>
/// <param name="Plane">The plane in force after the block: 17, 18 or 19.</param>
/// <param name="Absolute">G90 in force after the block.</param>
/// <param name="NamedX">The line named X.</param>
/// <param name="NamedY">The line named Y.</param>
/// <param name="NamedZ">The line named Z.</param>
/// <param name="Units">The units in force after the block.</param>
/// <param name="Holes">A cycle block's holes.</param>
public readonly record struct DrawnBlock(
    int Line, MotionKind Kind, Point3 Start, Point3 End, Point3? Centre, int Plane, bool Absolute, bool NamedX, bool NamedY, bool NamedZ,
    LengthUnits Units, CycleHoles? Holes)
{
    /// <summary>A stored block (its row, decided by the interpreter when the revision was imported) and its holes.</summary>
    public static DrawnBlock Of(DecodedBlock block, CycleHoles? holes)
    {
        ArgumentNullException.ThrowIfNull(block);
        return new DrawnBlock(block.Line, block.Motion, block.Start, block.End, block.Center, block.Modal.Plane, block.Modal.Absolute,
            block.X.HasValue, block.Y.HasValue, block.Z.HasValue, block.Modal.Units, holes);
    }
}

/// <summary>
/// Turns the blocks the interpreter decided (millimetres) into drawable segments, and withholds moves along an axis
/// whose position has not been set yet. Only motion sets a position: a data block (G10, G52, G92) carries axis words
/// that are offsets, not a place the tool goes to. The interpreter's positions are machine coordinates (the work offset,
/// G52, G92 and the tool length applied), so a program run under G55 is drawn where G55 puts it. A cycle block is
/// drawn hole by hole.
/// </summary>
public sealed class ToolpathBuilder
{
    private bool _x;
    private bool _y;
    private bool _z;
    private bool _unitsSeen;

    /// <summary>Units of the first block (millimetres before any).</summary>
    public LengthUnits Units { get; private set; }

    /// <summary>True when later blocks used other units than the first.</summary>
    public bool MixedUnits { get; private set; }

    /// <summary>
    /// Adds the segments of a move whose moving axes start from known positions to <paramref name="into"/> (one, or
    /// four per hole of a cycle block); returns how many. None for non-moves, data blocks and first positionings.
    /// </summary>
    public int Add(in DrawnBlock block, List<PathSegment> into)
    {
        ArgumentNullException.ThrowIfNull(into);
        if (!_unitsSeen)
        {
            _unitsSeen = true;
            Units = block.Units;
        }
        else if (block.Units != Units)
        {
            MixedUnits = true;
        }

        if (block.Kind is MotionKind.None or MotionKind.Dwell)
        {
            return 0;
        }

        // A move is drawn when every axis it moves started from a known position. An axis the program never sets
        // (Z in a 2D program) does not move, so it does not withhold the moves of the others.
        var known = (!block.NamedX || _x) && (!block.NamedY || _y) && (!block.NamedZ || _z);
        if (block.Absolute)
        {
            _x |= block.NamedX;
            _y |= block.NamedY;
            _z |= block.NamedZ;
        }

        if (!known)
        {
            return 0;
        }

        // The interpreter's positions are millimetres already, whatever the program's units.
        switch (block.Kind)
        {
            case MotionKind.Rapid:
            case MotionKind.Linear:
                into.Add(PathSegment.Line(block.Start, block.End, block.Kind == MotionKind.Rapid, block.Line));
                return 1;
            case MotionKind.Cycle:
                return block.Holes is { Count: > 0 } h ? AddHoles(block, h, into) : 0;
            default:
                if (block.Centre is not { } c)
                {
                    return 0; // the interpreter could not place the centre; the error is reported
                }

                into.Add(PathSegment.Arc(block.Start, block.End, c, (ArcPlane)block.Plane, block.Kind == MotionKind.ArcCw, block.Line));
                return 1;
        }
    }

    /// <summary>Each hole: rapid over it at the height the tool has, rapid down to R, feed to the bottom, rapid up to the retract level.</summary>
    private static int AddHoles(in DrawnBlock block, CycleHoles holes, List<PathSegment> into)
    {
        var at = block.Start;
        var retract = block.End.Z;
        for (var n = 1; n <= holes.Count; n++)
        {
            var t = block.Absolute ? 1.0 : (double)n / holes.Count;
            var hole = new Point3(block.Start.X + ((block.End.X - block.Start.X) * t), block.Start.Y + ((block.End.Y - block.Start.Y) * t), at.Z);
            into.Add(PathSegment.Line(at, hole, rapid: true, block.Line));
            into.Add(PathSegment.Line(hole, hole with { Z = holes.RLevel }, rapid: true, block.Line));
            into.Add(PathSegment.Line(hole with { Z = holes.RLevel }, hole with { Z = holes.Bottom }, rapid: false, block.Line));
            into.Add(PathSegment.Line(hole with { Z = holes.Bottom }, hole with { Z = retract }, rapid: true, block.Line));
            at = hole with { Z = retract };
        }

        return 4 * holes.Count;
    }
}

/// <summary>
/// The preview's canonical sink: what the interpreter decided for the line it took last, as a <see cref="DrawnBlock"/>
/// (its <see cref="ICanonicalMoves.Motion"/> and <see cref="ICanonicalMoves.EndBlock"/>), the inside corner it decided
/// there and the rotary axes the program names. Nothing is read back from the interpreter or the line's words.
/// </summary>
internal sealed class CanonToolpath : ICanonicalMoves
{
    private CanonMotion _motion;
    private bool _moved;

    /// <summary>The block of the line taken last.</summary>
    public DrawnBlock Block { get; private set; }

    /// <summary>At a G41/G42 inside corner: where the move before this block ends instead (<see cref="CanonBlock.AmendedEnd"/>).</summary>
    public Point3? AmendedEnd { get; private set; }

    /// <summary>The block's part in the moves held under G41/G42 (<see cref="CanonBlock.Hold"/>).</summary>
    public CompensationHold Hold { get; private set; }

    /// <summary>The rotary axes (A, B, C) some line named, as bits 1, 2, 4: the picture draws X, Y and Z only, and the legend says so.</summary>
    public int Rotary { get; private set; }

    public void StartBlock(in CanonStart start) => _moved = false;

    public void Step(in HostMove step)
    {
    }

    public void Motion(in CanonMotion motion) => (_motion, _moved) = (motion, true);

    public void EndBlock(in CanonBlock block)
    {
        var given = block.Given;
        Rotary |= (given.A.HasValue ? 1 : 0) | (given.B.HasValue ? 2 : 0) | (given.C.HasValue ? 4 : 0);
        (AmendedEnd, Hold) = (block.AmendedEnd, block.Hold);
        var m = _moved ? _motion : default;
        Block = new DrawnBlock(m.Line, _moved ? m.Kind : MotionKind.None, m.Start, m.End, m.Centre, block.Plane, block.Absolute,
            given.X.HasValue, given.Y.HasValue, given.Z.HasValue, block.UnitScale != 1.0 ? LengthUnits.Inches : LengthUnits.Millimetres, block.Holes);
    }
}
