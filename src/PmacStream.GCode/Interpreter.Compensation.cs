namespace PmacStream.GCode;

/// <summary>
/// Cutter radius compensation (G40/G41/G42): the interpreter's positions are the compensated tool positions, so the
/// preview, the ETA, the position proof and the moves the host sends all share them. The radius comes from the
/// profile's <c>toolRadii</c> (FANUC: by the D number in force, set again by <c>G10 L12/L13</c>; RS274/NGC: by the tool
/// number D names, else the tool in the spindle, set again by <c>G10 L1 R</c>).
/// </summary>
public sealed partial class Interpreter
{
    private readonly CutterCompensation _comp = new();
    private readonly Dictionary<int, double> _radiusSet = new();  // radii the program set with G10, by D (or tool) number
    private readonly Dictionary<int, double> _radiusWear = new(); // FANUC G10 L13 wear, by D number
    private int _compRequest = -1;  // 40, 41 or 42 when the block's G code changes the compensation
    private CompensationCorner? _corner;
    private bool _compensated;
    private Point3? _amended; // the block's inside corner: where the move before it ends instead (CanonBlock.AmendedEnd)
    private bool _taken;      // the last line was a block (not a comment or label line): the hold's decision is its own

    /// <summary>Blocks after a compensated move within which an inside corner still moves its end back (a sender holds it that long at most).</summary>
    public const int MaxHeldCompensationBlocks = CutterCompensation.MaxHeldBlocks;

    /// <summary>The last block's inside corner under compensation: where the compensated move before it ends instead of its reported end; null for other blocks.</summary>
    internal Point3? AmendedEnd => _amended; // consumers read CanonBlock.AmendedEnd; the compensation tests read it here

    /// <summary>The last block's part in the hold under G41/G42 (<see cref="CanonBlock.Hold"/>).</summary>
    public CompensationHold HoldOfBlock => _comp.Active ? _comp.HoldOfBlock : CompensationHold.None;

    /// <summary>The last block's move was compensated: the host sends the interpreter's positions, not the block's words.</summary>
    internal bool CompensatedMove => _compensated;

    /// <summary>The corner the last compensated move went around first, null when it went straight.</summary>
    internal CompensationCorner? LastCorner => _corner;

    /// <summary>True while G41/G42 is in force with a radius above zero.</summary>
    internal bool Compensating => _comp.Active;

    /// <summary>G10 L12/L13 (FANUC) or L1/L10 with R (RS274/NGC): a cutter radius the program sets.</summary>
    private void SetRadius(double? l, double? p, double? r)
    {
        if (p is not { } n || r is not { } value)
        {
            return;
        }

        var index = (int)n;
        if (_profile.ExtendedWorkOffsets && l is 12 or 13)
        {
            (l == 12 ? _radiusSet : _radiusWear)[index] = value;
        }
        else if (!_profile.ExtendedWorkOffsets && l is 1 or 10)
        {
            _radiusSet[index] = value;
        }
    }

    /// <summary>The radius of offset (or tool) <paramref name="index"/>: the program's setting, else the profile's table; null when neither has it.</summary>
    private double? RadiusOf(int index)
    {
        if (index == 0)
        {
            return 0; // D0: no offset
        }

        var geometry = _radiusSet.TryGetValue(index, out var set) ? set : _profile.ToolRadius(index);
        return geometry is { } g ? g + (_radiusWear.TryGetValue(index, out var wear) ? wear : 0) : null;
    }

    /// <summary>After the block's G codes and values: G40/G41/G42 take effect, with the radius they name.</summary>
    private void UpdateCompensation(bool dInBlock, List<Diagnostic>? diags, int line, int column)
    {
        var request = _compRequest;
        _compRequest = -1;
        if (request < 0)
        {
            if (dInBlock && _comp.Active)
            {
                Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, "D", "the radius changes only with G40 between", "半径只能在 G40 之后改变");
            }

            return;
        }

