namespace PmacStream.Sim;

/// <summary>
/// A coordinate system's segments on the virtual clock: those calculated ahead (the lookahead queue) and the one
/// executing, the feed override with its slew, and the dwell calculation waits for. Time advances the executing
/// segment at the current override (a hold slews it to 0). Guarded by the simulator's lock.
/// </summary>
/// <param name="options">The override slew rate.</param>
internal sealed class MotionQueue(SimOptions options)
{
    private const double Epsilon = 1e-9;

    private readonly Queue<Segment> _queue = new();

    /// <summary>The segment executing, or null.</summary>
    public Segment? Current { get; private set; }

    /// <summary>A <c>DWELL</c> queued or executing: calculation waits until it has executed.</summary>
    public Segment? BlockedBy { get; private set; }

    /// <summary>Segments calculated and waiting.</summary>
    public int Count => _queue.Count;

    /// <summary>True while a segment executes or waits (a field: the clock asks every coordinate system at every event).</summary>
    public bool IsMoving { get; private set; }

    /// <summary>The override set (<c>%n</c>), percent.</summary>
    public double OverrideTarget { get; set; } = 100;

    /// <summary>The override now, slewing towards the target (or towards 0 while held), percent.</summary>
    public double OverrideCurrent { get; private set; } = 100;

    /// <summary>Queues a calculated segment.</summary>
    public void Enqueue(Segment seg)
    {
        seg.Remaining = seg.Duration;
        _queue.Enqueue(seg);
        IsMoving = true;
        if (seg.BlocksCalculation)
        {
            BlockedBy = seg;
        }
    }

    /// <summary>Starts the next queued segment at <paramref name="now"/> (there must be one and none executing); returns it.</summary>
    public Segment StartNext(double now)
    {
        var seg = _queue.Dequeue();
        seg.StartTime = now;
        Current = seg;
        return seg;
    }

    /// <summary>Stops at once: queued and executing segments dropped, the override at its target.</summary>
    public void Stop()
    {
        Current = null;
        _queue.Clear();
        IsMoving = false;
        BlockedBy = null;
        OverrideCurrent = OverrideTarget;
    }

    /// <summary>Axis positions now: within the executing segment, else where the next one starts, else <paramref name="idle"/>.</summary>
    public void Position(double[] into, double[] idle)
    {
        if (Current is { } cur)
        {
            var fraction = cur.Duration <= 0 ? 1 : 1 - Math.Clamp(cur.Remaining / cur.Duration, 0, 1);
            cur.PositionAt(fraction, into);
        }
        else if (_queue.Count > 0)
        {
            Array.Copy(_queue.Peek().Start, into, CoordinateSystem.AxisCount);
        }
        else if (!ReferenceEquals(into, idle))
        {
            Array.Copy(idle, into, CoordinateSystem.AxisCount);
        }
    }

    /// <summary>The next time this queue needs attention (a segment ends or starts, or the override slews a step); infinity when nothing can progress.</summary>
    public double NextEventTime(double now, bool holding)
    {
        var cur = Current;
        if (cur is null)
        {
            return _queue.Count > 0 ? now : double.PositiveInfinity;
        }

        var target = holding ? 0 : OverrideTarget;
        if (Math.Abs(OverrideCurrent - target) > 1e-9)
        {
            var rate = Math.Max(1e-6, options.OverrideSlewPercentPerSecond);
            var step = Math.Max(1e-6, Math.Min(0.001, Math.Abs(target - OverrideCurrent) / rate));
            return now + step; // at least 1 us so that time always moves on while slewing
        }

        if (cur.Remaining <= Epsilon)
        {
            return now;
        }

        if (OverrideCurrent <= 0)
        {
            return double.PositiveInfinity;
        }

        var end = now + (cur.Remaining / (OverrideCurrent / 100.0));
        if (end <= now)
        {
            cur.Remaining = 0; // below the clock's resolution at this time
            return now;
        }

        return end;
    }

    /// <summary>Advances the executing segment and the override slew over [t0, t1].</summary>
    public void AdvanceTime(double t0, double t1, bool holding)
    {
        var dt = t1 - t0;
        if (dt <= 0)
        {
            return;
        }

        var target = holding ? 0 : OverrideTarget;
        var start = OverrideCurrent;
        var end = start;
        if (Math.Abs(start - target) > 1e-9)
        {
            var step = Math.Max(1e-6, options.OverrideSlewPercentPerSecond) * dt;
            end = start < target ? Math.Min(target, start + step) : Math.Max(target, start - step);
        }

        OverrideCurrent = end;
        if (Current is { } cur)
        {
            cur.Remaining -= dt * (start + end) / 200.0;
        }
    }

    /// <summary>Finishes the executing segment if it is done; returns it.</summary>
    public Segment? CompleteIfDone()
    {
        var cur = Current;
        if (cur is null || cur.Remaining > Epsilon)
        {
            return null;
        }

        Current = null;
        IsMoving = _queue.Count > 0;
        if (ReferenceEquals(cur, BlockedBy))
        {
            BlockedBy = null;
        }

        return cur;
    }
}
