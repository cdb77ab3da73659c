using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Program;

/// <summary>
/// Turns a block the interpreter marked as a host block (<see cref="Interpreter.HostBlock"/>) into the plain blocks a
/// Turbo PMAC with the generated library runs, all in millimetres and in the order the library's <c>READ</c> needs:
/// modes first, then data settings (each on its own line, its words right after its code), then the move, then the
/// stops. What is pure program syntax is converted here: inch values, absolute arc centres (G90.1), feed per
/// revolution and inverse time into a feed per minute, canned cycles and reference returns into the moves they make
/// (every one carrying the block's line), G92 and "from the current position" settings (G10 L20 of RS274/NGC, L10)
/// into the table values they give, T words into the tool M06 changes to. What the operator changes at the machine
/// (work offsets, tool lengths, reference positions) stays on the controller: the moves are in work coordinates and
/// machine-coordinate moves go through G53. Runs on the reading thread, right after the interpreter took the block.
/// </summary>
internal sealed class HostConversion
{
    /// <summary>The library's code that ends a G53 block: back to the work coordinates (PROG 1000 N53900).</summary>
    public const string BackFromMachineCoordinates = "G53.9";

    /// <summary>
    /// The library's code that puts the controller in the profile's power-on state (G54, no shifts, G49, G90: PROG
    /// 1000 N99900), sent before the program's first block so the controller starts where the interpreter does.
    /// </summary>
    public const string PowerOnState = "G99.9";

    /// <summary>The library's own exact stop (PROG 1000 N9900, DWELL0), for a profile without a G09 routine.</summary>
    public const string ExactStopCode = "G09.9";

    private readonly Interpreter _interp;
    private readonly MachineProfile _profile;
    private readonly List<HostMove> _moves = [];
    private readonly List<string> _lines = [];
    private readonly StringBuilder _sb = new(128);
    private readonly double?[] _given = new double?[26]; // the block's words by letter (the first of each)
    private Point3 _start;
    private Point3 _offsetBefore;
    private int _toolBefore;

    // The words of the move line as written (an inch program converts every move), so it is not lexed again.
    private readonly WrittenWords _moveWords = new();
    private int _moveLine = -1;
    private readonly List<string> _modes = [], _data = [], _before = [], _after = []; // a block's parts, reused

    public HostConversion(Interpreter interp)
    {
        _interp = interp;
        _profile = interp.Profile;
        interp.HostMoves = _moves;
    }

    /// <summary>Call before the interpreter takes a block: what the conversion needs of the state before it.</summary>
    public void Before()
    {
        _moves.Clear();
        _start = _interp.Position;
        _offsetBefore = _interp.ActiveOffset;
        _toolBefore = _interp.Tool;
    }