        if (request == 40)
        {
            _comp.Set(0, 0);
            return;
        }

        var code = "G" + request.ToString(System.Globalization.CultureInfo.InvariantCulture);
        if (_comp.Active)
        {
            Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, code, "compensation is already on: G40 first", "补偿已经打开：应先 G40");
            return;
        }

        // FANUC: the D number in force; RS274/NGC: the tool D names, else the tool in the spindle.
        var index = _profile.ExtendedWorkOffsets || dInBlock ? _d : _tool;
        var radius = RadiusOf(index);
        if (radius is null)
        {
            var what = (_profile.ExtendedWorkOffsets || dInBlock ? "D" : "tool ") + index.ToString(System.Globalization.CultureInfo.InvariantCulture);
            Add(diags, DiagnosticCodes.NoCutterRadius, line, column, code, what, _profile.Name);
        }

        _comp.Set(request, radius ?? 0);
        if (_comp.Active && (_plane != 17 || _transform != null))
        {
            Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, code, _plane != 17 ? "compensation runs in the XY plane (G17) only" : "mirror, scaling and rotation are not compensated",
                _plane != 17 ? "补偿只在 XY 平面（G17）执行" : "镜像、缩放和旋转下不执行补偿");
        }
    }

    /// <summary>
    /// The compensated end of a straight move (G00/G01) to the programmed <paramref name="target"/> and the length of
    /// its corner, when compensation is on; reports what cannot be compensated.
    /// </summary>
    private (Point3 End, double CornerLength) Compensate(Point3 start, Point3 target, int mode, bool rotary, List<Diagnostic>? diags, int line, int column)
    {
        if (_comp.Lost)
        {
            return (target, 0);
        }

        if (mode is not (0 or 1) || rotary || _plane != 17 || _transform != null)
        {
            var (what, en, zh) = rotary ? ("A/B/C", "a rotary axis move is not compensated", "不补偿旋转轴运动")
                : mode is 0 or 1 ? ("G0" + mode.ToString(System.Globalization.CultureInfo.InvariantCulture), "compensation runs in the XY plane (G17) without mirror, scaling or rotation only", "补偿只在无镜像、缩放、旋转的 XY 平面（G17）执行")
                : ("move", "only G00 and G01 are compensated", "只补偿 G00 和 G01");
            Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, what, en, zh);
            _comp.Lose();
            return (target, 0);
        }

        var (end, corner, fault) = _comp.Line(start, target, mode == 0, line);
        switch (fault)
        {
            case CompensationFault.EntryTooShort:
                Add(diags, DiagnosticCodes.CompensationEntryTooShort, line, column, ModalState.Num(_comp.Radius));
                return (target, 0);
            case CompensationFault.ConcaveCorner:
                ConcaveCorner(diags, line, column);
                _comp.Lose();
                return (end, 0);
        }

        (_corner, _compensated, _amended) = (corner, true, _comp.Amend);
        return corner is { } c ? (end, _comp.CornerLength(start, c) + c.Mid.DistanceTo(end) - start.DistanceTo(end)) : (end, 0);
    }

    /// <summary>
    /// The compensated end of an arc about the programmed <paramref name="centre"/> and its length (the corner's, then
    /// the offset arc's), when compensation is on; reports what cannot be compensated.
    /// </summary>
    private (Point3 End, double Length) CompensateArc(Point3 start, Point3 target, Point3? centre, bool clockwise, double length, bool rotary, List<Diagnostic>? diags, int line, int column)
    {
        var code = clockwise ? "G02" : "G03";
        if (_comp.Lost || centre is not { } c)
        {
            return (target, length);
        }

        if (rotary || _plane != 17 || _transform != null)
        {
            Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, rotary ? "A/B/C" : code,
                rotary ? "a rotary axis move is not compensated" : "compensation runs in the XY plane (G17) without mirror, scaling or rotation only",
                rotary ? "不补偿旋转轴运动" : "补偿只在无镜像、缩放、旋转的 XY 平面（G17）执行");
            _comp.Lose();
            return (target, length);
        }

        var (end, corner, fault) = _comp.Arc(start, target, c, clockwise, line);
        if (fault != CompensationFault.None)
        {
            var (en, zh) = fault switch
            {
                CompensationFault.StartOnArc => ("compensation cannot start on an arc: enter with a straight move", "补偿不能从圆弧开始：请用直线引入"),
                CompensationFault.ArcTooSmall => ($"the cutter runs inside an arc whose radius is not larger than the cutter radius ({ModalState.Num(_comp.Radius)} mm)", $"刀具在半径不大于刀具半径（{ModalState.Num(_comp.Radius)} mm）的圆弧内侧"),
                CompensationFault.FullCircle => ("a full circle is not compensated", "不补偿整圆"),
                _ => (string.Empty, string.Empty),
            };
            if (fault == CompensationFault.ConcaveCorner)
            {
                ConcaveCorner(diags, line, column);
            }
            else
            {
                Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, code, en, zh);
            }

            _comp.Lose();
            return (fault == CompensationFault.ConcaveCorner ? end : target, length);
        }

        (_corner, _compensated, _amended) = (corner, true, _comp.Amend);
        var programmedRadius = Math.Sqrt(((target.X - c.X) * (target.X - c.X)) + ((target.Y - c.Y) * (target.Y - c.Y)));
        var compensatedRadius = Math.Sqrt(((end.X - c.X) * (end.X - c.X)) + ((end.Y - c.Y) * (end.Y - c.Y)));
        var arc = programmedRadius > 0 ? length * compensatedRadius / programmedRadius : length;
        if (_amended is { } from)
        {
            // From the crossing of the offset paths: the same circle, a shorter (or longer) sweep.
            arc = Sweep(from, end, c, clockwise, length / Math.Max(programmedRadius, 1e-12)) * compensatedRadius;
        }

        return (end, corner is { } k ? _comp.CornerLength(start, k) + arc : arc);
    }

    /// <summary>E135: the offset paths do not cross, or the move the corner ends lies beyond the hold's bound (named by its line).</summary>
    private void ConcaveCorner(List<Diagnostic>? diags, int line, int column)
    {
        if (_comp.HeldTooFar is { } held)
        {
            diags?.Add(new Diagnostic(Severity.Error, DiagnosticCodes.CompensationConcaveCorner, line, column,
                DiagnosticText.Format(DiagnosticText.HeldTooFarKey, held, CutterCompensation.MaxHeldBlocks)));
        }
        else
        {
            Add(diags, DiagnosticCodes.CompensationConcaveCorner, line, column);
        }
    }

    /// <summary>The sweep from <paramref name="from"/> to <paramref name="to"/> about <paramref name="centre"/> in the arc's sense, the nearest to <paramref name="programmed"/> radians (a full turn more or less).</summary>
    private static double Sweep(Point3 from, Point3 to, Point3 centre, bool clockwise, double programmed)
    {
        var a0 = Math.Atan2(from.Y - centre.Y, from.X - centre.X);
        var a1 = Math.Atan2(to.Y - centre.Y, to.X - centre.X);
        var sweep = clockwise ? a0 - a1 : a1 - a0;
        sweep += sweep < 0 ? 2 * Math.PI : 0;
        return Math.Abs(sweep + (2 * Math.PI) - programmed) < Math.Abs(sweep - programmed) ? sweep + (2 * Math.PI) : sweep;
    }

    /// <summary>A move compensation does not take (a cycle, a reference return, G53) while it is on.</summary>
    private void RefuseUnderCompensation(string what, List<Diagnostic>? diags, int line, int column)
    {
        if (_comp.Active && !_comp.Lost)
        {
            Add(diags, DiagnosticCodes.CompensationNotRunnable, line, column, what, "only G00 and G01 are compensated; G40 first", "只补偿 G00 和 G01：应先 G40");
            _comp.Lose();
        }
    }
}
