using System.Runtime.CompilerServices;
using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// The motion side of a coordinate system's calculation: the modal state (move mode, ABS/INC per axis and for arc
/// centres, feed or move time, TA/TS, NORMAL, cutter compensation) and the segments calculated from it, moves (with
/// their arc geometry) and dwells, from the calculated position (where the last calculated move ends).
/// </summary>
/// <param name="options">Rapid and default feeds, the feed time unit.</param>
/// <param name="matrices">The axis transformation matrices <c>TSEL</c> chooses from.</param>
internal sealed class MoveCalculator(SimOptions options, AxisMatrices matrices)
{
    private static readonly double[] NoDisplacement = new double[3];

    private const string Axes = "XYZABCUVW";
    private const double Epsilon = 1e-9;

    private readonly bool[] _incremental = new bool[CoordinateSystem.AxisCount];
    private readonly double[] _calcPos = new double[CoordinateSystem.AxisCount];
    private readonly double[] _wordValues = new double[CoordinateSystem.AxisCount + 4];
    private bool _anyAxis;
    private bool _anyVector;

    /// <summary>The move mode (RAPID, LINEAR, CIRCLE1/2).</summary>
    public MotionMode Mode { get; private set; }

    /// <summary>True after <c>TM</c>: moves take the given time instead of following the feed.</summary>
    public bool TimeMode { get; private set; }

    /// <summary>Cutter radius compensation mode: 0 off (CC0), 1 left (CC1), 2 right (CC2).</summary>
    public int CutterComp { get; private set; }

    /// <summary>Cutter radius (CCR).</summary>
    public double CutterRadius { get; private set; }

    /// <summary>The calculated position: where the last calculated move ends (set where an abort stopped the axes).</summary>
    public double[] Position => _calcPos;

    private double Feed { get; set; }

    private double Ta { get; set; }

    private double Ts { get; set; }

    private double Tm { get; set; }

    private bool IncrementalRadius { get; set; }

    /// <summary>The selected transformation matrix's displacement (zero when none is selected): programmed X, Y, Z plus this are machine positions.</summary>
    private double[] Displacement { get; set; } = NoDisplacement;

    /// <summary>The matrix <c>TSEL</c> selected, 0 for none.</summary>
    public int SelectedMatrix { get; private set; }

    private (double I, double J, double K) Normal { get; set; }

    /// <summary>The power-on modes: LINEAR, ABS, INC arc centres, no feed, TA and TS from Isx87 and Isx88, NORMAL K-1.</summary>
    public void Reset()
    {
        Mode = MotionMode.Linear;
        Array.Clear(_incremental);
        IncrementalRadius = true;
        Feed = 0;
        Ta = options.AccelerationTimeMs;
        Ts = options.SCurveTimeMs;
        Tm = 0;
        TimeMode = false;
        Normal = (0, 0, -1);
        SelectedMatrix = 0;
        Displacement = NoDisplacement;
    }

    /// <summary>Applies a modal statement (mode, ABS/INC, F/TA/TS/TM/CC/CCR, NORMAL); false for any other statement.</summary>
    public bool Apply(Stmt stmt, IVariableAccess variables)
    {
        switch (stmt)
        {
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
                    var v = p.Value.Eval(variables);
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
            case MatrixStmt t:
                ApplyMatrix(t, variables);
                break;
            default:
                return false;
        }

        return true;
    }

    /// <summary><c>TSEL</c>, <c>TINIT</c>, <c>ADIS</c>, <c>IDIS</c>: they change which positions later moves reach, and move nothing.</summary>
    private void ApplyMatrix(MatrixStmt t, IVariableAccess variables)
    {
        switch (t.Op)
        {
            case MatrixOp.Select:
                SelectedMatrix = t.Argument;
                Displacement = t.Argument == 0 ? NoDisplacement : matrices.Displacement(t.Argument);
                break;
            case MatrixOp.Init when SelectedMatrix > 0:
                Array.Clear(Displacement);
                break;
            case MatrixOp.AbsoluteDisplacement or MatrixOp.IncrementalDisplacement when SelectedMatrix > 0:
                for (var i = 0; i < 3; i++)
                {
                    var q = variables.Get('Q', t.Argument + i);
                    Displacement[i] = t.Op == MatrixOp.AbsoluteDisplacement ? q : Displacement[i] + q;
                }

                break;
            case MatrixOp.Init or MatrixOp.AbsoluteDisplacement or MatrixOp.IncrementalDisplacement:
                // No matrix selected: nothing to load (assumed; the manual names the selected matrix only).
                break;
            default:
                // AROT/IROT: rotation and scaling are not simulated.
                throw new SimRuntimeException(3);
        }
    }

