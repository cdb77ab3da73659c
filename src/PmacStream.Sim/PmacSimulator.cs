using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Parsing;
using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// A simulated Turbo PMAC: online commands, program/PLC/rotary buffers, lookahead calculation and a virtual clock
/// that executes moves. Every port (<see cref="OpenPort"/>) speaks the ASCII protocol with its own I3/I6 framing.
/// All state is guarded by one lock; ports may be called from any thread.
/// </summary>
/// <remarks>
/// This type is the engine: the coordinate systems (<see cref="CoordinateSystem"/>) calculating and executing on the
/// virtual clock, the PLC scan, power-on and the public view. Command lines go to <see cref="OnlineCommands"/>
/// (with <see cref="ProgramBuffers"/> for the buffer commands and <see cref="MotorMap"/> for motors) and replies are
/// framed by <see cref="ReplyFrame"/>; <see cref="ExecutionLog"/> keeps what ran, <see cref="SimClock"/> runs time
/// in the background.
/// </remarks>
public sealed class PmacSimulator : IDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSimulator>();

    private readonly object _sync = new();
    private readonly object _raiseLock = new();
    private readonly CoordinateSystem[] _cs = new CoordinateSystem[SimMemory.CoordinateSystems + 1];
    private readonly PlcTable _plcs = new();
    private readonly List<SimPort> _ports = [];
    private readonly ExecutionLog _log;
    private readonly MotorMap _motors;
    private readonly MotorSet _motorSet;
    private readonly ProgramBuffers _buffers;
    private readonly OnlineCommands _commands;
    private readonly SimClock _clock;
    private readonly List<string> _outputs = new(2); // a command line's values, reused under the lock
    private readonly VirtualClock _time;
    private long _underruns;
    private long _errors;
    private bool _disposed;

    /// <summary>Creates a simulator in its power-on state.</summary>
    public PmacSimulator(SimOptions? options = null)
    {
        Options = options ?? new SimOptions();
        _log = new ExecutionLog(Options.RetainExecutedMoves);
        for (var i = 1; i < _cs.Length; i++)
        {
            _cs[i] = new CoordinateSystem(this, i);
        }

        _motors = new MotorMap();
        _motorSet = new MotorSet(_cs, _motors, Memory, Options, () => _time!.Now);
        Memory.Register = _motorSet.Register;
        _buffers = new ProgramBuffers(_cs, _plcs, Options, Matrices);
        _commands = new OnlineCommands(this, _cs, _buffers, _plcs, _motors, _motorSet);
        _time = new VirtualClock(_cs, _plcs, _log, Memory, Options, () => MoveExecuted is not null, PlcError, _motorSet);
        _clock = new SimClock(_sync, _time.Step, RaiseEvents, _ => InternalFaults++);
        PowerOn(factory: true);
    }

    /// <summary>The axis transformation matrices (<c>DEFINE TBUF</c>) the coordinate systems select with <c>TSEL</c>.</summary>
    internal AxisMatrices Matrices { get; } = new();

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
                return _time.Now;
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
                return _log.Moves();
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
                return _log.RotaryLines();
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
            return _log.MovesFrom(fromIndex);
        }
    }

    /// <summary>A snapshot of the counters.</summary>
    public SimCounters Counters
    {
        get
        {
            lock (_sync)
            {
                return new SimCounters(_log.Count, _underruns, _errors, _buffers.LinesReceived);
            }
        }
    }

    /// <summary>True while the clock thread runs.</summary>
    public bool ClockRunning => _clock.Running;

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
            _time.Pump(_time.Now + virtualTime.TotalSeconds, untilIdle: false, maxIterations: long.MaxValue);
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
            var start = _time.Now;
            _time.Pump(start + (maxVirtualTime ?? TimeSpan.FromDays(1)).TotalSeconds, untilIdle: true, maxIterations: long.MaxValue);
            used = _time.Now - start;
        }

        RaiseEvents();
        return TimeSpan.FromSeconds(used);
    }

    /// <summary>Runs one scan of every enabled PLC program now (deterministic PLC tests).</summary>
    public void RunPlcScan()
    {
        lock (_sync)
        {
            _plcs.Scan(_cs[1], (int)Memory.GetI(5), Options.MaxStatementsPerCalculation, PlcError);
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
            _clock.Start();
        }
    }

    /// <summary>Stops the background clock (waits for its thread).</summary>
    public void StopClock() => _clock.Stop();

    /// <summary>
    /// Writes the executed-move log as CSV: <c>sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block</c> (the moves kept in memory;
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

    /// <summary>
    /// Schedules <paramref name="fault"/> at its time on the program clock (seconds after a motion program first
    /// starts running; at once when that time has passed), as <c>pmacstream sim --inject</c> does.
    /// </summary>
    public void InjectFault(FaultInjection fault)
    {
        ArgumentNullException.ThrowIfNull(fault);
        lock (_sync)
        {
            _motorSet.Schedule(fault);
        }
    }

    /// <summary>Injects <paramref name="kind"/> into motor <paramref name="motor"/> now.</summary>
    public void InjectFault(FaultKind kind, int motor)
    {
        ArgumentOutOfRangeException.ThrowIfLessThan(motor, 1);
        ArgumentOutOfRangeException.ThrowIfGreaterThan(motor, MotorMap.Count);
        lock (_sync)
        {
            _motorSet.Fire(kind, motor);
        }
    }

    /// <summary>Virtual seconds since a motion program first started running (the fault-injection clock); null before.</summary>
    public double? ProgramClock
    {
        get
        {
            lock (_sync)
            {
                return _motorSet.ProgramEpoch is { } epoch ? _time.Now - epoch : null;
            }
        }
    }

    /// <summary>A snapshot of motor <paramref name="motor"/> (1..32): what <c>P</c>, <c>V</c>, <c>F</c> and <c>?</c> report, in counts.</summary>
    public MotorSnapshot Motor(int motor)
    {
        ArgumentOutOfRangeException.ThrowIfLessThan(motor, 1);
        ArgumentOutOfRangeException.ThrowIfGreaterThan(motor, MotorMap.Count);
        lock (_sync)
        {
            var m = _motorSet.Get(motor);
            return new MotorSnapshot(
                _motorSet.ActualPosition(motor),
                m.Commanded,
                m.Machine,
                m.Velocity,
                _motorSet.FollowingError(motor),
                m.HomeComplete,
                m.Enabled,
                m.Moving,
                _motorSet.InPosition(motor),
                m.StoppedOnLimit,
                _motorSet.PlusLimitInput(motor),
                _motorSet.MinusLimitInput(motor),
                m.AmpFault,
                m.FatalFollowingError);
        }
    }

    /// <inheritdoc />
    public void Dispose()
    {
        if (_disposed)
        {
            return;
        }

        _clock.Dispose();
        _disposed = true;
    }

    internal ProgramBuffer? FindProgram(int number) => _buffers.FindProgram(number);

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
            _log.RecordRotaryLine(cs.Number, text, _time.Now);
        }
    }

    /// <summary>Logs a move an abort found at its end (called under the lock): it ended, as a finished move does.</summary>
    internal void RecordAbortedAtEnd(CoordinateSystem cs, Segment seg)
    {
        _log.Record(cs.Number, seg, _time.Now, notify: MoveExecuted is not null);
        Log.Debug("C.S.{Cs} aborted at the end of the move of line {Line}: logged as executed", cs.Number, seg.SourceLine);
    }

    /// <summary>
    /// How close (axis units) an axis of <paramref name="coordinateSystem"/> must be to a move's end for an abort to
    /// find the move ended: <see cref="SimOptions.AbortAtEndCounts"/> of the axis's motor plus
    /// <see cref="SimOptions.AbortAtEndUnits"/> (called under the lock).
    /// </summary>
    internal double EndTolerance(int coordinateSystem, int axis)
    {
        var scale = 1.0;
        for (var m = 1; m <= MotorMap.Count; m++)
        {
            var (cs, a, s) = _motors.Definition(m);
            if (cs == coordinateSystem && a == axis && s != 0)
            {
                scale = Math.Abs(s);
                break;
            }
        }

        return (Options.AbortAtEndCounts / scale) + Options.AbortAtEndUnits;
    }

    internal void CountUnderrun(CoordinateSystem cs)
    {
        _underruns++;
        Log.Debug("C.S.{Cs} rotary underrun at {Time:0.000} s (lines ahead 0)", cs.Number, _time.Now);
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
            if (_buffers.IsOpenOn(port))
            {
                _buffers.Close();
            }

            _ports.Remove(port);
        }
    }

    /// <summary>Runs one command line from <paramref name="port"/> and returns the framed reply.</summary>
    internal byte[] ExecuteLine(SimPort port, string line)
    {
        int error = 0;
        byte[] reply;
        bool wake, events;
        lock (_sync)
        {
            var outputs = _outputs;
            outputs.Clear();
            try
            {
                _commands.Execute(port, line, outputs);
            }
            catch (SimSyntaxException e)
            {
                error = e.Error;
                _errors++;
            }
            catch (Exception e) when (e is not OutOfMemoryException)
            {
                // A simulator bug must not take a server down: answer ERR003 and remember it for the tests.
                error = 3;
                _errors++;
                InternalFaults++;
                Log.Error(e, "simulator fault on {Port} for '{Line}'", port.Name, line);
            }

            // Let the controller react at this instant (calculation after R, zero-time moves).
            _time.Pump(_time.Now, untilIdle: false, maxIterations: 1);
            reply = ReplyFrame.Build(outputs, error, port.I3, port.I6);
            outputs.Clear();

            // Waking the clock thread costs a futex call and lock contention per line. It only matters while a
            // coordinate system has motion to run or a PLC scans; otherwise the clock's own 1 ms tick does the same.
            wake = _time.AnyRunningOrMoving() || _plcs.AnyEnabled;
            events = _log.HasPending;
        }

        if (wake)
        {
            _clock.Wake();
        }

        if (events)
        {
            RaiseEvents();
        }

        return reply;
    }

    /// <summary>Answers a control character from <paramref name="port"/> (raw bytes, no terminator); one not known is a BEL.</summary>
    internal byte[] ExecuteControl(SimPort port, char control)
    {
        string? text;
        lock (_sync)
        {
            text = _commands.Control(control);
            if (text is null)
            {
                _errors++;
                return [ReplyParser.Bel];
            }
        }

        return Encoding.ASCII.GetBytes(text);
    }

    /// <summary><c>$$$</c> (values cleared, programs kept) or <c>$$$***</c> (everything cleared).</summary>
    internal void Reset(bool factory)
    {
        PowerOn(factory);
        Log.Information("simulated PMAC reset ({Kind})", factory ? "factory" : "$$$");
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

        _buffers.Close();
        if (factory)
        {
            Memory.ClearAll();
            _buffers.ClearPrograms();
            _plcs.Clear();
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
        _motors.PowerOn();
        _motorSet.PowerOn();

        foreach (var port in _ports)
        {
            port.ResetFraming(Options.I3, Options.I6);
        }

        if (Options.DefaultRotWords > 0)
        {
            _cs[1].Rotary = new ProgramBuffer(BufferKind.Rotary, 0, Options.DefaultRotWords);
        }

        _plcs.PowerOn();

        _time.PowerOn();
    }

    private void PlcError(int plc, int error)
    {
        _errors++;
        Log.Warning("PLC {Plc} disabled by run-time error ERR{Error:000}", plc, error);
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
                events = _log.TakePending();
            }

            if (events.Length > 0)
            {
                ExecutionLog.Deliver(MoveExecuted, events);
            }
        }
    }

}
