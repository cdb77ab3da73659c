using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// What the simulator executed, the record the tests and the CLI prove exactness with: every move and dwell finished,
/// in order, and (with <see cref="SimOptions.RecordRotaryLines"/>) every rotary line started. Moves wait here for
/// the <see cref="PmacSimulator.MoveExecuted"/> subscribers, who are called outside the simulator's lock. Guarded by
/// that lock.
/// </summary>
internal sealed class ExecutionLog
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSimulator>();

    private readonly List<ExecutedMove> _moves = [];
    private readonly List<ExecutedMove> _pending = [];
    private readonly List<ExecutedRotaryLine> _rotaryLines = [];
    private readonly bool _retain;
    private long _count;

    /// <summary>Creates the log; <paramref name="retain"/> keeps every move in memory (<see cref="SimOptions.RetainExecutedMoves"/>).</summary>
    public ExecutionLog(bool retain) => _retain = retain;

    /// <summary>Moves executed so far (counted whether or not they are kept).</summary>
    public long Count => _count;

    /// <summary>True when moves wait for the subscribers.</summary>
    public bool HasPending => _pending.Count > 0;

    /// <summary>A copy of every move kept, in order (none unless the log retains them).</summary>
    public ExecutedMove[] Moves() => _moves.ToArray();

    /// <summary>The moves from 0-based index <paramref name="fromIndex"/> on.</summary>
    public List<ExecutedMove> MovesFrom(int fromIndex)
    {
        var start = Math.Clamp(fromIndex, 0, _moves.Count);
        return _moves.GetRange(start, _moves.Count - start);
    }

    /// <summary>A copy of every rotary line started, in order.</summary>
    public ExecutedRotaryLine[] RotaryLines() => _rotaryLines.ToArray();

    /// <summary>Records a finished segment of coordinate system <paramref name="cs"/> at <paramref name="now"/>; <paramref name="notify"/> keeps it for the subscribers.</summary>
    public void Record(int cs, Segment seg, double now, bool notify)
    {
        var center = new double[3] { double.NaN, double.NaN, double.NaN };
        if (seg.IsArc)
        {
            var c = new double[CoordinateSystem.AxisCount];
            c[seg.A1] = seg.C1;
            c[seg.A2] = seg.C2;
            c[seg.An] = seg.Start[seg.An];
            center = [c[0], c[1], c[2]];
        }

        var move = new ExecutedMove(++_count, seg.SourceLine, seg.StartTime, now, seg.End[0], seg.End[1], seg.End[2], seg.Kind)
        {
            CoordinateSystem = cs,
            StartX = seg.Start[0],
            StartY = seg.Start[1],
            StartZ = seg.Start[2],
            CenterX = center[0],
            CenterY = center[1],
            CenterZ = center[2],
            Radius = seg.IsArc ? seg.Radius : 0,
            Length = seg.Length,
            Feed = seg.Feed,
            Rotary = (seg.End[3], seg.End[4], seg.End[5]),
            BlockStart = seg.BlockStart,
        };
        if (_retain)
        {
            _moves.Add(move);
        }

        if (notify)
        {
            _pending.Add(move);
        }
    }

    /// <summary>Records a rotary line coordinate system <paramref name="cs"/> starts calculating.</summary>
    public void RecordRotaryLine(int cs, string text, double now) =>
        _rotaryLines.Add(new ExecutedRotaryLine(_rotaryLines.Count + 1, cs, text, now));

    /// <summary>Takes the moves waiting for the subscribers (empty when none).</summary>
    public ExecutedMove[] TakePending()
    {
        if (_pending.Count == 0)
        {
            return [];
        }

        var events = _pending.ToArray();
        _pending.Clear();
        return events;
    }

    /// <summary>Calls every subscriber for every move, in order; a subscriber that throws is logged and does not stop the others.</summary>
    public static void Deliver(Action<ExecutedMove>? handler, ExecutedMove[] moves)
    {
        if (handler is null)
        {
            return;
        }

        foreach (var e in moves)
        {
            foreach (var subscriber in handler.GetInvocationList())
            {
                try
                {
                    ((Action<ExecutedMove>)subscriber)(e);
                }
                catch (Exception ex)
                {
                    // A subscriber's bug must not stop the clock or lose the other subscribers' events.
                    Log.Error(ex, "MoveExecuted subscriber failed for move {Sequence}", e.Sequence);
                }
            }
        }
    }
}
