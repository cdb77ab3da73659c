using System.Diagnostics;
using System.Globalization;
using System.Text;
using PmacStream.Sim.Parsing;
using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// A simulated Turbo PMAC: online commands, program/PLC/rotary buffers, lookahead calculation and a virtual clock
/// that executes moves. Every port (<see cref="OpenPort"/>) speaks the ASCII protocol with its own I3/I6 framing.
/// All state is guarded by one lock; ports may be called from any thread.
/// </summary>
public sealed partial class PmacSimulator : IDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSimulator>();

    private readonly object _sync = new();
    private readonly object _raiseLock = new();
    private readonly CoordinateSystem[] _cs = new CoordinateSystem[SimMemory.CoordinateSystems + 1];
    private readonly Dictionary<int, ProgramBuffer> _programs = [];
    private readonly PlcProgram?[] _plcs = new PlcProgram?[32];
    private readonly List<SimPort> _ports = [];
    private readonly List<ExecutedMove> _executed = [];
    private readonly List<ExecutedMove> _pendingEvents = [];
    private readonly List<ExecutedRotaryLine> _rotaryLines = [];
    private readonly (int Cs, int Axis, double Scale)[] _motors = new (int, int, double)[33];
    private readonly double[] _scratch = new double[CoordinateSystem.AxisCount];
    private readonly AutoResetEvent _wake = new(false);

    // Per-line scratch for ExecuteLine, reused under _sync so that storing a line allocates only what is kept.
    private readonly List<string> _outputs = new(2);
    private readonly List<Token> _tokens = new(32);
    private readonly List<Stmt> _stmts = new(8);
    private readonly ExprParser _parser = new([]);
    private bool _lineBusy;
    private SimPort? _openOwner;
    private BufferKind _openKind;
    private ProgramBuffer? _openBuffer;
    private double _now;
    private double _nextPlcScan;
    private long _underruns;
    private long _errors;
    private long _linesReceived;
    private long _movesExecuted;
    private Thread? _clock;
    private volatile bool _clockStop;
    private bool _disposed;

    /// <summary>Creates a simulator in its power-on state.</summary>
    public PmacSimulator(SimOptions? options = null)
    {
        Options = options ?? new SimOptions();
        for (var i = 1; i < _cs.Length; i++)
        {
            _cs[i] = new CoordinateSystem(this, i);
        }

        PowerOn(factory: true);
    }

    /// <summary>The options this simulator was created with.</summary>
    public SimOptions Options { get; }

    /// <summary>
    /// Raised (outside the lock, on the thread that advanced the clock) for every finished move or dwell, in execution
    /// order, one delivery at a time.
    /// </summary>
    public event Action<ExecutedMove>? MoveExecuted;

    /// <summary>Virtual time in seconds since power-on.</summary>
    public double Now
    {
        get
        {
            lock (_sync)
            {
                return _now;
            }
        }
    }

    /// <summary>A snapshot of every move executed so far, in order (empty unless <see cref="SimOptions.RetainExecutedMoves"/>).</summary>
    public IReadOnlyList<ExecutedMove> ExecutedMoves
    {
        get
        {
            lock (_sync)
            {
                return _executed.ToArray();
            }
        }
    }

    /// <summary>
    /// A snapshot of every rotary-buffer line started (motion and non-motion), in order; empty unless
    /// <see cref="SimOptions.RecordRotaryLines"/> is set.
    /// </summary>
    public IReadOnlyList<ExecutedRotaryLine> ExecutedRotaryLines
    {
        get
        {
            lock (_sync)
            {
                return _rotaryLines.ToArray();
            }
        }
    }

    /// <summary>
    /// The executed moves from 0-based index <paramref name="fromIndex"/> on (Sequence = index + 1): for pollers that
    /// should not copy the whole log each time. Empty unless <see cref="SimOptions.RetainExecutedMoves"/>.
    /// </summary>
    public IReadOnlyList<ExecutedMove> ExecutedMovesFrom(int fromIndex)
    {
        lock (_sync)
        {
            var start = Math.Clamp(fromIndex, 0, _executed.Count);
            return _executed.GetRange(start, _executed.Count - start);
        }
    }

    /// <summary>A snapshot of the counters.</summary>
    public SimCounters Counters
    {
        get
        {
            lock (_sync)
            {
                return new SimCounters(_movesExecuted, _underruns, _errors, _linesReceived);
            }
        }
    }

    /// <summary>True while the clock thread runs.</summary>
    public bool ClockRunning => _clock is not null;

    internal SimMemory Memory { get; } = new();

    /// <summary>Unexpected exceptions caught while executing commands (a simulator bug; tests assert 0).</summary>
    internal long InternalFaults { get; private set; }

    /// <summary>Opens a new port (a serial line, a TCP connection, an in-process client).</summary>
    public SimPort OpenPort(string name)
    {
        lock (_sync)
        {
            var port = new SimPort(this, name, Options.I3, Options.I6);
            _ports.Add(port);
            return port;
        }
    }

    /// <summary>Runs the virtual clock forward by exactly <paramref name="virtualTime"/>, executing moves and PLC scans.</summary>
    public void Advance(TimeSpan virtualTime)
    {
        if (virtualTime < TimeSpan.Zero)
        {
            throw new ArgumentOutOfRangeException(nameof(virtualTime));
        }

        lock (_sync)
        {
            Pump(_now + virtualTime.TotalSeconds, untilIdle: false, maxIterations: long.MaxValue);
        }

        RaiseEvents();
    }

    /// <summary>
    /// Runs the virtual clock until no coordinate system has motion left (programs ended, or waiting for rotary
    /// lines, or stopped), or until <paramref name="maxVirtualTime"/> has passed. Returns the virtual time used.
    /// </summary>
    public TimeSpan RunUntilIdle(TimeSpan? maxVirtualTime = null)
    {
        double used;
        lock (_sync)
        {
            var start = _now;
            Pump(start + (maxVirtualTime ?? TimeSpan.FromDays(1)).TotalSeconds, untilIdle: true, maxIterations: long.MaxValue);
            used = _now - start;
        }

        RaiseEvents();
        return TimeSpan.FromSeconds(used);
    }

    /// <summary>Runs one scan of every enabled PLC program now (deterministic PLC tests).</summary>
    public void RunPlcScan()
    {
        lock (_sync)
        {
            ScanPlcs();
        }
    }

    /// <summary>
    /// Starts a background thread that advances virtual time at <see cref="SimOptions.Speed"/>: realtime × factor,
    /// or for instant as fast as lines arrive (virtual time then follows real time only while nothing moves).
    /// </summary>
    public void StartClock()
    {
        lock (_sync)
        {
            ObjectDisposedException.ThrowIf(_disposed, this);
            if (_clock is not null)
            {
                return;
            }

            _clockStop = false;
            _clock = new Thread(ClockLoop) { IsBackground = true, Name = "pmac-sim-clock" };
            _clock.Start();
        }
    }

    /// <summary>Stops the background clock (waits for its thread).</summary>
    public void StopClock()
    {
        Thread? t;
        lock (_sync)
        {
            t = _clock;
            _clock = null;
            _clockStop = true;
        }

        _wake.Set();
        t?.Join();
    }

    /// <summary>
    /// Writes the executed-move log as CSV: <c>sequence,line,start_s,end_s,x,y,z,kind</c> (the moves kept in memory;
    /// a host that does not keep them streams the log with <see cref="ExecutedLogWriter.Attach"/>).
    /// </summary>
    public void WriteExecutedLog(string path) => ExecutedLogWriter.WriteAll(path, ExecutedMoves);

    /// <summary>Sets a simulated X: or Y: memory word (24 bits), e.g. an input card word that M-variables point into.</summary>
    public void SetWord(char space, int address, int value)
    {
        lock (_sync)
        {
            Memory.SetWord(NormalizeSpace(space), address, value);
        }
    }

    /// <summary>Reads a simulated X: or Y: memory word (24 bits), e.g. an output card word written by a PLC.</summary>
    public int GetWord(char space, int address)
    {
        lock (_sync)
        {
            return (int)Memory.GetWord(NormalizeSpace(space), address);
        }
    }

    /// <summary>Sets the Y: word at <paramref name="address"/> (where Turbo PMAC I/O cards live, e.g. $078800).</summary>
    public void SetInputWord(int address, int value) => SetWord('Y', address, value);

    /// <summary>Sets or clears one bit of a simulated memory word.</summary>
    public void SetBit(char space, int address, int bit, bool value)
    {
        lock (_sync)
        {
            var s = NormalizeSpace(space);
            var word = Memory.GetWord(s, address);
            Memory.SetWord(s, address, value ? word | (1L << bit) : word & ~(1L << bit));
        }
    }

    /// <summary>Reads one bit of a simulated memory word.</summary>
    public bool GetBit(char space, int address, int bit) => ((GetWord(space, address) >> bit) & 1) != 0;

    /// <summary>Reads a variable: <paramref name="kind"/> I, P, Q (of <paramref name="coordinateSystem"/>) or M.</summary>
    public double ReadVariable(char kind, int index, int coordinateSystem = 1)
    {
        lock (_sync)
        {
            return char.ToUpperInvariant(kind) == 'Q' ? Memory.GetQ(coordinateSystem, index) : GetVariable(char.ToUpperInvariant(kind), index);
        }
    }

    /// <summary>Writes a variable (as an online assignment would).</summary>
    public void WriteVariable(char kind, int index, double value, int coordinateSystem = 1)
    {
        lock (_sync)
        {
            if (char.ToUpperInvariant(kind) == 'Q')
            {
                Memory.SetQ(coordinateSystem, index, value);
            }
            else
            {
                SetVariable(char.ToUpperInvariant(kind), index, value);
            }
        }
    }

    /// <summary>Whether coordinate system <paramref name="coordinateSystem"/> is running a program.</summary>
    public bool IsRunning(int coordinateSystem = 1)
    {
        lock (_sync)
        {
            return _cs[coordinateSystem].Running;
        }
    }

    /// <summary>Rotary lines ahead of calculation in coordinate system <paramref name="coordinateSystem"/> (as <c>PR</c>).</summary>
    public int RotaryLinesAhead(int coordinateSystem = 1)
    {
        lock (_sync)
        {
            return _cs[coordinateSystem].RotaryLinesAhead();
        }
    }

    /// <summary>Axis positions (X Y Z A B C U V W) of a coordinate system now, interpolated within the executing move.</summary>
    public double[] Position(int coordinateSystem = 1)
    {
        lock (_sync)
        {
            var p = new double[CoordinateSystem.AxisCount];
            _cs[coordinateSystem].ActualPosition(p);
            return p;
        }
    }

    /// <inheritdoc />
    public void Dispose()
    {
        if (_disposed)
        {
            return;
        }

        StopClock();
        _disposed = true;
        lock (_sync)
        {
            _wake.Dispose();
        }
    }

    internal ProgramBuffer? FindProgram(int number) => _programs.GetValueOrDefault(number);

    internal double GetVariable(char kind, int index) => kind switch
    {
        'I' => Memory.GetI(index),
        'P' => Memory.GetP(index),
        'M' => Memory.GetM(index),
        'Q' => Memory.GetQ(1, index),
        _ => 0,
    };

    internal void SetVariable(char kind, int index, double value)
    {
        switch (kind)
        {
            case 'I':
                Memory.SetI(index, value);
                break;
            case 'P':
                Memory.SetP(index, value);
                break;
            case 'M':
                Memory.SetM(index, value);
                break;
            case 'Q':
                Memory.SetQ(1, index, value);
                break;
        }
    }

    /// <summary>Logs a rotary line a coordinate system starts calculating (called under the lock).</summary>
    internal void RecordRotaryLine(CoordinateSystem cs, string text)
    {
        if (Options.RecordRotaryLines)
        {
            _rotaryLines.Add(new ExecutedRotaryLine(_rotaryLines.Count + 1, cs.Number, text, _now));
        }
    }

    internal void CountUnderrun(CoordinateSystem cs)
    {
        _underruns++;
        Log.Debug("C.S.{Cs} rotary underrun at {Time:0.000} s (lines ahead 0)", cs.Number, _now);
    }

    internal void RuntimeError(CoordinateSystem cs, int error)
    {
        _errors++;
        Log.Warning("C.S.{Cs} program stopped with run-time error ERR{Error:000}", cs.Number, error);
    }

    internal void PortClosed(SimPort port)
    {
        lock (_sync)
        {
            if (_openOwner == port)
            {
                CloseBuffer();
            }

            _ports.Remove(port);
        }
    }

    internal void Wake()
    {
        if (_disposed || _clock is null)
        {
            return; // nobody waits; after Dispose the event is gone
        }

        try
        {
            _wake.Set();
        }
        catch (ObjectDisposedException)
        {
            // disposed concurrently: nothing to wake
        }
    }

    private static char NormalizeSpace(char space)
    {
        var s = char.ToUpperInvariant(space);
        return s is 'X' or 'Y' ? s : throw new ArgumentOutOfRangeException(nameof(space), "memory space must be X or Y");
    }

    private void PowerOn(bool factory)
    {
        foreach (var cs in _cs.Skip(1))
        {
            cs.Abort();
            cs.DropRotary();
            cs.Begin(-1);
            cs.ResetModal();
            cs.OverrideTarget = 100;
        }

        CloseBuffer();
        if (factory)
        {
            Memory.ClearAll();
            _programs.Clear();
            Array.Clear(_plcs);
        }
        else
        {
            Memory.ClearValues();
        }

        Memory.SetI(3, Options.I3);
        Memory.SetI(5, Options.I5);
        Memory.SetI(6, Options.I6);
        Memory.SetI(16, Options.I16);
        Memory.SetI(17, Options.I17);
        Memory.SetI(10, 3713991);
        for (var m = 1; m < _motors.Length; m++)
        {
            _motors[m] = (1, m <= CoordinateSystem.AxisCount ? m - 1 : -1, 1.0);
        }

        foreach (var port in _ports)
        {
            port.ResetFraming(Options.I3, Options.I6);
        }

        if (Options.DefaultRotWords > 0)
        {
            _cs[1].Rotary = new ProgramBuffer(BufferKind.Rotary, 0, Options.DefaultRotWords);
        }

        // At power-on every PLC program in memory runs (subject to I5).
        foreach (var plc in _plcs)
        {
            if (plc is not null)
            {
                plc.Enabled = true;
                plc.Restart();
            }
        }

        _nextPlcScan = _now;
    }

    private void Pump(double until, bool untilIdle, long maxIterations)
    {
        long iterations = 0;
        var stalled = 0;
        var interval = Math.Max(1e-6, Options.PlcScanIntervalMs / 1000.0);
        while (true)
        {
            var before = _now;
            var movesBefore = _movesExecuted;
            Settle();
            if (_now >= until)
            {
                break;
            }

            var motionNext = double.PositiveInfinity;
            for (var i = 1; i < _cs.Length; i++)
            {
                var cs = _cs[i];
                if (cs.IsMoving)
                {
                    motionNext = Math.Min(motionNext, cs.NextEventTime(_now));
                }
            }

            // Idle means no motion that can progress (none, or all held at 0 %).
            if (untilIdle && double.IsPositiveInfinity(motionNext))
            {
                break;
            }

            var next = Math.Min(until, motionNext);

            var plcActive = AnyPlcEnabled();
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
                for (var i = 1; i < _cs.Length; i++)
                {
                    if (_cs[i].IsMoving)
                    {
                        _cs[i].AdvanceTime(_now, next);
                    }
                }

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
            stalled = _now > before || _movesExecuted > movesBefore ? 0 : stalled + 1;
            if (stalled > 10_000)
            {
                Log.Error("simulated clock stalled at {Time} s; giving up this advance", _now);
                break;
            }
        }
    }

    /// <summary>At the current instant: calculate ahead, start and finish zero-time segments until nothing changes.</summary>
    private void Settle()
    {
        var guard = 0;
        bool changed;
        do
        {
            changed = false;
            for (var i = 1; i < _cs.Length; i++)
            {
                var cs = _cs[i];
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

                if (cs.CompleteIfDone(_now) is { } seg)
                {
                    Record(cs, seg);
                    changed = true;
                }

                cs.UpdateFullBit();
            }
        }
        while (changed && ++guard < 1_000_000);
    }

    private void Record(CoordinateSystem cs, Segment seg)
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

        var move = new ExecutedMove(++_movesExecuted, seg.SourceLine, seg.StartTime, _now, seg.End[0], seg.End[1], seg.End[2], seg.Kind)
        {
            CoordinateSystem = cs.Number,
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
        };
        if (Options.RetainExecutedMoves)
        {
            _executed.Add(move);
        }

        if (MoveExecuted is not null)
        {
            _pendingEvents.Add(move);
        }
    }

    private void RaiseEvents()
    {
        // One thread delivers at a time, taking what is pending under the same lock: the clock thread and a command's
        // thread both raise events, and without this a log or a check saw moves out of their execution order.
        // Lock order is always _raiseLock then _sync (nothing holds _sync while it raises).
        lock (_raiseLock)
        {
            ExecutedMove[] events;
            lock (_sync)
            {
                if (_pendingEvents.Count == 0)
                {
                    return;
                }

                events = _pendingEvents.ToArray();
                _pendingEvents.Clear();
            }

            var handler = MoveExecuted;
            if (handler is null)
            {
                return;
            }

            foreach (var e in events)
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

    private bool AnyPlcEnabled()
    {
        foreach (var p in _plcs)
        {
            if (p is { Enabled: true })
            {
                return true;
            }
        }

        return false;
    }

    private void ScanPlcs()
    {
        var i5 = (int)Memory.GetI(5);
        for (var n = 0; n < _plcs.Length; n++)
        {
            var plc = _plcs[n];
            if (plc is not { Enabled: true } || (n == 0 ? (i5 & 1) == 0 : (i5 & 2) == 0))
            {
                continue;
            }

            var error = plc.Scan(_cs[1], Options.MaxStatementsPerCalculation);
            if (error != 0)
            {
                _errors++;
                Log.Warning("PLC {Plc} disabled by run-time error ERR{Error:000}", n, error);
            }
        }
    }

    private void ClockLoop()
    {
        // An exception on this thread would take the whole host process down (a server, a test run), so a fault
        // is logged and counted like a command fault, and the clock goes on.
        while (!_clockStop)
        {
            try
            {
                RunClock();
            }
            catch (Exception e)
            {
                lock (_sync)
                {
                    InternalFaults++;
                }

                Log.Error(e, "simulator clock fault");
                Thread.Sleep(1);
            }
        }
    }

    private void RunClock()
    {
        var sw = Stopwatch.StartNew();
        var last = sw.Elapsed.TotalSeconds;
        while (!_clockStop)
        {
            var speed = Options.Speed;
            var nowReal = sw.Elapsed.TotalSeconds;
            var realDt = Math.Min(nowReal - last, 0.25); // a stalled thread does not make time jump
            last = nowReal;
            bool busy;
            lock (_sync)
            {
                if (_clockStop)
                {
                    break;
                }

                if (speed.IsInstant)
                {
                    Pump(double.PositiveInfinity, untilIdle: true, maxIterations: 20_000);
                    busy = AnyMotion() && !AllHeld();
                    if (!busy && realDt > 0)
                    {
                        Pump(_now + realDt, untilIdle: false, maxIterations: long.MaxValue);
                    }
                }
                else
                {
                    Pump(_now + (realDt * speed.Multiplier), untilIdle: false, maxIterations: long.MaxValue);
                    busy = false;
                }
            }

            RaiseEvents();
            if (!busy)
            {
                _wake.WaitOne(1);
            }
        }
    }

    private bool AllHeld()
    {
        for (var i = 1; i < _cs.Length; i++)
        {
            if (_cs[i].IsMoving && !double.IsPositiveInfinity(_cs[i].NextEventTime(_now)))
            {
                return false;
            }
        }

        return true;
    }

    private bool AnyRunningOrMoving()
    {
        for (var i = 1; i < _cs.Length; i++)
        {
            if (_cs[i].Running || _cs[i].IsMoving)
            {
                return true;
            }
        }

        return false;
    }

    private bool AnyMotion()
    {
        for (var i = 1; i < _cs.Length; i++)
        {
            if (_cs[i].IsMoving)
            {
                return true;
            }
        }

        return false;
    }
}
