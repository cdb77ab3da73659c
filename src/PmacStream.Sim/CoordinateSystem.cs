using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// One coordinate system: its program pointer and call stack, run control (<c>B R S H Q A</c>), the calculation
/// (lookahead) of program lines into segments, with the synchronous assignments they carry, and the rotary buffer's
/// status. The modal state and the segments' geometry are <see cref="MoveCalculator"/>'s, their execution on the
/// virtual clock <see cref="MotionQueue"/>'s. Guarded by the simulator's lock.
/// </summary>
internal sealed class CoordinateSystem : IVariableAccess
{
    /// <summary>Axes X Y Z A B C U V W.</summary>
    public const int AxisCount = 9;

    private readonly PmacSimulator _sim;
    private readonly CallStack _calls = new();
    private readonly UnderrunWatch _underruns = new();

    // Whether the next blended move continues a blended sequence (the last segment done was a LINEAR or CIRCLE move
    // and the next one followed it at once) or starts from rest and so pays its acceleration (Turbo timing, issue 28).
    private bool _inBlendedSequence;
    private readonly MoveCalculator _moves;
    private readonly MotionQueue _motion;
    private readonly List<(int Index, double Value)> _pendingSync = [];
    private ProgramBuffer? _loggedBuffer;
    private long _loggedLine = -1;
    private bool _cursorReset;
    private Cursor _pc;
    private bool _pcValid;
    private bool _programEnded;
    private int _stepSegments;

    public CoordinateSystem(PmacSimulator sim, int number)
    {
        _sim = sim;
        Number = number;
        _moves = new MoveCalculator(sim.Options, sim.Matrices);
        _motion = new MotionQueue(sim.Options);
        ResetModal();
    }

    public int Number { get; }

    public ProgramBuffer? Rotary { get; set; }

    /// <summary>Program the C.S. points at (<c>B</c>): 0 = rotary buffer, -1 = none.</summary>
    public int ProgramNumber { get; private set; } = -1;

    public bool Running { get; private set; }

    public bool Holding { get; private set; }

    public bool Quitting { get; private set; }

    public bool Stepping { get; private set; }

    public Segment? Current => _motion.Current;

    public double OverrideTarget
    {
        get => _motion.OverrideTarget;
        set => _motion.OverrideTarget = value;
    }

    public double OverrideCurrent => _motion.OverrideCurrent;

    public MotionMode Mode => _moves.Mode;

    public bool TimeMode => _moves.TimeMode;

    public bool RotaryFullBit { get; private set; }

    public int QueuedSegments => _motion.Count;

    public bool IsMoving => _motion.IsMoving;

    /// <summary>True while a program runs whose calculation is inside <paramref name="buffer"/> or returns into it.</summary>
    public bool IsExecuting(ProgramBuffer buffer) =>
        Running && _pcValid && (_pc.Buffer == buffer || _calls.Contains(buffer));

    public double Get(char kind, int index) => kind == 'Q' ? _sim.Memory.GetQ(Number, index) : _sim.GetVariable(kind, index);

    public void Set(char kind, int index, double value)
    {
        if (kind == 'Q')
        {
            _sim.Memory.SetQ(Number, index, value);
        }
        else
        {
            _sim.SetVariable(kind, index, value);
        }
    }

    /// <summary>The power-on modes (<see cref="MoveCalculator.Reset"/>).</summary>
    public void ResetModal() => _moves.Reset();

    /// <summary>Lines in the rotary buffer ahead of the line being calculated (<c>PR</c>).</summary>
    public int RotaryLinesAhead()
    {
        if (Rotary is null)
        {
            return 0;
        }

        if (_pcValid && ProgramNumber == 0)
        {
            var top = _calls.Depth > 0 ? _calls.Bottom : _pc;
            if (top.Buffer == Rotary)
            {
                var inProgress = _calls.Depth > 0 || top.Stmt > 0 ? 1 : 0;
                return (int)Math.Max(0, Rotary.EndIndex - top.Line - inProgress);
            }
        }

        return Rotary.LineCount;
    }

