using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>A move or dwell calculated ahead of execution, waiting in the lookahead queue or executing.</summary>
internal sealed class Segment
{
    public MoveKind Kind;
    public double[] Start = new double[CoordinateSystem.AxisCount];
    public double[] End = new double[CoordinateSystem.AxisCount];
    public double Duration;
    public double Remaining;
    public double Length;
    public double Feed;
    public bool BlocksCalculation;
    public List<(int Index, double Value)>? Sync;

    // Arc geometry (circle moves only): plane axes, centre in plane, start angle, signed sweep, radius.
    public int A1;
    public int A2;
    public int An;
    public double C1;
    public double C2;
    public double StartAngle;
    public double Sweep;
    public double Radius;
    public double StartTime;
    public int SourceLine;

    public bool IsArc => Kind is MoveKind.Circle1 or MoveKind.Circle2;

    public void PositionAt(double fraction, double[] into)
    {
        for (var i = 0; i < into.Length; i++)
        {
            into[i] = Start[i] + ((End[i] - Start[i]) * fraction);
        }

        if (IsArc && fraction < 1)
        {
            var a = StartAngle + (Sweep * fraction);
            into[A1] = C1 + (Radius * Math.Cos(a));
            into[A2] = C2 + (Radius * Math.Sin(a));
        }
    }
}

/// <summary>
/// One coordinate system: its program pointer, the calculation (lookahead) of program lines into segments and the
/// execution of those segments on the virtual clock. Guarded by the simulator's lock.
/// </summary>
internal sealed class CoordinateSystem : IVariableAccess
{
    public const int AxisCount = 9;
    private const string Axes = "XYZABCUVW";
    private const double Epsilon = 1e-9;

    private readonly PmacSimulator _sim;
    private readonly List<Cursor> _stack = [];
    private readonly Queue<Segment> _queue = new();
    private readonly List<(int Index, double Value)> _pendingSync = [];
    private ProgramBuffer? _loggedBuffer;
    private long _loggedLine = -1;
    private bool _cursorReset;
    private readonly bool[] _incremental = new bool[AxisCount];
    private readonly double[] _calcPos = new double[AxisCount];
    private readonly double[] _wordValues = new double[AxisCount + 4];
    private Cursor _pc;
    private bool _pcValid;
    private Segment? _blockedBy;
    private bool _programEnded;
    private int _stepSegments;
    private bool _movedSinceStart;
    private bool _starved;
    private bool _starvedWhileClosed;

