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

    private readonly MachineProfile _profile;
    private readonly List<HostMove> _moves = [];
    private readonly List<string> _lines = [];
    private readonly StringBuilder _sb = new(128);
    private readonly double?[] _given = new double?[26]; // the block's words by letter: the first of each (a library routine's)
    private readonly double?[] _word = new double?[26];  // and the last of each (the move's)
    private readonly List<(char Letter, double Value)> _codes = []; // the block's G and M codes as written
    private CanonStart _before;  // the state the line started from (ICanonicalMoves.StartBlock)
    private CanonBlock _block;   // what the interpreter decided for it (ICanonicalMoves.EndBlock)

    // The words of the move line as written (an inch program converts every move), so it is not lexed again.
    private readonly WrittenWords _moveWords = new();
    private int _moveLine = -1;
    private int _heldLine = -1;  // the line of the converted block that ends its compensated move
    private Point3 _heldOffset;  // the work offset that move was written in

    /// <summary>
    /// The index, in the lines <see cref="Convert"/> returned last, of the line ending a compensated move: the sender
    /// holds it until the next move is known, since an inside corner there moves its end back (<see cref="AmendedLine"/>);
    /// -1 when the block has none.
    /// </summary>
    public int HeldMoveLine => _heldLine;

    /// <summary>
    /// When the block taken last has an inside corner under compensation: <paramref name="held"/> (the line
    /// <see cref="HeldMoveLine"/> named for the compensated move before it) rewritten to end where the offset paths
    /// cross; null for any other block.
    /// </summary>
    public string? AmendedLine(string held) =>
        _block.AmendedEnd is { } end ? CompensatedMoves.MoveEndTo(held, end - _heldOffsetBefore) : null;

    private Point3 _heldOffsetBefore; // the offset of the move held before this block (AmendedLine)
    private readonly List<string> _modes = [], _data = [], _stopsBefore = [], _after = []; // a block's parts, reused

    /// <summary>Converts what <paramref name="interp"/> decides: it becomes the interpreter's canonical move sink.</summary>
    public HostConversion(Interpreter interp)
    {
        _profile = interp.Profile;
        interp.Canon = new Sink(this);
    }

    /// <summary>
    /// The blocks to send instead of <paramref name="block"/> (which the interpreter just took), or null when it is
    /// not a host block and goes as it is.
    /// </summary>
    public IReadOnlyList<string>? Convert(GBlock block)
    {
        if (!_block.Host)
        {
            return null;
        }

        _lines.Clear();
        _moveLine = -1;
        _heldLine = -1;
        ReadWords(block);
        var seen = SortCodes(_block.UnitScale);
        if (seen.LengthCode || (W('H').HasValue && _block.LengthMode != 0))
        {
            _data.Add(_block.LengthMode == 0 ? "G49" : $"G{_block.LengthMode} H{_block.LengthOffsetNumber.ToString(CultureInfo.InvariantCulture)}");
        }

        if (W('S') is { } sv)
        {
            _stopsBefore.Insert(0, "S" + Num(sv));
        }

        if (_modes.Count > 0)
        {
            _lines.Add(string.Join(' ', _modes));
        }

        Add(_stopsBefore);
        Add(_data);
        WriteMotion(seen, FeedPerMinute(W('F')));
        if (_block.ExactStop)
        {
            // The library's G09 (DWELL0) after the move: the move decelerates to rest before the next one starts. A
            // profile without a G09 routine (grbl) has the library's own G09.9.
            _lines.Add(_profile.Find('G', 9) is { Controller: ControllerSupport.Library } g09 ? g09.Code : ExactStopCode);
        }

        Add(_after);
        return _lines;
    }

    /// <summary>What the block's codes say about its motion (<see cref="SortCodes"/>).</summary>
    private struct Seen
    {
        public string? Motion;   // G00..G03 in the block
        public bool Machine;     // G53
        public bool Dwell;       // G04
        public bool AxisData;    // a data code takes the block's axis words: nothing moves
        public bool LengthCode;  // G43, G44 or G49 in the block
    }

    /// <summary>The block's words by letter (<see cref="W"/>, <see cref="_given"/>) and its G and M codes in order.</summary>
    private void ReadWords(GBlock block)
    {
        _codes.Clear();
        Array.Clear(_given);
        Array.Clear(_word);
        foreach (var w in block.WordList)
        {
            if (w.Letter is < 'A' or > 'Z')
            {
                continue;
            }

            _given[w.Letter - 'A'] ??= w.Value;
            _word[w.Letter - 'A'] = w.Value;
            if (w.Letter is 'G' or 'M')
            {
                _codes.Add((w.Letter, w.Value));
            }
        }
    }

    /// <summary>The block's word <paramref name="letter"/> as written (the last one when it is there twice).</summary>
    private double? W(char letter) => _word[letter - 'A'];

    /// <summary>
    /// The block's codes into the parts of what is sent: modes, data settings, stops before the move, codes after it;
    /// what is pure program syntax the host already applied is left out.
    /// </summary>
    private Seen SortCodes(double scale)
    {
        var seen = default(Seen);
        _modes.Clear();
        _data.Clear();
        _stopsBefore.Clear();
        _after.Clear();
        foreach (var (letter, value) in _codes)
        {
            if (letter == 'M')
            {
                SortM(value, scale);
            }
            else
            {
                SortG(value, scale, ref seen);
            }
        }

        return seen;
    }

    private void SortM(double value, double scale)
    {
        var key = (int)Math.Round(value * 10);
        var m = "M" + Code(value) + LibraryWords('M', value, scale);
        if (key == 60)
        {
            // The tool change routine reads the tool it changes to.
            _after.Add($"{m} T{_block.Tool.ToString(CultureInfo.InvariantCulture)}");
        }
        else if (key is 30 or 40 or 70 or 80 or 190 or 880)
        {
            _stopsBefore.Add(m);
        }
        else
        {
            _after.Add(m);
        }
    }

    private void SortG(double value, double scale, ref Seen seen)
    {
        switch ((int)Math.Round(value * 10))
        {
            case 0 or 10 or 20 or 30:
                seen.Motion = "G" + Code(value);
                break;
            case 40:
                seen.Dwell = true;
                break;
            case 530:
                seen.Machine = true;
                break;
            case 100:
                seen.AxisData = true;
                _data.AddRange(TableSettings(W('L'), W('P')));
                break;
            case 520:
                seen.AxisData = true;
                _data.Add("G52" + Axes(W('X'), W('Y'), W('Z'), scale, _block.Tables.Local, all: false));
                break;
            case 920:
                seen.AxisData = true;
                _data.Add("G92" + Axes(W('X'), W('Y'), W('Z'), 1.0, _block.Tables.Shift, all: false, fromResult: true));
                break;
            case 921 or 922:
                _data.Add("G92.1");
                break;
            case 430 or 440 or 490:
                seen.LengthCode = true;
                break;
            case 541 or 1540:
                _modes.Add("G54.1 P" + Num(W('P') ?? 1));
                break;
            // Pure program syntax the host has already applied: units, arc centre mode, cycles and their return
            // levels, reference returns (their moves follow), feed modes (feeds are sent per minute).
            case 200 or 210 or 901 or 911 or 800 or 980 or 990 or 270 or 280 or 290 or 300 or 930 or 940 or 950:
                break;
            // Mirror, scaling and rotation are in the positions sent; exact stop mode and G09 are a G09 after the move.
            case 510 or 511 or 680:
                seen.AxisData = true;
                break;
            case 500 or 501 or 690 or 610 or 90:
                break;
            // Cutter radius compensation is in the positions sent (CompensatedMoves).
            case 410 or 420:
                break;
            case var key and >= 730 and <= 890 when CodeIsCycle(key):
                break;
            case var key:
                // Codes that take the block's axis words as data (scaling, rotation, macro calls...) never move.
                seen.AxisData |= CodeRoles.OfG(key) == GRole.AxisData;
                _modes.Add("G" + Code(value) + LibraryWords('G', value, scale));
                break;
        }
    }

    /// <summary>The block's motion as the controller runs it: a dwell, the interpreter's steps, a compensated, transformed or plain move, or the mode and feed alone.</summary>
    private void WriteMotion(in Seen seen, double? feed)
    {
        var hasAxes = W('X').HasValue || W('Y').HasValue || W('Z').HasValue || W('A').HasValue || W('B').HasValue || W('C').HasValue;
        var arcByCentre = (seen.Motion is "G02" or "G03" || _block.MotionCode is 2 or 3) && (W('I').HasValue || W('J').HasValue || W('K').HasValue);
        if (seen.Dwell)
        {
            _lines.Add("G04 P" + Num(DwellP(W('P'), W('X'))));
        }
        else if (_moves.Count > 0)
        {
            // A cycle's holes or a reference return: the interpreter's steps.
            Expand(feed);
        }
        else if (seen.AxisData)
        {
            // The axis words were the data settings' values (G10, G52, G92).
        }
        else if (_block.Compensated)
        {
            _heldLine = CompensatedMoves.Write(_lines, _block, _before.Position, feed);
            _heldOffset = _block.Offset;
        }
        else if (_block.Transforming && !seen.Machine && (hasAxes || arcByCentre))
        {
            TransformedMove(W('A'), W('B'), W('C'), feed);
        }
        else if (hasAxes || arcByCentre)
        {
            PlainMove(seen, feed);
        }
        else if (seen.Motion != null)
        {
            _lines.Add(seen.Motion + (feed is { } fv ? " F" + Num(fv) : string.Empty));
        }
        else if (feed is { } fv)
        {
            _lines.Add("F" + Num(fv));
        }
    }

    /// <summary>The move as written, in millimetres: G53 and the motion code, axes, the arc's centre or radius, the feed.</summary>
    private void PlainMove(in Seen seen, double? feed)
    {
        var scale = _block.UnitScale;
        _sb.Clear();
        _moveWords.Begin();
        if (seen.Machine)
        {
            AppendCode("G53");
        }

        if (seen.Motion != null)
        {
            AppendCode(seen.Motion);
        }

        AppendAxes(W('X'), W('Y'), W('Z'), scale);
        AppendWord('A', W('A'));
        AppendWord('B', W('B'));
        AppendWord('C', W('C'));
        if (_block.MotionCode is 2 or 3)
        {
            var (i, j, k) = (W('I'), W('J'), W('K'));
            if (W('R') is { } rv && !ShortRadius(rv * scale))
            {
                AppendWord('R', rv * scale);
            }
            else if (W('R').HasValue && _block.ArcCentre is { } mid)
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
        if (seen.Machine)
        {
            _lines.Add(BackFromMachineCoordinates);
        }
    }

    /// <summary>
    /// The interpreter's canonical moves as the conversion needs them: the state each block starts from, the steps
    /// of its cycle holes or reference return, and what it decided (<see cref="CanonBlock"/>). The interpreter calls it
    /// for every line it takes, so <see cref="Convert"/> reads only these records, never the interpreter.
    /// </summary>
    private sealed class Sink(HostConversion host) : ICanonicalMoves
    {
        public void StartBlock(in CanonStart start)
        {
            host._moves.Clear();
            host._before = start;
            host._heldOffsetBefore = host._heldOffset;
        }

        public void Step(in HostMove step) => host._moves.Add(step);

        public void Motion(in CanonMotion motion)
        {
            // The block's own motion is written from its decisions (EndBlock) in Convert.
        }

        public void EndBlock(in CanonBlock block) => host._block = block;
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

        AppendAxes(end.X, end.Y, end.Z, 1.0);
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

                    AppendAxes((m.Axes & 1) != 0 ? target.X : null, (m.Axes & 2) != 0 ? target.Y : null, (m.Axes & 4) != 0 ? target.Z : null, 1.0);
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
        if (_block.MotionCode is >= 0 and <= 3 && _block.MotionCode != mode)
        {
            _lines.Add("G0" + _block.MotionCode.ToString(CultureInfo.InvariantCulture));
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
        var coords = _block.Tables;
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
