using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// Turns a block the interpreter marked as a host block (<see cref="CanonBlock.Host"/>) into the plain blocks a
/// Turbo PMAC with the generated library runs, all in millimetres and in the order the library's <c>READ</c> needs:
/// modes first, then data settings (each on its own line, its words right after its code), then the move, then the
/// stops. What is pure program syntax is converted here: inch values, absolute arc centres (G90.1), feed per
/// revolution and inverse time into a feed per minute, canned cycles and reference returns into the moves they make
/// (every one carrying the block's line), G92 and "from the current position" settings (G10 L20 of RS274/NGC, L10)
/// into the table values they give, T words into the tool M06 changes to. What the operator changes at the machine
/// (work offsets, tool lengths, reference positions) stays on the controller: the moves are in work coordinates and
/// machine-coordinate moves go through G53. It is the interpreter's canonical sink (<see cref="ICanonicalMoves"/>):
/// it reads nothing but the interpreter's calls for the line (the codes the line wrote, in order, its settings, the
/// steps of its cycle or reference return, the <see cref="CanonBlock"/>), and writes the block when the interpreter
/// ends it. Runs on the reading thread.
/// </summary>
internal sealed class HostConversion : ICanonicalMoves
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

    private readonly MachineProfile _profile;
    private readonly List<HostMove> _moves = [];
    private readonly List<string> _lines = [];
    private readonly StringBuilder _sb = new(128);
    private CanonStart _before;  // the state the line started from (ICanonicalMoves.StartBlock)
    private CanonBlock _block;   // what the interpreter decided for it (ICanonicalMoves.EndBlock)
    private List<string>? _converted; // the lines of the block taken last, when it is a host block (TakeLines)

    // The line's calls, as they came (ICanonicalMoves.SelectTool ... Code), until EndBlock writes the block from them.
    private double? _feedWord;   // SET_FEED_RATE: the line's F, in program units
    private double? _speedWord;  // SET_SPINDLE_SPEED: the line's S
    private double? _dwell;      // DWELL: seconds
    private string? _lengthLine; // USE_TOOL_LENGTH_OFFSET, as the library takes it

    // The words of the move line as written (an inch program converts every move), so it is not lexed again.
    private readonly WrittenWords _moveWords = new();
    private int _moveLine = -1;
    private int _heldLine = -1;  // the line of the converted block that ends its compensated move

    /// <summary>
    /// The index, in the lines <see cref="TakeLines"/> returned last, of the line ending a compensated move: the sender
    /// holds it while the interpreter holds the move (<see cref="CanonBlock.Hold"/>), since an inside corner at the next
    /// XY move moves it to the crossing (<see cref="MovedLine"/>); -1 when the block has none.
    /// </summary>
    public int HeldMoveLine => _heldLine;

    /// <summary>What the interpreter decided for the line taken last: its part in the hold under G41/G42, its inside corner.</summary>
    public CanonBlock Block => _block;

    /// <summary>
    /// A move line <see cref="HeldMoveLine"/> named, written in work offset <paramref name="offset"/>, moved on X and Y to
    /// the <paramref name="crossing"/> of an inside corner (machine coordinates, <see cref="CanonBlock.AmendedEnd"/>):
    /// the held move's end, or a plunge or retract queued behind it.
    /// </summary>
    public static string MovedLine(string line, Point3 crossing, Point3 offset) => CompensatedMoves.MoveEndTo(line, crossing - offset);

    private readonly List<string> _modes = [], _data = [], _stopsBefore = [], _after = []; // a block's parts, reused

    /// <summary>Converts what <paramref name="interp"/> decides: it becomes the interpreter's canonical move sink.</summary>
    public HostConversion(Interpreter interp)
    {
        _profile = interp.Profile;
        interp.Canon = this;
    }

    /// <summary>
    /// The blocks to send instead of the line the interpreter took last, or null when it is not a host block and goes
    /// as it is (or no line was taken since the last call): the conversion is written as the interpreter ends the
    /// line (<see cref="ICanonicalMoves.EndBlock"/>), from its calls alone.
    /// </summary>
    public IReadOnlyList<string>? TakeLines()
    {
        var lines = _converted;
        _converted = null;
        return lines;
    }

    /// <summary>The block, written from the interpreter's calls: modes, stops before the move, data, the move, exact stop, codes after.</summary>
    private void Write()
    {
        _lines.Clear();
        _moveLine = -1;
        _heldLine = -1;
        if (_lengthLine != null)
        {
            _data.Add(_lengthLine);
        }

        if (_speedWord is { } sv)
        {
            _stopsBefore.Insert(0, "S" + Num(sv));
        }

        if (_modes.Count > 0)
        {
            _lines.Add(string.Join(' ', _modes));
        }

        Add(_stopsBefore);
        Add(_data);
        WriteMotion(FeedPerMinute(_feedWord));
        if (_block.ExactStop)
        {
            // The library's G09 (DWELL0) after the move: the move decelerates to rest before the next one starts. A
            // profile without a G09 routine (grbl) has the library's own G09.9.
            _lines.Add(_profile.Find('G', 9) is { Controller: ControllerSupport.Library } g09 ? g09.Code : ExactStopCode);
        }

        Add(_after);
    }

    /// <summary>A code as the controller gets it: the code (M03, G54.1), then the words its library routine reads.</summary>
    private static string CodeText(in CanonCode code)
    {
        var text = code.Letter + Code(code.Number);
        if (code.Words.IsEmpty)
        {
            return text;
        }

        var sb = new StringBuilder(text);
        foreach (var w in code.Words)
        {
            sb.Append(' ').Append(w.Letter).Append(Num(w.Value));
        }

        return sb.ToString();
    }

    void ICanonicalMoves.StartBlock(in CanonStart start)
    {
        _moves.Clear();
        _before = start;
        _converted = null;
        (_feedWord, _speedWord, _dwell, _lengthLine) = (null, null, null, null);
        _modes.Clear();
        _data.Clear();
        _stopsBefore.Clear();
        _after.Clear();
    }

    void ICanonicalMoves.Step(in HostMove step) => _moves.Add(step);

    void ICanonicalMoves.Motion(in CanonMotion motion)
    {
        // The block's own motion is written from its decisions (EndBlock).
    }

    void ICanonicalMoves.EndBlock(in CanonBlock block)
    {
        _block = block;
        if (block.Host)
        {
            Write();
            _converted = _lines;
        }
    }

    void ICanonicalMoves.SetFeedRate(double feed) => _feedWord = feed;

    void ICanonicalMoves.SetSpindleSpeed(double speed) => _speedWord = speed;

    void ICanonicalMoves.Dwell(double seconds) => _dwell = seconds;

    // Spindle and coolant on before the move (the library's routines wait for them); stops, offs and changes after it.
    void ICanonicalMoves.Spindle(SpindleCall call, in CanonCode code) => (call == SpindleCall.Stop ? _after : _stopsBefore).Add(CodeText(code));

    void ICanonicalMoves.Coolant(CoolantCall call, in CanonCode code) =>
        (call is CoolantCall.Mist or CoolantCall.Flood or CoolantCall.ThroughTool ? _stopsBefore : _after).Add(CodeText(code));

    void ICanonicalMoves.ProgramStop(ProgramStopCall call, in CanonCode code) => _after.Add(CodeText(code));

    // The tool change routine reads the tool it changes to.
    void ICanonicalMoves.ChangeTool(int tool, in CanonCode code) => _after.Add($"{CodeText(code)} T{tool.ToString(CultureInfo.InvariantCulture)}");

    void ICanonicalMoves.Code(in CanonCode code) => (code.Letter == 'M' ? _after : _modes).Add(CodeText(code));

    void ICanonicalMoves.SelectExtendedWorkOffset(int number) => _modes.Add("G54.1 P" + number.ToString(CultureInfo.InvariantCulture));

    void ICanonicalMoves.UseToolLengthOffset(int mode, int number) =>
        _lengthLine = mode == 0 ? "G49" : $"G{mode} H{number.ToString(CultureInfo.InvariantCulture)}";

    // G10, G52 and G92 as the library takes them: the resulting table entry or shift, absolute, in millimetres.
    void ICanonicalMoves.SetWorkOffset(int key, Point3 offset) => _data.Add(ControllerState.WorkOffset(key, offset));

    void ICanonicalMoves.SetExternalOffset(Point3 offset) => _data.Add(ControllerState.ExternalOffset(offset));

    void ICanonicalMoves.SetToolLength(int tool, double length) => _data.Add(ControllerState.ToolLength(tool, length));

    void ICanonicalMoves.SetLocalShift(double? x, double? y, double? z) => _data.Add("G52" + Axes(x, y, z));

    void ICanonicalMoves.SetShift(double? x, double? y, double? z) => _data.Add("G92" + Axes(x, y, z));

    void ICanonicalMoves.CancelShift() => _data.Add("G92.1");

    /// <summary>The block's motion as the controller runs it: a dwell, the interpreter's steps, a compensated, transformed or plain move, or the mode and feed alone.</summary>
    private void WriteMotion(double? feed)
    {
        var given = _block.Given;
        var motion = _block.MotionInBlock;
        var arcByCentre = (motion is 2 or 3 || _block.MotionCode is 2 or 3) && given.AnyCentre;
        if (_dwell is { } seconds)
        {
            _lines.Add("G04 P" + Num(_profile.DwellPInMilliseconds ? seconds * 1000 : seconds));
        }
        else if (_moves.Count > 0)
        {
            // A cycle's holes or a reference return: the interpreter's steps.
            Expand(feed);
        }
        else if (_block.AxisData)
        {
            // The axis words were the data settings' values (G10, G52, G92).
        }
        else if (_block.Compensated)
        {
            _heldLine = CompensatedMoves.Write(_lines, _block, _before.Position, feed);
        }
        else if (_block.Transforming && !_block.MachineCoordinates && (given.Any || arcByCentre))
        {
            TransformedMove(given.A, given.B, given.C, feed);
        }
        else if (given.Any || arcByCentre)
        {
            PlainMove(given, feed);
        }
        else if (motion >= 0)
        {
            _lines.Add(MotionText(motion) + (feed is { } fv ? " F" + Num(fv) : string.Empty));
        }
        else if (feed is { } fv)
        {
            _lines.Add("F" + Num(fv));
        }
    }

    private static string MotionText(int code) => code switch { 0 => "G00", 1 => "G01", 2 => "G02", _ => "G03" };

    /// <summary>The move as the line gave it, in millimetres: G53 and the motion code, axes, the arc's centre or radius, the feed.</summary>
    private void PlainMove(in CanonAxes given, double? feed)
    {
        _sb.Clear();
        _moveWords.Begin();
        if (_block.MachineCoordinates)
        {
            AppendCode("G53");
        }

        if (_block.MotionInBlock >= 0)
        {
            AppendCode(MotionText(_block.MotionInBlock));
        }

        AppendAxes(given.X, given.Y, given.Z);
        AppendWord('A', given.A);
        AppendWord('B', given.B);
        AppendWord('C', given.C);
        if (_block.MotionCode is 2 or 3)
        {
            ArcWords(given);
        }

        if (feed is { } fv)
        {
            AppendWord('F', fv);
        }

        _lines.Add(_sb.Length > 0 && _sb[^1] == ' ' ? _sb.ToString(0, _sb.Length - 1) : _sb.ToString()); // less the blank after the last word
        _moveLine = _moveWords.End() ? _lines.Count - 1 : -1;
        if (_block.MachineCoordinates)
        {
            _lines.Add(BackFromMachineCoordinates);
        }
    }

    /// <summary>An arc's centre or radius as the controller takes it, in millimetres.</summary>
    private void ArcWords(in CanonAxes given)
    {
        if (given.R is { } rv && !ShortRadius(rv))
        {
            AppendWord('R', rv);
        }
        else if (given.R.HasValue && _block.ArcCentre is { } mid)
        {
            // An R a rounding short of half the chord runs as the half circle on the chord (rs274ngc's
            // arc_data_r): its centre is sent, since a PMAC given the short R would spiral (Isx96).
            var v = mid - _before.Position;
            var plane = _block.Plane;
            AppendWord('I', plane is 17 or 18 ? v.X : null);
            AppendWord('J', plane is 17 or 19 ? v.Y : null);
            AppendWord('K', plane is 18 or 19 ? v.Z : null);
        }
        else if (_block.ArcCentresAbsolute)
        {
            // G90.1: the PMAC's centre vector is incremental from the start (its default INC(R)).
            var startProgram = _before.Position - _before.Offset;
            AppendWord('I', given.I - startProgram.X);
            AppendWord('J', given.J - startProgram.Y);
            AppendWord('K', given.K - startProgram.Z);
        }
        else
        {
            AppendWord('I', given.I);
            AppendWord('J', given.J);
            AppendWord('K', given.K);
        }
    }

    /// <summary>
    /// A move under mirror, scaling or rotation: the interpreter's end point in work coordinates (absolute, whatever the
    /// distance mode), an arc's centre as the PMAC's incremental vector from the start, the direction it really runs.
    /// </summary>
    private void TransformedMove(double? a, double? b, double? c, double? feed)
    {
        var incremental = !_block.Absolute;
        if (incremental)
        {
            _lines.Add("G90");
        }

        var mode = _block.MotionCode;
        var end = _block.Position - _block.Offset;
        _sb.Clear();
        var sent = mode;
        if (mode is 2 or 3 && _block.ArcCentre is not null)
        {
            sent = _block.ArcClockwise ? 2 : 3;
        }

        if (sent is >= 0 and <= 3)
        {
            _sb.Append("G0").Append(sent.ToString(CultureInfo.InvariantCulture)).Append(' ');
        }

        AppendAxes(end.X, end.Y, end.Z);
        AppendWord('A', a);
        AppendWord('B', b);
        AppendWord('C', c);
        if (sent is 2 or 3 && _block.ArcCentre is { } at)
        {
            var v = at - _before.Position;
            var plane = _block.Plane;
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
        var offset = _block.Offset;
        var incremental = !_block.Absolute;
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

                    AppendAxes((m.Axes & 1) != 0 ? target.X : null, (m.Axes & 2) != 0 ? target.Y : null, (m.Axes & 4) != 0 ? target.Z : null);
                    if (code == 1 && !feedSent && (feed ?? FeedPerMinute(_block.Feed)) is { } fv)
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
                    AppendAxes((m.Axes & 1) != 0 ? m.Target.X : null, (m.Axes & 2) != 0 ? m.Target.Y : null, (m.Axes & 4) != 0 ? m.Target.Z : null);
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
        if (_block.MotionCode is >= 0 and <= 3 && _block.MotionCode != mode)
        {
            _lines.Add("G0" + _block.MotionCode.ToString(CultureInfo.InvariantCulture));
        }
    }

    /// <summary>The profile's spelling of a spindle M code (M3 or M03).</summary>
    private string SpindleCode(int code) =>
        _profile.Find('M', code)?.Code ?? "M" + code.ToString("00", CultureInfo.InvariantCulture);

    /// <summary>The library's work offset table index: 1-6 G54-G59, 7-9 G59.1-G59.3, 10 and up the extended ones (G54.1 P1 = 10).</summary>
    public static int WorkOffsetIndex(int key) => key switch
    {
        >= 5410 => key - 5410 + 9,
        591 or 592 or 593 => key - 584,
        _ => (key - 530) / 10,
    };

    private double? FeedPerMinute(double? f)
    {
        var feed = f ?? (_block.FeedMode != 94 ? _block.Feed : null);
        if (feed is not { } fv)
        {
            return null;
        }

        return _block.FeedMode switch
        {
            // Per revolution: at the spindle speed in force.
            95 => fv * _block.UnitScale * _block.SpindleSpeed,
            // Inverse time: the move takes 1/F minutes, so its feed is its length times F.
            93 => _block.InverseTimeLength * fv,
            _ => fv * _block.UnitScale,
        };
    }

    /// <summary>The axes given, as data words.</summary>
    private static string Axes(double? x, double? y, double? z)
    {
        var sb = new StringBuilder();
        if (x is { } xv)
        {
            sb.Append(" X").Append(Num(xv));
        }

        if (y is { } yv)
        {
            sb.Append(" Y").Append(Num(yv));
        }

        if (z is { } zv)
        {
            sb.Append(" Z").Append(Num(zv));
        }

        return sb.ToString();
    }

    private void AppendAxes(double? x, double? y, double? z)
    {
        AppendWord('X', x);
        AppendWord('Y', y);
        AppendWord('Z', z);
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
        if (_block.ArcCentre is not { } c)
        {
            return false;
        }

        var v = c - _before.Position;
        var (a, b) = _block.Plane switch { 18 => (v.Z, v.X), 19 => (v.Y, v.Z), _ => (v.X, v.Y) };
        return Math.Sqrt((a * a) + (b * b)) > Math.Abs(radius) + 1e-9;
    }
}