    /// <summary>Re-evaluates the rotary-full bit with its I17/I16 hysteresis.</summary>
    public void UpdateFullBit()
    {
        if (Rotary is null)
        {
            RotaryFullBit = false;
            return;
        }

        var ahead = RotaryLinesAhead();
        if (ahead >= (int)_sim.Memory.GetI(17))
        {
            RotaryFullBit = true;
        }
        else if (ahead < (int)_sim.Memory.GetI(16))
        {
            RotaryFullBit = false;
        }
    }

    /// <summary><c>B n</c>.</summary>
    public int Begin(int program)
    {
        if (Running && !(Quitting || Stepping) && IsMoving)
        {
            return 1;
        }

        ProgramNumber = program;
        _calls.Clear();
        _pcValid = false;
        _programEnded = false;
        return 0;
    }

    /// <summary><c>R</c> or <c>S</c>: returns 0 or an ERR number.</summary>
    public int Run(bool step)
    {
        if (Holding)
        {
            Holding = false;
            Stepping = step;
            _stepSegments = 0;
            return 0;
        }

        if (Running && !Quitting && !Stepping)
        {
            return step ? 1 : 0;
        }

        if (!_pcValid || _programEnded)
        {
            var buffer = ProgramNumber == 0 ? Rotary : _sim.FindProgram(ProgramNumber);
            if (buffer is null)
            {
                return 15;
            }

            _calls.Clear();
            _pc = new Cursor(buffer, buffer.BaseIndex, 0);
            _cursorReset = true;
            _pc.SkipEmptyLines();
            _pcValid = true;
            _programEnded = false;
        }

        Running = true;
        Quitting = false;
        Stepping = step;
        _stepSegments = 0;
        _underruns.Started();
        _inBlendedSequence = false;
        return 0;
    }

    public void Hold()
    {
        if (Running)
        {
            Holding = true;
        }
    }

    public void Quit()
    {
        if (Running)
        {
            Quitting = true;
            if (!IsMoving)
            {
                StopRunning();
            }
        }
    }

    /// <summary>
    /// <c>A</c>/<c>K</c>: stops at once where the axes are; queued moves are dropped. A move stopped with every axis
    /// at its end point (to the controller's position grid) had ended: it is logged as executed and the axes stand at
    /// its end, so the executed-move log and the positions a host reads say the same (see <see cref="FinishAtEnd"/>).
    /// </summary>
    public void Abort()
    {
        if (FinishAtEnd() is { } ended)
        {
            Array.Copy(ended.End, _moves.Position, AxisCount);
        }
        else
        {
            _motion.Position(_moves.Position, _moves.Position);
        }

        _motion.Stop();
        _pendingSync.Clear();
        Holding = false;
        StopRunning();
    }

    /// <summary>
    /// On a controller the trajectory reaches a move's end point on a servo cycle: an abort finds the move either at its
    /// end exactly or a servo cycle's travel or more short of it. The simulator's clock is continuous, so a move whose
    /// every axis is within <see cref="PmacSimulator.EndTolerance"/> of its end when aborted counts as ended (logged);
    /// any other stays unfinished (not logged), and a host re-runs it.
    /// </summary>
    private Segment? FinishAtEnd()
    {
        if (_motion.Current is not { } current)
        {
            return null;
        }

        var at = new double[AxisCount];
        _motion.Position(at, _moves.Position);
        for (var axis = 0; axis < AxisCount; axis++)
        {
            if (Math.Abs(current.End[axis] - at[axis]) > _sim.EndTolerance(Number, axis))
            {
                return null;
            }
        }

        current.Remaining = 0;
        var done = _motion.CompleteIfDone();
        if (done is not null)
        {
            _sim.RecordAbortedAtEnd(this, done);
        }

        return done;
    }

