namespace PmacStream.GCode;

/// <summary>The interpreter's side of the splitter's axis lane, and the position arithmetic it shares with the full path.</summary>
public sealed partial class Interpreter
{
    /// <summary>
    /// Interprets an <see cref="AxisLine"/> (N, the motion code in force, X/Y/Z), whose text is at
    /// <paramref name="textStart"/> of <paramref name="text"/>, when that is sure to raise no diagnostic and to do
    /// nothing but move: absolute G00 (with a rapid rate) or G01 with a feed, no non-modal code pending, no cycle in
    /// force, neither lengths nor records wanted. The state then ends as <see cref="StepCore"/> leaves it
    /// (<see cref="Last"/> is not filled: nobody reads it without records); otherwise nothing changes and the answer
    /// is false.
    /// </summary>
    public bool TryStepAxisLine(in AxisLine a, byte[] text, int textStart)
    {
        if (!_laneOpen || (a.HasG && a.G != _g[_motionGroup]))
        {
            return false;
        }

        if (!ReferenceEquals(text, _pendingText))
        {
            // Values left in another array (a grown or earlier batch) are read while it is still intact.
            Resolve();
            _pendingText = text;
        }

        var axes = a.Axes;
        for (var axis = 0; axis < 3; axis++)
        {
            if ((axes & (AxisLine.XBit << axis)) != 0)
            {
                _pendingAt[axis] = textStart + a.At[axis];
                _pendingSize[axis] = a.Size[axis];
            }
        }

        _pendingAxes |= axes;
        LastHadProgramNumber = false;
        return true;
    }

    /// <summary>Whether <see cref="TryStepAxisLine"/> can take a line at all now (false in G91, G02/G03, without a feed, in a cycle ...).</summary>
    public bool AxisLaneOpen => _laneOpen;

    /// <summary>
    /// Whether <see cref="TryStepAxisLine"/> would take <paramref name="a"/> now if neither lengths nor records were
    /// wanted: the line then only moves, and its full interpretation (<see cref="StepCore"/>, which records and
    /// measures it) leaves the state the lane would. A split that stores every block in its pass interprets such a
    /// line in full and still sends it as the lane's text.
    /// </summary>
    public bool AxisLineOnlyMoves(in AxisLine a) => _laneOpenUnrecorded && !(a.HasG && a.G != _g[_motionGroup]);

    /// <summary>
    /// The caller is about to reuse <paramref name="text"/> (an <see cref="AxisLine"/>'s text array given to
    /// <see cref="TryStepAxisLine"/>): values still held there are read now.
    /// </summary>
    public void ReleaseText(byte[] text)
    {
        if (ReferenceEquals(text, _pendingText))
        {
            Resolve();
            _pendingText = null;
        }
    }

    /// <summary>Converts the axis values lane lines left as text into the position.</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private void Resolve()
    {
        if (_pendingAxes != 0)
        {
            ResolvePending();
        }
    }

    private void ResolvePending()
    {
        // The lane only takes lines in absolute mode, and nothing changed the mode or the work offset since: the
        // block's own target computation gives the same position the full path would have.
        var axes = _pendingAxes;
        _pendingAxes = 0;
        _pos = Target(_pos, PendingValue(axes, 0), PendingValue(axes, 1), PendingValue(axes, 2));
    }

    private double? PendingValue(int axes, int axis) =>
        (axes & (AxisLine.XBit << axis)) != 0 ? AxisLine.Value(_pendingText.AsSpan(_pendingAt[axis], _pendingSize[axis])) : null;

    /// <summary>Whether an <see cref="AxisLine"/> would only move in the state reached (recomputed whenever it may change).</summary>
    private void UpdateLane()
    {
        var mode = MotionMode();
        _laneOpenUnrecorded = !_nonModalSet && _absolute && _axisLineLetters && !_cycle.Active &&
            _feedMode == 94 && _scale == 1.0 && _transform == null && !_exactStop && !_comp.Active && (mode == 1 ? _feed > 0 : mode == 0 && _profile.RapidRate > 0);
        _laneOpen = _laneOpenUnrecorded && !_recordBlocks && !_measureMoves;
    }

    // The motion mode of the motion group (0..3 for G00..G03, 4 for the other moves to a point, -1 when none),
    // recomputed only when that group changes.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private int MotionMode()
    {
        var ga = _motionGroup >= 0 ? _g[_motionGroup] : null;
        if (ga != _motionFor)
        {
            _motionFor = ga;
            _motion = ga is { } v ? ModeOf(MachineProfile.Key(v)) : -1;
        }

        return _motion;
    }

    private static int ModeOf(int key) => key switch
    {
        0 or 10 or 20 or 30 => key / 10,
        _ => CodeRoles.OfG(key) == GRole.Motion ? 4 : -1,
    };

    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private Point3 Target(Point3 start, double? x, double? y, double? z)
    {
        if (_transform != null)
        {
            return TransformedTarget(x, y, z);
        }

        if (_absolute)
        {
            // The offset of the active work coordinate system, looked up once per change, not per block.
            var o = _coords.Active;
            return new Point3(x is { } ax ? ax + o.X : start.X, y is { } ay ? ay + o.Y : start.Y, z is { } az ? az + o.Z : start.Z);
        }

        return new Point3(start.X + (x ?? 0), start.Y + (y ?? 0), start.Z + (z ?? 0));
    }

    /// <summary>G53: the words are machine coordinates (absolute whatever the distance mode).</summary>
    private static Point3 MachineTarget(Point3 start, double? x, double? y, double? z) => new(x ?? start.X, y ?? start.Y, z ?? start.Z);
}