    /// <summary>
    /// The blocks to send instead of <paramref name="block"/> (which the interpreter just took), or null when it is
    /// not a host block and goes as it is.
    /// </summary>
    public IReadOnlyList<string>? Convert(GBlock block)
    {
        if (!_interp.HostBlock)
        {
            return null;
        }

        _lines.Clear();
        _moveLine = -1;
        var words = block.WordList;
        var (modes, data, before, after) = (Cleared(_modes), Cleared(_data), Cleared(_before), Cleared(_after));
        string? motionCode = null;
        var machine = false;
        var dwell = false;
        var cycleOrReference = _moves.Count > 0;
        double? x = null, y = null, z = null, a = null, b = null, c = null, i = null, j = null, k = null, r = null, f = null, p = null, s = null, l = null, h = null;
        var codes = new List<(char Letter, double Value)>();
        Array.Clear(_given);
        foreach (var w in words)
        {
            if (w.Letter is >= 'A' and <= 'Z' && _given[w.Letter - 'A'] is null)
            {
                _given[w.Letter - 'A'] = w.Value;
            }

            switch (w.Letter)
            {
                case 'G' or 'M': codes.Add((w.Letter, w.Value)); break;
                case 'X': x = w.Value; break;
                case 'Y': y = w.Value; break;
                case 'Z': z = w.Value; break;
                case 'A': a = w.Value; break;
                case 'B': b = w.Value; break;
                case 'C': c = w.Value; break;
                case 'I': i = w.Value; break;
                case 'J': j = w.Value; break;
                case 'K': k = w.Value; break;
                case 'R': r = w.Value; break;
                case 'F': f = w.Value; break;
                case 'P': p = w.Value; break;
                case 'S': s = w.Value; break;
                case 'L': l = w.Value; break;
                case 'H': h = w.Value; break;
            }
        }

        var scale = _interp.UnitScale;
        var hasAxes = x.HasValue || y.HasValue || z.HasValue || a.HasValue || b.HasValue || c.HasValue;
        var lengthCodeInBlock = false;
        var axisData = false; // a data code takes the block's axis words: nothing moves
        foreach (var (letter, value) in codes)
        {
            var key = (int)Math.Round(value * 10);
            if (letter == 'M')
            {
                var m = "M" + Code(value) + LibraryWords('M', value, scale);
                if (key == 60)
                {
                    // The tool change routine reads the tool it changes to.
                    after.Add($"{m} T{_interp.Tool.ToString(CultureInfo.InvariantCulture)}");
                }
                else if (key is 30 or 40 or 70 or 80 or 190 or 880)
                {
                    before.Add(m);
                }
                else
                {
                    after.Add(m);
                }

                continue;
            }

            switch (key)
            {
                case 0 or 10 or 20 or 30:
                    motionCode = "G" + Code(value);
                    break;
                case 40:
                    dwell = true;
                    break;
                case 530:
                    machine = true;
                    break;
                case 100:
                    axisData = true;
                    data.AddRange(TableSettings(l, p));
                    break;
                case 520:
                    axisData = true;
                    data.Add("G52" + Axes(x, y, z, scale, _interp.Coordinates.Local, all: false));
                    break;
                case 920:
                    axisData = true;
                    data.Add("G92" + Axes(x, y, z, 1.0, _interp.Coordinates.Shift, all: false, fromResult: true));
                    break;
                case 921 or 922:
                    data.Add("G92.1");
                    break;
                case 430 or 440 or 490:
                    lengthCodeInBlock = true;
                    break;
                case 541 or 1540:
                    modes.Add("G54.1 P" + Num(p ?? 1));
                    break;
                // Pure program syntax the host has already applied: units, arc centre mode, cycles and their return
                // levels, reference returns (their moves follow), feed modes (feeds are sent per minute).
                case 200 or 210 or 901 or 911 or 800 or 980 or 990 or 270 or 280 or 290 or 300 or 930 or 940 or 950:
                    break;
                // Mirror, scaling and rotation are in the positions sent; exact stop mode and G09 are a G09 after the move.
                case 510 or 511 or 680:
                    axisData = true;
                    break;
                case 500 or 501 or 690 or 610 or 90:
                    break;
                // Cutter radius compensation is in the positions sent (CompensatedMoves).
                case 410 or 420:
                    break;
                case >= 730 and <= 890 when CodeIsCycle(key):
                    break;
                default:
                    // Codes that take the block's axis words as data (scaling, rotation, macro calls...) never move.
                    axisData |= CodeRoles.OfG(key) == GRole.AxisData;
                    modes.Add("G" + Code(value) + LibraryWords('G', value, scale));
                    break;
            }
        }

        if (lengthCodeInBlock || (h.HasValue && _interp.LengthMode != 0))
        {
            data.Add(_interp.LengthMode == 0 ? "G49" : $"G{_interp.LengthMode} H{_interp.LengthOffsetNumber.ToString(CultureInfo.InvariantCulture)}");
        }

        if (s is { } sv)
        {
            before.Insert(0, "S" + Num(sv));
        }

        if (modes.Count > 0)
        {
            _lines.Add(string.Join(' ', modes));
        }

        Add(before);
        Add(data);
        var feed = FeedPerMinute(f);
        if (dwell)
        {
            _lines.Add("G04 P" + Num(DwellP(p, x)));
        }
        else if (cycleOrReference)
        {
            Expand(feed);
        }
        else if (axisData)
        {
            // The axis words were the data settings' values (G10, G52, G92).
        }
        else if (_interp.CompensatedMove)
        {
            CompensatedMoves.Write(_lines, _interp, _start, feed);
        }
        else if (_interp.Transforming && !machine && (hasAxes || (motionCode is "G02" or "G03" || _interp.MotionCode is 2 or 3) && (i.HasValue || j.HasValue || k.HasValue)))
        {
            TransformedMove(a, b, c, feed);
        }
        else if (hasAxes || (motionCode is "G02" or "G03" || _interp.MotionCode is 2 or 3) && (i.HasValue || j.HasValue || k.HasValue))
        {
            _sb.Clear();
            _moveWords.Begin();
            if (machine)
            {
                AppendCode("G53");
            }

            if (motionCode != null)
            {
                AppendCode(motionCode);
            }

            AppendAxes(x, y, z, scale);
            AppendWord('A', a);
            AppendWord('B', b);
            AppendWord('C', c);
            if (_interp.MotionCode is 2 or 3)
            {
                if (r is { } rv && !ShortRadius(rv * scale))
                {
                    AppendWord('R', rv * scale);
                }
                else if (r.HasValue && _interp.LastArc.Centre is { } mid)
                {
                    // An R a rounding short of half the chord runs as the half circle on the chord (rs274ngc's
                    // arc_data_r): its centre is sent, since a PMAC given the short R would spiral (Isx96).
                    var v = mid - _start;
                    var plane = _interp.State.Plane;
                    AppendWord('I', plane is 17 or 18 ? v.X : null);
                    AppendWord('J', plane is 17 or 19 ? v.Y : null);
                    AppendWord('K', plane is 18 or 19 ? v.Z : null);
                }
                else if (_interp.ArcCentresAbsolute)
                {
                    // G90.1: the PMAC's centre vector is incremental from the start (its default INC(R)).
                    var startProgram = _start - _offsetBefore;
                    AppendWord('I', i is { } iv ? (iv * scale) - startProgram.X : null);
                    AppendWord('J', j is { } jv ? (jv * scale) - startProgram.Y : null);
                    AppendWord('K', k is { } kv ? (kv * scale) - startProgram.Z : null);
                }
                else
                {
                    AppendWord('I', i * scale);
                    AppendWord('J', j * scale);
                    AppendWord('K', k * scale);
                }
            }

            if (feed is { } fv)
            {
                AppendWord('F', fv);
            }

            _lines.Add(_sb.Length > 0 && _sb[^1] == ' ' ? _sb.ToString(0, _sb.Length - 1) : _sb.ToString()); // less the blank after the last word
            _moveLine = _moveWords.End() ? _lines.Count - 1 : -1;
            if (machine)
            {
                _lines.Add(BackFromMachineCoordinates);
            }
        }
        else if (motionCode != null)
        {
            _lines.Add(motionCode + (feed is { } fv ? " F" + Num(fv) : string.Empty));
        }
        else if (feed is { } fv)
        {
            _lines.Add("F" + Num(fv));
        }

        if (_interp.ExactStopBlock)
        {
            // The library's G09 (DWELL0) after the move: the move decelerates to rest before the next one starts. A
            // profile without a G09 routine (grbl) has the library's own G09.9.
            _lines.Add(_profile.Find('G', 9) is { Controller: ControllerSupport.Library } g09 ? g09.Code : ExactStopCode);
        }

        Add(after);
        return _lines;
    }