    /// <summary>PMATCH for one axis: the next move starts from <paramref name="value"/>, where the axis's motor is (not while moving).</summary>
    public void MatchAxis(int axis, double value)
    {
        if (!IsMoving)
        {
            _moves.Position[axis] = value;
        }
    }

    /// <summary>Positions as the motors are now (interpolated within the executing move).</summary>
    public void ActualPosition(double[] into) => _motion.Position(into, _moves.Position);

    /// <summary>Forgets the rotary buffer (DELETE ROT, $$$); the program stops if it was running from it.</summary>
    public void DropRotary()
    {
        if (ProgramNumber == 0)
        {
            Abort();
            _pcValid = false;
        }

        Rotary = null;
        RotaryFullBit = false;
    }

    /// <summary>Clears a rotary buffer's content and re-points the program at its (new) start.</summary>
    public void RotaryCleared()
    {
        if (ProgramNumber == 0 && _pcValid && Rotary is not null)
        {
            _calls.Clear();
            _pc = new Cursor(Rotary, Rotary.BaseIndex, 0);
            _cursorReset = true;
        }
    }

    /// <summary>Calculates program statements until the lookahead queue is full or the program must wait.</summary>
    public void Calculate()
    {
        if (!Running || Quitting || !_pcValid || _programEnded || _motion.BlockedBy is not null)
        {
            return;
        }

        var budget = _sim.Options.MaxStatementsPerCalculation;
        var lookahead = Math.Max(0, _sim.Options.LookaheadMoves);
        while (budget-- > 0)
        {
            if (_motion.Count >= lookahead && !(Current is null && _motion.Count == 0))
            {
                return;
            }

            if (Stepping && _stepSegments > 0)
            {
                return;
            }

            if (_motion.BlockedBy is not null || _programEnded || Quitting || !Running)
            {
                return;
            }

            if (_pc.AtEnd)
            {
                if (_calls.Depth > 0 && _pc.Buffer.Kind != BufferKind.Rotary)
                {
                    // Falling off the end of a subroutine returns to the caller.
                    Return();
                    continue;
                }

                if (_pc.Buffer.Kind == BufferKind.Rotary)
                {
                    return; // waiting for more lines
                }

                EndProgram();
                return;
            }

            try
            {
                Execute();
            }
            catch (SimRuntimeException e)
            {
                _sim.RuntimeError(this, e.Error);
                Abort();
                return;
            }
        }
    }

