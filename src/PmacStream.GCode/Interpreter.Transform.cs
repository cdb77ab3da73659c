namespace PmacStream.GCode;

/// <summary>
/// The interpreter's programmable transformations (G51.1 mirror, G51 scaling, G68 rotation; <see cref="ProgramTransform"/>)
/// and exact stop mode (G61). While a transformation is in force the interpreter keeps the untransformed program
/// position, so that an axis a block leaves out keeps its programmed value, and every moving block is a host block:
/// the host sends the transformed positions the interpreter computed, the controller needs no matrix rotation.
/// </summary>
public sealed partial class Interpreter
{
    private ProgramTransform? _transform;   // null while none is in force: the hot path tests one reference
    private Point3 _programPos;              // the untransformed program position while _transform is set
    private bool _exactStop;                 // G61 in force
    private bool _exactStopBlock;            // the last block moved and ends at rest (G61 in force or G09 in it)
    private Point3? _arcCentre;              // the last arc's centre, machine coordinates
    private bool _arcClockwise;
    private double _inverseTimeLength;       // the last move's path length in G93 (arcs along the arc)

    /// <summary>The path length of the last feed move under G93 inverse time (millimetres, arcs along the arc).</summary>
    internal double InverseTimeLength => _inverseTimeLength;

    /// <summary>Whether a programmable transformation (G51.1, G51, G68) is in force: the host converts every move.</summary>
    internal bool Transforming => _transform != null;

    /// <summary>The last block moved and must end at rest before the next starts (G61 in force, or G09 in the block).</summary>
    internal bool ExactStopBlock => _exactStopBlock;

    /// <summary>The centre of the last arc (machine coordinates), and whether it ran clockwise (a mirror reverses it).</summary>
    internal (Point3? Centre, bool Clockwise) LastArc => (_arcCentre, _arcClockwise);

    /// <summary>G50, G50.1, G69 and the G61 group: modal switches without words.</summary>
    private bool ApplyTransformMode(int key)
    {
        switch (key)
        {
            case 500: _transform?.CancelScale(); break;
            case 501: _transform?.CancelMirror(); break;
            case 690: _transform?.CancelRotation(); break;
            // Exact stop mode where the profile has the host run it (FANUC G61, LinuxCNC G61.1; grbl's G61 is its
            // blending path mode, run by the controller).
            case 610 or 611 when _gInfo.TryGetValue(key, out var info) && info.Def.Controller == ControllerSupport.Host: _exactStop = true; return true;
            case 610 or 611 or 620 or 630 or 640 or 641: _exactStop = false; return true;
            default: return false;
        }

        if (_transform is { Active: false })
        {
            _transform = null;
        }

        return true;
    }

    /// <summary>The program position now: untransformed while a transformation is in force.</summary>
    private Point3 ProgramPosition() => _transform != null ? _programPos : _pos - _coords.Active;

    /// <summary>G51.1 X Y Z, G51 X Y Z P (or I J K) and G68 (plane axes, R): the transformation starts from the block's words.</summary>
    private void SetTransform(int key, double? x, double? y, double? z, double? i, double? j, double? k, double? p, double? r,
        ReadOnlySpan<GWord> words, List<Diagnostic>? diags, int line, int column)
    {
        var here = ProgramPosition();
        _transform ??= new ProgramTransform();
        _programPos = here;
        var centre = new Point3(x ?? here.X, y ?? here.Y, z ?? here.Z);
        switch (key)
        {
            case 511:
                _transform.Mirror(x, y, z);
                break;
            case 510:
                var all = p is { } pv ? Factor('P', pv, words) : 1.0;
                _transform.Scale(centre, i is { } fi ? Factor('I', fi, words) : all, j is { } fj ? Factor('J', fj, words) : all, k is { } fk ? Factor('K', fk, words) : all);
                break;
            case 680:
                if (i.HasValue || j.HasValue || k.HasValue)
                {
                    Add(diags, DiagnosticCodes.TransformNotRunnable, line, column, "G68 I/J/K", "G68", "a rotation about an axis other than the plane's normal is not run", "不执行绕非平面法线轴的旋转");
                }

                _transform.Rotate(_plane, centre, r ?? 0);
                break;
        }

        if (!_transform.Active)
        {
            _transform = null;
        }

        _dirty = true;
    }