    /// <summary>
    /// A move under mirror, scaling or rotation: the interpreter's end point in work coordinates (absolute, whatever the
    /// distance mode), an arc's centre as the PMAC's incremental vector from the start, the direction it really runs.
    /// </summary>
    private void TransformedMove(double? a, double? b, double? c, double? feed)
    {
        var incremental = !_interp.AbsoluteMode;
        if (incremental)
        {
            _lines.Add("G90");
        }

        var mode = _interp.MotionCode;
        var end = _interp.Position - _interp.ActiveOffset;
        _sb.Clear();
        var sent = mode;
        if (mode is 2 or 3 && _interp.LastArc is { Centre: not null } arc)
        {
            sent = arc.Clockwise ? 2 : 3;
        }

        if (sent is >= 0 and <= 3)
        {
            _sb.Append("G0").Append(sent.ToString(CultureInfo.InvariantCulture)).Append(' ');
        }

        AppendAxes(end.X, end.Y, end.Z, 1.0);
        AppendWord('A', a);
        AppendWord('B', b);
        AppendWord('C', c);
        if (sent is 2 or 3 && _interp.LastArc.Centre is { } at)
        {
            var v = at - _start;
            var plane = _interp.State.Plane;
            AppendWord('I', plane is 17 or 18 ? v.X : null);
            AppendWord('J', plane is 17 or 19 ? v.Y : null);
            AppendWord('K', plane is 18 or 19 ? v.Z : null);
        }

        if (feed is { } fv)
        {
            AppendWord('F', fv);
        }

        _lines.Add(_sb.ToString().TrimEnd());
        if (incremental)
        {
            _lines.Add("G91");
        }

        if (sent != mode && mode is >= 0 and <= 3)
        {
            // A mirrored arc ran the other way: the program's motion mode comes back for the blocks that follow.
            _lines.Add("G0" + mode.ToString(CultureInfo.InvariantCulture));
        }
    }

    private static bool CodeIsCycle(int key) => key is 730 or 740 or 760 or 810 or 820 or 830 or 840 or 850 or 860 or 870 or 880 or 890;

    private void Add(List<string> lines)
    {
        foreach (var line in lines)
        {
            _lines.Add(line);
        }
    }