    private void Execute()
    {
        if (_pc.Buffer.Kind == BufferKind.Rotary && (!ReferenceEquals(_pc.Buffer, _loggedBuffer) || _pc.Line != _loggedLine || _cursorReset))
        {
            // First statement calculated on a rotary line (or the line again after a restart): the line runs now.
            _loggedBuffer = _pc.Buffer;
            _loggedLine = _pc.Line;
            _cursorReset = false;
            _sim.RecordRotaryLine(this, _pc.Buffer[_pc.Line].Text);
        }

        var stmt = _pc.Current;
        if (Flow.TryExecute(ref _pc, this, out _))
        {
            AfterAdvance();
            return;
        }

        switch (stmt)
        {
            case WordStmt:
                ExecuteMove();
                return;
            case AssignStmt a:
                {
                    var value = a.Value.Eval(this);
                    if (a.Synchronous)
                    {
                        _pendingSync.Add((a.Index, value));
                    }
                    else
                    {
                        Set(a.Kind, a.IndexOf(this), value);
                    }

                    break;
                }

            case DwellStmt d:
                {
                    var seg = _moves.Dwell(d.Milliseconds.Eval(this), d.Delay);
                    _pc.Step();
                    AfterAdvance();
                    Enqueue(seg);
                    return;
                }

            case CodeCallStmt cc:
                {
                    var code = cc.Code.Eval(this);
                    var program = cc.Letter switch { 'G' => 1000, 'M' => 1001, 'T' => 1002, _ => 1003 };
                    var label = (int)Math.Round(code * 1000);
                    _pc.Step();
                    Call(program, label, silentIfMissing: true);
                    return;
                }

            case JumpStmt j:
                {
                    var target = j.Target.Eval(this);
                    _pc.Step();
                    switch (j.Kind)
                    {
                        case JumpKind.Call:
                            {
                                var program = (int)Math.Floor(target);
                                var label = (int)Math.Round((target - program) * 100000);
                                Call(program, label, silentIfMissing: false);
                                return;
                            }

                        case JumpKind.Gosub:
                            Call(_pc.Buffer, (int)Math.Round(target), silentIfMissing: false);
                            return;
                        default:
                            if (!_pc.Buffer.TryFindLabel((int)Math.Round(target), out var pos))
                            {
                                throw new SimRuntimeException(16);
                            }

                            _pc.JumpTo(pos);
                            AfterAdvance();
                            return;
                    }
                }

            case ReturnStmt:
                _pc.Step();
                if (_calls.Depth > 0)
                {
                    Return();
                }
                else if (_pc.Buffer.Kind != BufferKind.Rotary)
                {
                    EndProgram();
                }

                return;
            case StopStmt:
                _pc.Step();
                AfterAdvance();
                Quitting = true;
                if (!IsMoving)
                {
                    StopRunning();
                }

                return;
            case ReadStmt r:
                _calls.Read(r.Letters, this);
                break;
            default:
                // Modes, ABS/INC, F/TA/TS/TM/CC, NORMAL (last: moves and assignments are by far the most frequent).
                _moves.Apply(stmt, this);
                break;
        }

        _pc.Step();
        AfterAdvance();
    }

    private void Call(int program, int label, bool silentIfMissing)
    {
        var buffer = _sim.FindProgram(program);
        if (buffer is null)
        {
            if (silentIfMissing)
            {
                AfterAdvance();
                return;
            }

            throw new SimRuntimeException(15);
        }

        Call(buffer, label, silentIfMissing);
    }

    private void Call(ProgramBuffer buffer, int label, bool silentIfMissing)
    {
        (long Line, int Stmt) target = (buffer.BaseIndex, 0);
        if (label != 0 || silentIfMissing)
        {
            if (!buffer.TryFindLabel(label, out target))
            {
                if (silentIfMissing)
                {
                    // A missing label is silently ignored, as the controller does for G/M/T/D codes.
                    AfterAdvance();
                    return;
                }

                throw new SimRuntimeException(16);
            }
        }

        _calls.Call(ref _pc, buffer, target);
    }

    private void Return()
    {
        _calls.Return(ref _pc);
        AfterAdvance();
    }

    private void ExecuteMove()
    {
        // A move is the run of letter words on this line: axes, the I/J/K centre vector and R radius.
        _moves.ClearWords();
        var stmts = _pc.Buffer[_pc.Line].Statements;
        while (_pc.Stmt < stmts.Length && stmts[_pc.Stmt] is WordStmt w)
        {
            if (w.Letter == 'S')
            {
                // S{data}: "the value in {data} is loaded in variable Q127 for the coordinate system executing the
                // motion program. It takes no other action" (Turbo SRM p. 469): the programmed spindle speed.
                _sim.Memory.SetQ(Number, 127, w.Value.Eval(this));
                _pc.Stmt++;
                continue;
            }

            _moves.SetWord(w.Letter, w.Value.Eval(this));
            _pc.Stmt++;
        }

        // A modal F/TA/TS/TM on the move's own line is the move's, wherever it stands on the line ("modal commands can
        // precede the move commands they are to affect, or they can be on the same line", Turbo User Manual p. 272;
        // "X10Y0 F2 ; Linear move", Turbo SRM p. 421): the splitter writes F(P500) after the axis words. They run
        // again where they stand, which changes nothing.
        for (var i = _pc.Stmt; i < stmts.Length && stmts[i] is not (WordStmt or CodeCallStmt or JumpStmt); i++)
        {
            if (stmts[i] is ParamStmt { Kind: ParamKind.Feed or ParamKind.Ta or ParamKind.Ts or ParamKind.Tm } modal)
            {
                _moves.Apply(modal, this);
            }
        }

        _pc.Stmt--;
        _pc.Step();
        AfterAdvance();
        if (_moves.Move() is { } seg)
        {
            Enqueue(seg);
        }
    }