    public CoordinateSystem(PmacSimulator sim, int number)
    {
        _sim = sim;
        Number = number;
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

    public Segment? Current { get; private set; }

    public double OverrideTarget { get; set; } = 100;

    public double OverrideCurrent { get; private set; } = 100;

    public MotionMode Mode { get; private set; }

    public bool TimeMode { get; private set; }

    public bool RotaryFullBit { get; private set; }

    public int QueuedSegments => _queue.Count;

    public bool IsMoving => Current is not null || _queue.Count > 0;

    /// <summary>True while a program runs whose calculation is inside <paramref name="buffer"/> or returns into it.</summary>
    public bool IsExecuting(ProgramBuffer buffer) =>
        Running && _pcValid && (_pc.Buffer == buffer || _stack.Exists(f => f.Buffer == buffer));

    private double Feed { get; set; }

    private double Ta { get; set; }

    private double Ts { get; set; }

    private double Tm { get; set; }

    /// <summary>Cutter radius compensation mode: 0 off (CC0), 1 left (CC1), 2 right (CC2).</summary>
    public int CutterComp { get; private set; }

    /// <summary>Cutter radius (CCR).</summary>
    public double CutterRadius { get; private set; }

    private bool IncrementalRadius { get; set; }

    private (double I, double J, double K) Normal { get; set; }

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

    public void ResetModal()
    {
        Mode = MotionMode.Linear;
        Array.Clear(_incremental);
        IncrementalRadius = true;
        Feed = 0;
        Ta = 10;
        Ts = 0;
        Tm = 0;
        TimeMode = false;
        Normal = (0, 0, -1);
    }

    /// <summary>Lines in the rotary buffer ahead of the line being calculated (<c>PR</c>).</summary>
    public int RotaryLinesAhead()
    {
        if (Rotary is null)
        {
            return 0;
        }

        if (_pcValid && ProgramNumber == 0)
        {
            var top = _stack.Count > 0 ? _stack[0] : _pc;
            if (top.Buffer == Rotary)
            {
                var inProgress = _stack.Count > 0 || top.Stmt > 0 ? 1 : 0;
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
        _stack.Clear();
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

            _stack.Clear();
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
        _movedSinceStart = false;
        _starved = false;
        _starvedWhileClosed = false;
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

    /// <summary><c>A</c>/<c>K</c>: stops at once where the axes are; queued moves are dropped.</summary>
    public void Abort()
    {
        if (Current is { } cur)
        {
            var fraction = cur.Duration <= 0 ? 1 : 1 - Math.Clamp(cur.Remaining / cur.Duration, 0, 1);
            cur.PositionAt(fraction, _calcPos);
        }
        else if (_queue.Count > 0)
        {
            Array.Copy(_queue.Peek().Start, _calcPos, AxisCount);
        }

        Current = null;
        _queue.Clear();
        _pendingSync.Clear();
        _blockedBy = null;
        Holding = false;
        OverrideCurrent = OverrideTarget;
        StopRunning();
    }

    /// <summary>Positions as the motors are now (interpolated within the executing move).</summary>
    public void ActualPosition(double[] into)
    {
        if (Current is { } cur)
        {
            var fraction = cur.Duration <= 0 ? 1 : 1 - Math.Clamp(cur.Remaining / cur.Duration, 0, 1);
            cur.PositionAt(fraction, into);
        }
        else if (_queue.Count > 0)
        {
            Array.Copy(_queue.Peek().Start, into, AxisCount);
        }
        else
        {
            Array.Copy(_calcPos, into, AxisCount);
        }
    }

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
            _stack.Clear();
            _pc = new Cursor(Rotary, Rotary.BaseIndex, 0);
            _cursorReset = true;
        }
    }

    /// <summary>Calculates program statements until the lookahead queue is full or the program must wait.</summary>
    public void Calculate()
    {
        if (!Running || Quitting || !_pcValid || _programEnded || _blockedBy is not null)
        {
            return;
        }

        var budget = _sim.Options.MaxStatementsPerCalculation;
        var lookahead = Math.Max(0, _sim.Options.LookaheadMoves);
        while (budget-- > 0)
        {
            if (_queue.Count >= lookahead && !(Current is null && _queue.Count == 0))
            {
                return;
            }

            if (Stepping && _stepSegments > 0)
            {
                return;
            }

            if (_blockedBy is not null || _programEnded || Quitting || !Running)
            {
                return;
            }

            if (_pc.AtEnd)
            {
                if (_stack.Count > 0 && _pc.Buffer.Kind != BufferKind.Rotary)
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
                        Set(a.Kind, a.Index, value);
                    }

                    break;
                }

            case ModeStmt m:
                Mode = m.Mode;
                break;
            case AbsIncStmt ai:
                if (ai.Axes.Length == 0)
                {
                    Array.Fill(_incremental, ai.Incremental);
                }
                else
                {
                    foreach (var ch in ai.Axes)
                    {
                        if (ch == 'R')
                        {
                            IncrementalRadius = ai.Incremental;
                        }
                        else if (Axes.IndexOf(ch) is var idx and >= 0)
                        {
                            _incremental[idx] = ai.Incremental;
                        }
                    }
                }

                break;
            case ParamStmt p:
                {
                    var v = p.Value.Eval(this);
                    switch (p.Kind)
                    {
                        case ParamKind.Feed:
                            Feed = v;
                            TimeMode = false;
                            break;
                        case ParamKind.Ta:
                            Ta = v;
                            break;
                        case ParamKind.Ts:
                            Ts = v;
                            break;
                        case ParamKind.Tm:
                            Tm = v;
                            TimeMode = true;
                            break;
                        case ParamKind.CutterComp:
                            // Accepted and remembered; the simulated path stays the programmed (uncompensated) one.
                            CutterComp = (int)v;
                            break;
                        case ParamKind.CutterRadius:
                            CutterRadius = v;
                            break;
                    }

                    break;
                }

            case NormalStmt n:
                Normal = (n.I, n.J, n.K);
                break;
            case DwellStmt d:
                {
                    var seg = new Segment { Kind = MoveKind.Dwell, Duration = Math.Max(0, d.Milliseconds.Eval(this)) / 1000.0, BlocksCalculation = !d.Delay };
                    Array.Copy(_calcPos, seg.Start, AxisCount);
                    Array.Copy(_calcPos, seg.End, AxisCount);
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
                if (_stack.Count > 0)
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
                Read(r.Letters);
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

        if (_stack.Count >= 255)
        {
            throw new SimRuntimeException(16);
        }

        _stack.Add(_pc);
        _pc = new Cursor(buffer, target.Line, target.Stmt);
        if (!_pc.AtEnd && _pc.Stmt >= buffer[_pc.Line].Statements.Length)
        {
            _pc.EndLine();
        }
    }

    private void Return()
    {
        _pc = _stack[^1];
        _stack.RemoveAt(_stack.Count - 1);
        if (!_pc.AtEnd && _pc.Stmt >= _pc.Buffer[_pc.Line].Statements.Length)
        {
            _pc.EndLine();
        }

        AfterAdvance();
    }

    private void Read(string letters)
    {
        if (_stack.Count == 0)
        {
            return;
        }

        var caller = _stack[^1];
        var q100 = 0L; // READ reports only the letters this call received
        var line = caller.Buffer[caller.Line].Statements;
        while (caller.Stmt < line.Length && ArgumentOf(line[caller.Stmt]) is { } arg && letters.Contains(arg.Letter))
        {
            var n = arg.Letter - 'A';
            Set('Q', 101 + n, arg.Value.Eval(this));
            q100 |= 1L << n;
            caller.Stmt++;
        }

        Set('Q', 100, q100);
        _stack[^1] = caller;
    }

    /// <summary>Any letter-value pair after a call is an argument READ can take (F and M/G/T/D included).</summary>
    private static (char Letter, Expr Value)? ArgumentOf(Stmt s) => s switch
    {
        WordStmt w => (w.Letter, w.Value),
        ParamStmt { Kind: ParamKind.Feed } f => ('F', f.Value),
        CodeCallStmt c => (c.Letter, c.Code),
        _ => null,
    };

    private void ExecuteMove()
    {
        // A move is the run of letter words on this line: axes, the I/J/K centre vector and R radius.
        Array.Fill(_wordValues, double.NaN);
        var stmts = _pc.Buffer[_pc.Line].Statements;
        var anyAxis = false;
        var anyVector = false;
        while (_pc.Stmt < stmts.Length && stmts[_pc.Stmt] is WordStmt w)
        {
            var v = w.Value.Eval(this);
            var axis = Axes.IndexOf(w.Letter);
            if (axis >= 0)
            {
                _wordValues[axis] = v;
                anyAxis = true;
            }
            else if (w.Letter is 'I' or 'J' or 'K')
            {
                _wordValues[AxisCount + (w.Letter - 'I')] = v;
                anyVector = true;
            }
            else if (w.Letter == 'R')
            {
                _wordValues[AxisCount + 3] = v;
            }

            _pc.Stmt++;
        }

        _pc.Stmt--;
        _pc.Step();
        AfterAdvance();

        var isCircle = Mode is MotionMode.Circle1 or MotionMode.Circle2;
        if (!anyAxis && !(isCircle && anyVector))
        {
            return; // arguments nobody READ: ignored
        }

        var seg = new Segment();
        Array.Copy(_calcPos, seg.Start, AxisCount);
        for (var i = 0; i < AxisCount; i++)
        {
            var v = _wordValues[i];
            seg.End[i] = double.IsNaN(v) ? _calcPos[i] : _incremental[i] ? _calcPos[i] + v : v;
        }

        seg.Kind = Mode switch
        {
            MotionMode.Rapid => MoveKind.Rapid,
            MotionMode.Linear => MoveKind.Linear,
            MotionMode.Circle1 => MoveKind.Circle1,
            _ => MoveKind.Circle2,
        };

        var linear = Math.Sqrt(Sq(seg.End[0] - seg.Start[0]) + Sq(seg.End[1] - seg.Start[1]) + Sq(seg.End[2] - seg.Start[2]));
        seg.Length = linear;
        if (isCircle)
        {
            seg.Length = ArcGeometry(seg, linear);
        }

        if (seg.Length == 0)
        {
            for (var i = 3; i < AxisCount; i++)
            {
                seg.Length = Math.Max(seg.Length, Math.Abs(seg.End[i] - seg.Start[i]));
            }
        }

        var unit = _sim.Options.FeedTimeUnitMs / 1000.0;
        if (seg.Kind == MoveKind.Rapid)
        {
            seg.Duration = seg.Length / _sim.Options.RapidFeed * unit;
        }
        else if (TimeMode)
        {
            seg.Duration = Math.Max(0, Tm) / 1000.0;
            seg.Feed = seg.Duration > 0 ? seg.Length / seg.Duration * unit : 0;
        }
        else
        {
            var feed = Feed > 0 ? Feed : _sim.Options.DefaultFeed;
            seg.Feed = feed;
            seg.Duration = seg.Length / feed * unit;
        }

        Array.Copy(seg.End, _calcPos, AxisCount);
        Enqueue(seg);
    }

    private double ArcGeometry(Segment seg, double chordFallback)
    {
        var (ni, nj, nk) = Normal;
        int a1, a2, an;
        double sign;
        if (Math.Abs(nk) >= Math.Abs(ni) && Math.Abs(nk) >= Math.Abs(nj))
        {
            (a1, a2, an, sign) = (0, 1, 2, nk);
        }
        else if (Math.Abs(nj) >= Math.Abs(ni))
        {
            (a1, a2, an, sign) = (2, 0, 1, nj);
        }
        else
        {
            (a1, a2, an, sign) = (1, 2, 0, ni);
        }

        // With NORMAL K-1 (the default), CIRCLE1 is clockwise seen from +Z.
        var dir = (seg.Kind == MoveKind.Circle2 ? 1.0 : -1.0) * (sign < 0 ? 1.0 : -1.0);
        double s1 = seg.Start[a1], s2 = seg.Start[a2], e1 = seg.End[a1], e2 = seg.End[a2];
        double c1, c2;
        var radiusWord = _wordValues[AxisCount + 3];
        if (!double.IsNaN(radiusWord))
        {
            var chord = Math.Sqrt(Sq(e1 - s1) + Sq(e2 - s2));
            if (chord < Epsilon)
            {
                return chordFallback; // R form cannot describe a full circle
            }

            var r = Math.Abs(radiusWord);
            var h = Math.Sqrt(Math.Max(0, (r * r) - (chord * chord / 4)));
            double u1 = (e1 - s1) / chord, u2 = (e2 - s2) / chord;
            var side = dir * Math.Sign(radiusWord);
            c1 = ((s1 + e1) / 2) - (u2 * h * side);
            c2 = ((s2 + e2) / 2) + (u1 * h * side);
        }
        else
        {
            var vec1 = VectorComponent(a1);
            var vec2 = VectorComponent(a2);
            c1 = IncrementalRadius ? s1 + vec1 : vec1;
            c2 = IncrementalRadius ? s2 + vec2 : vec2;
        }

        var radius = Math.Sqrt(Sq(s1 - c1) + Sq(s2 - c2));
        var startAngle = Math.Atan2(s2 - c2, s1 - c1);
        var endAngle = Math.Atan2(e2 - c2, e1 - c1);
        var sweep = dir > 0 ? endAngle - startAngle : startAngle - endAngle;
        sweep %= 2 * Math.PI;
        if (sweep < 0)
        {
            sweep += 2 * Math.PI;
        }

        var closed = Math.Sqrt(Sq(e1 - s1) + Sq(e2 - s2)) < 1e-7;
        if (closed || sweep < 1e-12)
        {
            sweep = closed ? 2 * Math.PI : sweep;
        }

        seg.A1 = a1;
        seg.A2 = a2;
        seg.An = an;
        seg.C1 = c1;
        seg.C2 = c2;
        seg.Radius = radius;
        seg.StartAngle = startAngle;
        seg.Sweep = dir * sweep;
        var helix = seg.End[an] - seg.Start[an];
        return Math.Sqrt(Sq(radius * sweep) + Sq(helix));
    }

    private double VectorComponent(int axis)
    {
        var index = axis switch { 0 => 0, 1 => 1, 2 => 2, _ => -1 };
        if (index < 0)
        {
            return 0;
        }

        var v = _wordValues[AxisCount + index];
        return double.IsNaN(v) ? 0 : v;
    }

    private static double Sq(double v) => v * v;

    private void Enqueue(Segment seg)
    {
        if (_pendingSync.Count > 0)
        {
            seg.Sync = [.. _pendingSync];
            _pendingSync.Clear();
        }

        seg.Remaining = seg.Duration;
        _queue.Enqueue(seg);
        _stepSegments++;
        if (seg.BlocksCalculation)
        {
            _blockedBy = seg;
        }
    }

    private void AfterAdvance()
    {
        // Rotary lines are freed once calculation has left them (top level only: a caller's line stays in use).
        if (_stack.Count == 0 && _pc.Buffer.Kind == BufferKind.Rotary && _pc.Line > _pc.Buffer.BaseIndex)
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
        _starved = false;
        _starvedWhileClosed = false;
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

        if (_queue.Count == 0)
        {
            if (Running && !Quitting && !Stepping && !_programEnded && _blockedBy is null && _pcValid && _pc.Buffer.Kind == BufferKind.Rotary && _pc.AtEnd && _stack.Count == 0)
            {
                if (!_starved && _movedSinceStart)
                {
                    _starved = true;
                    if (_pc.Buffer.IsOpen)
                    {
                        _sim.CountUnderrun(this);
                    }
                    else if (_sim.Options.RotaryEndBehaviour == RotaryEndBehaviour.EndWhenClosed)
                    {
                        _programEnded = true;
                        StopRunning();
                    }
                    else
                    {
                        _starvedWhileClosed = true;
                    }
                }
            }
            else if (Running && (Quitting || Stepping || _programEnded))
            {
                StopRunning();
            }

            return;
        }

        var seg = _queue.Dequeue();
        if (_starved)
        {
            if (_starvedWhileClosed)
            {
                _sim.CountUnderrun(this); // it was not the end after all
            }

            _starved = false;
            _starvedWhileClosed = false;
        }

        if (seg.Sync is { } sync)
        {
            foreach (var (index, value) in sync)
            {
                _sim.SetVariable('M', index, value);
            }
        }

        seg.StartTime = now;
        seg.SourceLine = (int)Math.Round(_sim.GetVariable('M', _sim.Options.TrackingVariable));
        Current = seg;
        _movedSinceStart = true;
    }

    /// <summary>The next time this C.S. needs attention (a segment ends, or the override slews a tick).</summary>
    public double NextEventTime(double now)
    {
        var cur = Current;
        if (cur is null)
        {
            return _queue.Count > 0 ? now : double.PositiveInfinity;
        }

        var target = Holding ? 0 : OverrideTarget;
        if (Math.Abs(OverrideCurrent - target) > 1e-9)
        {
            var rate = Math.Max(1e-6, _sim.Options.OverrideSlewPercentPerSecond);
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
    public void AdvanceTime(double t0, double t1)
    {
        var dt = t1 - t0;
        if (dt <= 0)
        {
            return;
        }

        var target = Holding ? 0 : OverrideTarget;
        var start = OverrideCurrent;
        var end = start;
        if (Math.Abs(start - target) > 1e-9)
        {
            var step = Math.Max(1e-6, _sim.Options.OverrideSlewPercentPerSecond) * dt;
            end = start < target ? Math.Min(target, start + step) : Math.Max(target, start - step);
        }

        OverrideCurrent = end;
        if (Current is { } cur)
        {
            cur.Remaining -= dt * (start + end) / 200.0;
        }
    }

    /// <summary>Finishes the executing segment if it is done at <paramref name="now"/>; returns it.</summary>
    public Segment? CompleteIfDone(double now)
    {
        var cur = Current;
        if (cur is null || cur.Remaining > Epsilon)
        {
            return null;
        }

        Current = null;
        if (ReferenceEquals(cur, _blockedBy))
        {
            _blockedBy = null;
        }

        if (cur.Kind != MoveKind.Dwell)
        {
            // Executed positions are the calculated ones; nothing to copy.
        }

        return cur;
    }
}
