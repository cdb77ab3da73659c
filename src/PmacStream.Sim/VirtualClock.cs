using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// The simulator's virtual time. At each instant the coordinate systems calculate ahead and start and finish their
/// zero-time segments until nothing changes; then time jumps to the next event (a move ends, the feed override slews
/// a step, a PLC scan is due), advancing the executing moves, never past the time asked for. Guarded by the
/// simulator's lock.
/// </summary>
/// <param name="coordinateSystems">The coordinate systems (index 0 unused).</param>
/// <param name="plcs">The PLC programs, scanned every <see cref="SimOptions.PlcScanIntervalMs"/> while any is enabled.</param>
/// <param name="log">Records every move that finishes.</param>
/// <param name="memory">The variables (I5 selects the PLCs scanned).</param>
/// <param name="options">Speed, scan period, statement budget.</param>
/// <param name="notifyMoves">True when finished moves are to be kept for the subscribers.</param>
/// <param name="plcError">A PLC stopped with a run-time error (its number, the ERR number).</param>
/// <param name="motors">The motors: their own moves (jog, homing), limit checks and injected faults are events too.</param>
internal sealed class VirtualClock(CoordinateSystem[] coordinateSystems, PlcTable plcs, ExecutionLog log, SimMemory memory, SimOptions options,
    Func<bool> notifyMoves, Action<int, int> plcError, MotorSet motors)
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSimulator>();

    private double _now;
    private double _nextPlcScan;

    /// <summary>Virtual seconds since power-on.</summary>
    public double Now => _now;

    /// <summary>Power-on: the PLC scan is due now.</summary>
    public void PowerOn() => _nextPlcScan = _now;

    /// <summary>
    /// Runs time to <paramref name="until"/> (or, with <paramref name="untilIdle"/>, until no motion can progress),
    /// at most <paramref name="maxIterations"/> events.
    /// </summary>
    public void Pump(double until, bool untilIdle, long maxIterations)
    {
        long iterations = 0;
        var stalled = 0;
        var interval = Math.Max(1e-6, options.PlcScanIntervalMs / 1000.0);
        while (true)
        {
            var before = _now;
            var movesBefore = log.Count;
            Settle();
            motors.FireDue(_now);
            if (_now >= until)
            {
                break;
            }

            var motionNext = NextMotionEvent();

            motionNext = Math.Min(motionNext, motors.NextMotionTime(_now));

            // Idle means no motion that can progress (none, or all held at 0 %).
            if (untilIdle && double.IsPositiveInfinity(motionNext))
            {
                break;
            }

            var next = Math.Min(until, motionNext);
            next = Math.Min(next, Math.Max(_now, motors.NextFaultTime()));

            var plcActive = plcs.AnyEnabled;
            if (plcActive)
            {
                next = Math.Min(next, Math.Max(_nextPlcScan, _now));
            }

            if (double.IsPositiveInfinity(next))
            {
                break; // held at 0 % with nothing else to do
            }

            if (next > _now)
            {
                for (var i = 1; i < coordinateSystems.Length; i++)
                {
                    if (coordinateSystems[i].IsMoving)
                    {
                        coordinateSystems[i].AdvanceTime(_now, next);
                    }
                }

                motors.Advance(_now, next);
                _now = next;
            }

            if (plcActive && _now >= _nextPlcScan)
            {
                ScanPlcs();
                _nextPlcScan = Math.Max(_nextPlcScan + interval, _now);
            }
            else if (!plcActive)
            {
                _nextPlcScan = _now;
            }

            if (++iterations >= maxIterations)
            {
                break;
            }

            // Guard against a clock that cannot move on (a bug must never hang a host or a test run).
            stalled = _now > before || log.Count > movesBefore ? 0 : stalled + 1;
            if (stalled > 10_000)
            {
                Log.Error("simulated clock stalled at {Time} s; giving up this advance", _now);
                break;
            }
        }
    }

    /// <summary>The earliest next event of any moving coordinate system; infinity when none is moving.</summary>
    private double NextMotionEvent()
    {
        var motionNext = double.PositiveInfinity;
        for (var i = 1; i < coordinateSystems.Length; i++)
        {
            var cs = coordinateSystems[i];
            if (cs.IsMoving)
            {
                motionNext = Math.Min(motionNext, cs.NextEventTime(_now));
            }
        }

        return motionNext;
    }

    /// <summary>At the current instant: calculate ahead, start and finish zero-time segments until nothing changes.</summary>
    private void Settle()
    {
        var guard = 0;
        bool changed;
        do
        {
            changed = false;
            for (var i = 1; i < coordinateSystems.Length; i++)
            {
                var cs = coordinateSystems[i];
                if (!cs.Running && !cs.IsMoving)
                {
                    continue;
                }

                cs.Calculate();
                var before = cs.Current;
                cs.TryStartNext(_now);
                if (cs.Current is not null && !ReferenceEquals(before, cs.Current))
                {
                    changed = true; // a move started: calculation may run one further ahead
                }

                if (cs.CompleteIfDone() is { } seg)
                {
                    log.Record(cs.Number, seg, _now, notify: notifyMoves());
                    changed = true;
                }

                cs.UpdateFullBit();
            }
        }
        while (changed && ++guard < 1_000_000);
    }

    private void ScanPlcs() =>
        plcs.Scan(coordinateSystems[1], (int)memory.GetI(5), options.MaxStatementsPerCalculation, plcError);

    /// <summary>
    /// One step of the background clock, <paramref name="realSeconds"/> after the last: realtime x
    /// factor, or for instant speed everything that can run now (then, with nothing to run, time follows real time).
    /// True while busy (instant speed with motion that can progress).
    /// </summary>
    public bool Step(double realSeconds)
    {
        var speed = options.Speed;
        if (!speed.IsInstant)
        {
            Pump(_now + (realSeconds * speed.Multiplier), untilIdle: false, maxIterations: long.MaxValue);
            return false;
        }

        Pump(double.PositiveInfinity, untilIdle: true, maxIterations: 20_000);
        var busy = AnyMotion() && !AllHeld();
        if (!busy && realSeconds > 0)
        {
            Pump(_now + realSeconds, untilIdle: false, maxIterations: long.MaxValue);
        }

        return busy;
    }

    private bool AllHeld()
    {
        if (motors.AnyMoving)
        {
            return false;
        }

        for (var i = 1; i < coordinateSystems.Length; i++)
        {
            if (coordinateSystems[i].IsMoving && !double.IsPositiveInfinity(coordinateSystems[i].NextEventTime(_now)))
            {
                return false;
            }
        }

        return true;
    }

    public bool AnyRunningOrMoving()
    {
        for (var i = 1; i < coordinateSystems.Length; i++)
        {
            if (coordinateSystems[i].Running || coordinateSystems[i].IsMoving)
            {
                return true;
            }
        }

        return motors.AnyMoving;
    }

    private bool AnyMotion()
    {
        for (var i = 1; i < coordinateSystems.Length; i++)
        {
            if (coordinateSystems[i].IsMoving)
            {
                return true;
            }
        }

        return motors.AnyMoving;
    }
}