    /// <summary>A cycle's holes or a reference return as plain moves in work coordinates (absolute while they run).</summary>
    private void Expand(double? feed)
    {
        var offset = _interp.ActiveOffset;
        var incremental = !_interp.AbsoluteMode;
        if (incremental)
        {
            _lines.Add("G90");
        }

        var mode = -1;
        var feedSent = false;
        foreach (var m in _moves)
        {
            switch (m.Kind)
            {
                case HostMoveKind.Rapid or HostMoveKind.Feed:
                    var target = m.Target - offset;
                    _sb.Clear();
                    var code = m.Kind == HostMoveKind.Rapid ? 0 : 1;
                    if (code != mode)
                    {
                        _sb.Append(code == 0 ? "G00 " : "G01 ");
                        mode = code;
                    }

                    AppendAxes((m.Axes & 1) != 0 ? target.X : null, (m.Axes & 2) != 0 ? target.Y : null, (m.Axes & 4) != 0 ? target.Z : null, 1.0);
                    if (code == 1 && !feedSent && (feed ?? FeedPerMinute(_interp.FeedValue)) is { } fv)
                    {
                        AppendWord('F', fv);
                        feedSent = true;
                    }

                    _lines.Add(_sb.ToString().TrimEnd());
                    break;
                case HostMoveKind.MachineRapid:
                    _sb.Clear();
                    _sb.Append("G53 G00 ");
                    mode = 0;
                    AppendAxes((m.Axes & 1) != 0 ? m.Target.X : null, (m.Axes & 2) != 0 ? m.Target.Y : null, (m.Axes & 4) != 0 ? m.Target.Z : null, 1.0);
                    _lines.Add(_sb.ToString().TrimEnd());
                    _lines.Add(BackFromMachineCoordinates);
                    break;
                case HostMoveKind.Dwell:
                    _lines.Add("G04 P" + Num(_profile.DwellPInMilliseconds ? m.Seconds * 1000 : m.Seconds));
                    break;
                case HostMoveKind.SpindleStop:
                    _lines.Add(SpindleCode(5));
                    break;
                case HostMoveKind.SpindleForward:
                    _lines.Add(SpindleCode(3));
                    break;
                case HostMoveKind.SpindleReverse:
                    _lines.Add(SpindleCode(4));
                    break;
                case HostMoveKind.SpindleOrient:
                    _lines.Add(SpindleCode(19));
                    break;
            }
        }

        if (incremental)
        {
            _lines.Add("G91");
        }

        // The controller's motion mode is modal: the program's own mode in force comes back after the expansion.
        if (_interp.MotionCode is >= 0 and <= 3 && _interp.MotionCode != mode)
        {
            _lines.Add("G0" + _interp.MotionCode.ToString(CultureInfo.InvariantCulture));
        }
    }

    /// <summary>
    /// The words a library routine reads (the profile's <c>words</c> of the code), as the block gave them, to go right
    /// after the code: <c>READ</c> takes the letters that follow the call, so a word left out or sent elsewhere on the
    /// line would be lost or run as a statement. Lengths among them are sent in millimetres like everything else.
    /// </summary>
    private string LibraryWords(char letter, double value, double scale)
    {
        if (_profile.Find(letter, value) is not { Controller: ControllerSupport.Library, Words.Length: > 0 } def)
        {
            return string.Empty;
        }

        var key = (int)Math.Round(value * 10);
        var text = new StringBuilder();
        foreach (var c in def.Words)
        {
            if (_given[c - 'A'] is { } v)
            {
                text.Append(' ').Append(c).Append(Num(letter == 'G' && CodeRoles.WordIsLength(key, c) ? v * scale : v));
            }
        }

        return text.ToString();
    }

    /// <summary>The profile's spelling of a spindle M code (M3 or M03).</summary>
    private string SpindleCode(int code) =>
        _profile.Find('M', code)?.Code ?? "M" + code.ToString("00", CultureInfo.InvariantCulture);

    /// <summary>G10 as the library takes it: the resulting table entry, absolute, in millimetres.</summary>
    private IEnumerable<string> TableSettings(double? l, double? p)
    {
        var coords = _interp.Coordinates;
        switch (l)
        {
            case 2 when p is 0 && _profile.ExternalWorkOffset:
                // FANUC's external work offset: index 0 of the library's table, which its displacement adds to every offset.
                yield return ControllerState.ExternalOffset(coords.External);
                break;
            case 2 or 20:
                var extended = l == 20 && _profile.ExtendedWorkOffsets;
                var n = (int)(p ?? 0);
                var key = extended ? 5410 + n : n == 0 ? coords.Selected : n <= 6 ? 530 + (n * 10) : 590 + (n - 6);
                yield return ControllerState.WorkOffset(key, coords.OffsetOf(key));
                break;
            case 1 or 10 or 11 when p is { } t:
                yield return ControllerState.ToolLength((int)t, coords.LengthOf((int)t));
                break;
        }
    }