    /// <summary>A dwell (<c>DWELL</c>: calculation waits until it has executed) or a delay (<c>DELAY</c>: it does not) at the calculated position.</summary>
    public Segment Dwell(double milliseconds, bool delay)
    {
        var seg = new Segment { Kind = MoveKind.Dwell, Duration = Math.Max(0, milliseconds) / 1000.0, BlocksCalculation = !delay };
        Array.Copy(_calcPos, seg.Start, CoordinateSystem.AxisCount);
        Array.Copy(_calcPos, seg.End, CoordinateSystem.AxisCount);
        return seg;
    }

    /// <summary>Starts collecting the words of a move.</summary>
    public void ClearWords()
    {
        Array.Fill(_wordValues, double.NaN);
        _anyAxis = false;
        _anyVector = false;
    }

    /// <summary>One word of the move: an axis, the I/J/K centre vector or the R radius (other letters are ignored).</summary>
    [MethodImpl(MethodImplOptions.AggressiveInlining)] // once per word of every move
    public void SetWord(char letter, double value)
    {
        var axis = Axes.IndexOf(letter);
        if (axis >= 0)
        {
            _wordValues[axis] = value;
            _anyAxis = true;
        }
        else if (letter is 'I' or 'J' or 'K')
        {
            _wordValues[CoordinateSystem.AxisCount + (letter - 'I')] = value;
            _anyVector = true;
        }
        else if (letter == 'R')
        {
            _wordValues[CoordinateSystem.AxisCount + 3] = value;
        }
    }

    /// <summary>
    /// The move of the words collected, in the modes in force, from the calculated position (which moves to its end);
    /// null when they move nothing (arguments of a call nobody READ).
    /// </summary>
    public Segment? Move()
    {
        var isCircle = Mode is MotionMode.Circle1 or MotionMode.Circle2;
        if (!_anyAxis && !(isCircle && _anyVector))
        {
            return null; // arguments nobody READ: ignored
        }

        var seg = new Segment();
        Array.Copy(_calcPos, seg.Start, CoordinateSystem.AxisCount);
        for (var i = 0; i < CoordinateSystem.AxisCount; i++)
        {
            var v = _wordValues[i];
            seg.End[i] = double.IsNaN(v) ? _calcPos[i] : _incremental[i] ? _calcPos[i] + v : i < 3 ? v + Displacement[i] : v;
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
            for (var i = 3; i < CoordinateSystem.AxisCount; i++)
            {
                seg.Length = Math.Max(seg.Length, Math.Abs(seg.End[i] - seg.Start[i]));
            }
        }

        var unit = options.FeedTimeUnitMs / 1000.0;
        if (seg.Kind == MoveKind.Rapid)
        {
            seg.Duration = seg.Length / options.RapidFeed * unit;
        }
        else if (TimeMode)
        {
            seg.Duration = Math.Max(0, Tm) / 1000.0;
            seg.Feed = seg.Duration > 0 ? seg.Length / seg.Duration * unit : 0;
        }
        else
        {
            var feed = Feed > 0 ? Feed : options.DefaultFeed;
            seg.Feed = feed;
            seg.Duration = seg.Length / feed * unit;
        }

        if (seg.Kind != MoveKind.Rapid)
        {
            TurboTiming.Blend(seg, Ta, Ts, options);
        }

        Array.Copy(seg.End, _calcPos, CoordinateSystem.AxisCount);
        return seg;
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
        var radiusWord = _wordValues[CoordinateSystem.AxisCount + 3];
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
            c1 = IncrementalRadius ? s1 + vec1 : vec1 + Displacement[a1];
            c2 = IncrementalRadius ? s2 + vec2 : vec2 + Displacement[a2];
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
        // An end off the circle: the Turbo PMAC changes the radius smoothly over the move, a spiral ending exactly at
        // the programmed end point (SRM, CIRCLE1/CIRCLE2).
        seg.EndRadius = Math.Sqrt(Sq(e1 - c1) + Sq(e2 - c2));
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

        var v = _wordValues[CoordinateSystem.AxisCount + index];
        return double.IsNaN(v) ? 0 : v;
    }

    private static double Sq(double v) => v * v;
}