    private void Enqueue(Segment seg)
    {
        if (_pendingSync.Count > 0)
        {
            seg.Sync = [.. _pendingSync];
            _pendingSync.Clear();
        }

        _motion.Enqueue(seg);
        _stepSegments++;
    }

    private void AfterAdvance()
    {
        // Rotary lines are freed once calculation has left them (top level only: a caller's line stays in use).
        if (_calls.Depth == 0 && _pc.Buffer.Kind == BufferKind.Rotary && _pc.Line > _pc.Buffer.BaseIndex)
        {
            _pc.Buffer.FreeBefore(_pc.Line);
        }
    }

    private void EndProgram()
    {
        _programEnded = true;
        if (!IsMoving)
        {
            StopRunning();
        }
    }

    private void StopRunning()
    {
        if (_pendingSync.Count > 0)
        {
            foreach (var (index, value) in _pendingSync)
            {
                _sim.SetVariable('M', index, value);
            }

            _pendingSync.Clear();
        }

        Running = false;
        Quitting = false;
        Stepping = false;
        Holding = false;
        _underruns.Stopped();
        if (_programEnded)
        {
            _pcValid = false;
        }
    }

    /// <summary>Starts the next queued segment at <paramref name="now"/> if nothing is executing.</summary>
    public void TryStartNext(double now)
    {
        if (Current is not null)
        {
            return;
        }

        if (_motion.Count == 0)
        {
            _inBlendedSequence = false; // nothing to blend into: the axes decelerate to a stop
            if (Running && !Quitting && !Stepping && !_programEnded && _motion.BlockedBy is null && _pcValid && _pc.Buffer.Kind == BufferKind.Rotary && _pc.AtEnd && _calls.Depth == 0)
            {
                switch (_underruns.OutOfLines(_pc.Buffer.IsOpen, _sim.Options.RotaryEndBehaviour))
                {
                    case Starvation.Underrun:
                        _sim.CountUnderrun(this);
                        break;
                    case Starvation.End:
                        _programEnded = true;
                        StopRunning();
                        break;
                }
            }
            else if (Running && (Quitting || Stepping || _programEnded))
            {
                StopRunning();
            }

            return;
        }

        var seg = _motion.StartNext(now);
        TurboTiming.StartFromRest(seg, _inBlendedSequence);
        if (_underruns.MoveStarted())
        {
            _sim.CountUnderrun(this); // it was not the end after all
        }

        if (seg.Sync is { } sync)
        {
            foreach (var (index, value) in sync)
            {
                _sim.SetVariable('M', index, value);
                seg.BlockStart |= index == _sim.Options.TrackingVariable;
            }
        }

        seg.SourceLine = (int)Math.Round(_sim.GetVariable('M', _sim.Options.TrackingVariable));
    }

    /// <summary>The next time this C.S. needs attention (a segment ends, or the override slews a tick).</summary>
    public double NextEventTime(double now) => _motion.NextEventTime(now, Holding);

    /// <summary>Advances the executing segment and the override slew over [t0, t1].</summary>
    public void AdvanceTime(double t0, double t1) => _motion.AdvanceTime(t0, t1, Holding);

    /// <summary>Finishes the executing segment if it is done; returns it.</summary>
    public Segment? CompleteIfDone()
    {
        var done = _motion.CompleteIfDone();
        if (done is not null)
        {
            _inBlendedSequence = TurboTiming.IsBlended(done);
        }

        return done;
    }
}