    /// <summary>The library's work offset table index: 1-6 G54-G59, 7-9 G59.1-G59.3, 10 and up the extended ones (G54.1 P1 = 10).</summary>
    public static int WorkOffsetIndex(int key) => key switch
    {
        >= 5410 => key - 5410 + 9,
        591 or 592 or 593 => key - 584,
        _ => (key - 530) / 10,
    };

    private double? FeedPerMinute(double? f)
    {
        var feed = f ?? (_interp.FeedMode != 94 ? _interp.FeedValue : null);
        if (feed is not { } fv)
        {
            return null;
        }

        return _interp.FeedMode switch
        {
            // Per revolution: at the spindle speed in force.
            95 => fv * _interp.UnitScale * _interp.State.SpindleSpeed,
            // Inverse time: the move takes 1/F minutes, so its feed is its length times F.
            93 => _interp.InverseTimeLength * fv,
            _ => fv * _interp.UnitScale,
        };
    }

    /// <summary>G04's P in the profile's dwell unit, from P or from X (seconds).</summary>
    private double DwellP(double? p, double? x) =>
        p ?? (x is { } seconds ? (_profile.DwellPInMilliseconds ? seconds * 1000 : seconds) : 0);

    /// <summary>The axes given, as data words: scaled values, or with <paramref name="fromResult"/> the resulting values from <paramref name="result"/>.</summary>
    private static string Axes(double? x, double? y, double? z, double scale, Point3 result, bool all, bool fromResult = false)
    {
        var sb = new StringBuilder();
        if (x.HasValue || all)
        {
            sb.Append(" X").Append(Num(fromResult ? result.X : x!.Value * scale));
        }

        if (y.HasValue || all)
        {
            sb.Append(" Y").Append(Num(fromResult ? result.Y : y!.Value * scale));
        }

        if (z.HasValue || all)
        {
            sb.Append(" Z").Append(Num(fromResult ? result.Z : z!.Value * scale));
        }

        return sb.ToString();
    }

    private void AppendAxes(double? x, double? y, double? z, double scale)
    {
        AppendWord('X', x * scale);
        AppendWord('Y', y * scale);
        AppendWord('Z', z * scale);
    }

    private void AppendWord(char letter, double? value)
    {
        if (value is { } v)
        {
            var at = _sb.Length;
            _sb.Append(letter);
            WrittenWords.AppendNumber(_sb, v);
            _moveWords.Record(_sb, at);
            _sb.Append(' ');
        }
    }

    private static List<string> Cleared(List<string> list)
    {
        list.Clear();
        return list;
    }

    private void AppendCode(string code)
    {
        var at = _sb.Length;
        _sb.Append(code);
        _moveWords.Record(_sb, at);
        _sb.Append(' ');
    }

    /// <summary>
    /// The words of converted line <paramref name="index"/> when the conversion recorded them as it wrote the line
    /// (the move), exactly as the lexer reads its text; false: the line must be lexed.
    /// </summary>
    public bool TryWordsOf(int index, out ReadOnlySpan<GWord> words)
    {
        words = index == _moveLine ? _moveWords.Words : default;
        return index == _moveLine;
    }

    /// <summary>A code number as G-code writes it (01, 54.1).</summary>
    private static string Code(double value) =>
        (value < 10 ? "0" : string.Empty) + value.ToString("0.###", CultureInfo.InvariantCulture);

    /// <summary>A millimetre value to the micrometre's thousandth (the controller compares within 0.001 mm).</summary>
    public static string Num(double v)
    {
        var text = Math.Round(v, 6).ToString("0.######", CultureInfo.InvariantCulture);
        return text == "-0" ? "0" : text;
    }

    /// <summary>True when the interpreter placed this R arc's centre further from the start than R: R was short of half the chord.</summary>
    private bool ShortRadius(double radius)
    {
        if (_interp.LastArc.Centre is not { } c)
        {
            return false;
        }

        var v = c - _start;
        var (a, b) = _interp.State.Plane switch { 18 => (v.Z, v.X), 19 => (v.Y, v.Z), _ => (v.X, v.Y) };
        return Math.Sqrt((a * a) + (b * b)) > Math.Abs(radius) + 1e-9;
    }
}