    /// <summary>A scaling factor as written: with a decimal point it is the factor, an integer is in thousandths (FANUC's least increment).</summary>
    private static double Factor(char letter, double value, ReadOnlySpan<GWord> words)
    {
        foreach (ref readonly var w in words)
        {
            if (w.Letter == letter)
            {
                return w.IsInteger ? value / 1000.0 : value;
            }
        }

        return value;
    }

    /// <summary>Where a move's words lead under the transformation: absolute from the untransformed position, incremental as a turned vector.</summary>
    private Point3 TransformedTarget(double? x, double? y, double? z)
    {
        var from = _programPos;
        var p = _absolute
            ? new Point3(x ?? from.X, y ?? from.Y, z ?? from.Z)
            : new Point3(from.X + (x ?? 0), from.Y + (y ?? 0), from.Z + (z ?? 0));
        return _transform!.Apply(p) + _coords.Active;
    }

    /// <summary>
    /// A canned cycle's words under the transformation (cycles drill along Z in G17): the hole's X Y turned, its R and
    /// Z levels scaled. Q (peck depth) is not scaled, as on FANUC.
    /// </summary>
    private (double? X, double? Y, double? Z, double? R) TransformCycleWords(double? x, double? y, double? z, double? r, List<Diagnostic>? diags, int line, int column)
    {
        var t = _transform!;
        if (_plane != 17 || t.TiltsPlane(17))
        {
            Add(diags, DiagnosticCodes.TransformNotRunnable, line, column, "canned cycle", "G68/G51", "cycles run in G17 under a rotation in the XY plane only", "旋转时固定循环只在 G17 与 XY 平面旋转下执行");
        }

        if (x.HasValue || y.HasValue)
        {
            var from = _programPos;
            if (_absolute)
            {
                var q = t.Apply(new Point3(x ?? from.X, y ?? from.Y, 0));
                (x, y) = (q.X, q.Y);
            }
            else
            {
                var d = t.ApplyVector(new Point3(x ?? 0, y ?? 0, 0));
                (x, y) = (d.X, d.Y);
            }
        }

        return _absolute ? (x, y, z is { } az ? t.ApplyZ(az) : null, r is { } ar ? t.ApplyZ(ar) : null)
            : (x, y, z * t.FactorZ, r * t.FactorZ);
    }

    /// <summary>
    /// An arc's centre words and direction under the transformation: I/J/K (or the absolute centre of G90.1) become the
    /// turned vector from the start, R the scaled radius; a mirror of one plane axis reverses the direction. Unequal
    /// scaling of the plane (an ellipse) and an arc out of the rotation's plane are refused (E129).
    /// </summary>
    private (double? I, double? J, double? K, double? R, bool Clockwise) TransformArc(bool cw, double? i, double? j, double? k, double? r,
        List<Diagnostic>? diags, int line, int column)
    {
        var t = _transform!;
        var (f1, f2) = t.PlaneFactors(_plane);
        if (Math.Abs(Math.Abs(f1) - Math.Abs(f2)) > 1e-12)
        {
            Add(diags, DiagnosticCodes.TransformNotRunnable, line, column, "G0" + (cw ? "2" : "3"), "G51",
                "the plane's axes are scaled unequally, the path would be an ellipse", "平面两轴缩放比例不同，轨迹将为椭圆");
        }

        if (t.TiltsPlane(_plane))
        {
            Add(diags, DiagnosticCodes.TransformNotRunnable, line, column, "G0" + (cw ? "2" : "3"), "G68",
                "the arc's plane is not the plane of the rotation", "圆弧平面不是旋转平面");
        }

        var reversed = f1 * f2 < 0;
        if (r is { } radius)
        {
            return (null, null, null, radius * Math.Abs(f1), cw ^ reversed);
        }

        if (!i.HasValue && !j.HasValue && !k.HasValue)
        {
            return (null, null, null, null, cw ^ reversed);
        }

        var from = _programPos;
        var v = _arcAbsolute
            ? new Point3(i is { } ai ? ai - from.X : 0, j is { } aj ? aj - from.Y : 0, k is { } ak ? ak - from.Z : 0)
            : new Point3(i ?? 0, j ?? 0, k ?? 0);
        var d = t.ApplyVector(v);
        return (d.X, d.Y, d.Z, null, cw ^ reversed);
    }
}
