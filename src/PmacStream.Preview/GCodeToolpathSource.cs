using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>
/// Streams the moves of a G-code file through <see cref="GCodeReader"/> and the <see cref="Interpreter"/>: one line
/// and the modal state in memory, so it can be walked twice for a program of any size. Coordinates are converted to
/// millimetres. An axis counts as unknown until the program sets it absolutely, so no made-up move from the
/// interpreter's origin is drawn; the first positioning moves only establish where the tool is.
/// </summary>
public sealed class GCodeToolpathSource : IToolpathSource, IToolpathIssues
{
    /// <summary>At most this many error diagnostics are kept (the rest are only counted).</summary>
    public const int MaxIssuesKept = 50;

    private readonly string _path;
    private readonly MachineProfile _profile;
    private readonly List<Diagnostic> _issues = new();
    private long _length = 1;
    private long _position;

    /// <summary>Reads the program at <paramref name="path"/> (opened anew for each pass) with a machine profile.</summary>
    public GCodeToolpathSource(string path, MachineProfile? profile = null)
    {
        _path = path;
        _profile = profile ?? MachineProfile.Default;
        Name = Path.GetFileName(path);
    }

    /// <inheritdoc />
    public string Name { get; }

    /// <inheritdoc />
    public LengthUnits Units { get; private set; }

    /// <inheritdoc />
    public bool MixedUnits { get; private set; }

    /// <inheritdoc />
    public double PassFraction => Math.Clamp((double)_position / _length, 0, 1);

    /// <summary>Errors of the last complete pass, as the checker words them (the first <see cref="MaxIssuesKept"/>).</summary>
    public IReadOnlyList<Diagnostic> Issues => _issues;

    /// <summary>How many errors the last pass found in all.</summary>
    public long IssueCount { get; private set; }

    /// <summary>Source lines of the last pass.</summary>
    public long LineCount { get; private set; }

    /// <inheritdoc />
    public IEnumerable<PathSegment> ReadSegments(CancellationToken cancellationToken = default)
    {
        using var reader = GCode.Expansion.ProgramExpansion.OpenReader(_path, _profile); // subprograms and macros drawn as they run
        _length = Math.Max(1, new FileInfo(_path).Length);
        _issues.Clear();
        IssueCount = 0;
        var holes = new CycleHolesSink();
        var interpreter = new Interpreter(_profile) { Canon = holes };
        var adapter = new DecodedBlockAdapter();
        var diags = new List<Diagnostic>(4);
        var segments = new List<PathSegment>(4);
        var held = new List<PathSegment>(4); // the last move's segments: an inside corner at the next move moves its end back
        var rotary = new bool[3];
        var lines = 0L;
        while (reader.Read())
        {
            if ((++lines & 0xFFF) == 0)
            {
                cancellationToken.ThrowIfCancellationRequested();
                _position = reader.Position;
            }

            if (lines == 1 && reader.StartsWithUtf16Bom)
            {
                // As the check says it: the bytes are not G-code text, so nothing of it can be drawn.
                AddIssue(new Diagnostic(Severity.Error, DiagnosticCodes.Utf16File, 1, 1, DiagnosticText.Format(DiagnosticCodes.Utf16File)));
                break;
            }

            var block = reader.Current;
            NoteRotaryWords(block, rotary);
            IssueCount += block.UnlistedErrors;
            foreach (var d in block.LexicalDiagnostics)
            {
                AddIssue(d);
            }

            diags.Clear();
            var decoded = interpreter.Step(block, diags);
            foreach (var d in diags)
            {
                AddIssue(d);
            }

            if (decoded is not null && adapter.Convert(decoded, segments, holes.Last) > 0)
            {
                if (interpreter.AmendedEnd is { } amended && held.Count > 0)
                {
                    // G41/G42 inside corner: the move before ends where the offset paths cross, as the controller runs it.
                    held[^1] = held[^1] with { End = amended };
                }

                foreach (var segment in held)
                {
                    yield return segment;
                }

                (held, segments) = (segments, held);
                segments.Clear();
            }
        }

        foreach (var segment in held)
        {
            yield return segment;
        }

        _position = _length;
        LineCount = lines;
        RotaryAxes = string.Concat("ABC".Where((_, i) => rotary[i]));
        Units = adapter.Units;
        MixedUnits = adapter.MixedUnits;
    }

    /// <inheritdoc />
    public string RotaryAxes { get; private set; } = string.Empty;

    /// <summary>The holes of the block the interpreter took last when it was a cycle block (its canonical record), else null.</summary>
    private sealed class CycleHolesSink : ICanonicalMoves
    {
        public CycleHoles? Last { get; private set; }

        public void StartBlock(in CanonStart start) => Last = null;

        public void Step(in HostMove step)
        {
        }

        public void Motion(in CanonMotion motion)
        {
        }

        public void EndBlock(in CanonBlock block) => Last = block.Holes;
    }

    /// <summary>Marks the rotary axes (A, B, C) a line's words name: the picture draws X, Y and Z only, and the legend says so.</summary>
    private static void NoteRotaryWords(GBlock block, bool[] rotary)
    {
        foreach (var w in block.Words)
        {
            if (w.Letter is 'A' or 'B' or 'C')
            {
                rotary[w.Letter - 'A'] = true;
            }
        }
    }

    private void AddIssue(Diagnostic d)
    {
        if (d.Severity != Severity.Error)
        {
            return;
        }

        IssueCount++;
        if (_issues.Count < MaxIssuesKept)
        {
            _issues.Add(d);
        }
    }
}

/// <summary>
/// Turns interpreter records (millimetres) into drawable segments, and withholds moves along an axis whose
/// position has not been set yet. Only motion sets a position: a data block (G10, G52, G92) carries axis words that
/// are offsets, not a place the tool goes to. The interpreter's positions are machine coordinates (the work offset,
/// G52, G92 and the tool length applied), so a program run under G55 is drawn where G55 puts it. A cycle block is
/// drawn hole by hole.
/// </summary>
public sealed class DecodedBlockAdapter
{
    private bool _x;
    private bool _y;
    private bool _z;
    private bool _unitsSeen;

    /// <summary>Units of the first block (millimetres before any).</summary>
    public LengthUnits Units { get; private set; }

    /// <summary>True when later blocks used other units than the first.</summary>
    public bool MixedUnits { get; private set; }

    /// <summary>
    /// Adds the segments of a move whose moving axes start from known positions to <paramref name="into"/> (one, or
    /// four per hole of a cycle block, whose <paramref name="holes"/> the interpreter gives); returns how many. None for
    /// non-moves, data blocks and first positionings.
    /// </summary>
    public int Convert(DecodedBlock block, List<PathSegment> into, CycleHoles? holes = null)
    {
        ArgumentNullException.ThrowIfNull(block);
        ArgumentNullException.ThrowIfNull(into);
        var units = block.Modal.Units;
        if (!_unitsSeen)
        {
            _unitsSeen = true;
            Units = units;
        }
        else if (units != Units)
        {
            MixedUnits = true;
        }

        if (block.Motion is MotionKind.None or MotionKind.Dwell)
        {
            return 0;
        }

        // A move is drawn when every axis it moves started from a known position. An axis the program never sets
        // (Z in a 2D program) does not move, so it does not withhold the moves of the others.
        var known = (!block.X.HasValue || _x) && (!block.Y.HasValue || _y) && (!block.Z.HasValue || _z);
        if (block.Modal.Absolute)
        {
            _x |= block.X.HasValue;
            _y |= block.Y.HasValue;
            _z |= block.Z.HasValue;
        }

        if (!known)
        {
            return 0;
        }

        // The interpreter's positions are millimetres already, whatever the program's units.
        const double f = 1.0;
        var start = Mm(block.Start, f);
        var end = Mm(block.End, f);
        switch (block.Motion)
        {
            case MotionKind.Rapid:
            case MotionKind.Linear:
                into.Add(PathSegment.Line(start, end, block.Motion == MotionKind.Rapid, block.Line));
                return 1;
            case MotionKind.Cycle:
                return holes is { Count: > 0 } h ? AddHoles(block, h, f, into) : 0;
            default:
                if (block.Center is not { } c)
                {
                    return 0; // the interpreter could not place the centre; the error is reported
                }

                into.Add(PathSegment.Arc(start, end, Mm(c, f), (ArcPlane)block.Modal.Plane, block.Motion == MotionKind.ArcCw, block.Line));
                return 1;
        }
    }

    /// <summary>Each hole: rapid over it at the height the tool has, rapid down to R, feed to the bottom, rapid up to the retract level.</summary>
    private static int AddHoles(DecodedBlock block, CycleHoles holes, double f, List<PathSegment> into)
    {
        var at = block.Start;
        var retract = block.End.Z;
        for (var n = 1; n <= holes.Count; n++)
        {
            var t = block.Modal.Absolute ? 1.0 : (double)n / holes.Count;
            var hole = new Point3(block.Start.X + ((block.End.X - block.Start.X) * t), block.Start.Y + ((block.End.Y - block.Start.Y) * t), at.Z);
            into.Add(PathSegment.Line(Mm(at, f), Mm(hole, f), rapid: true, block.Line));
            into.Add(PathSegment.Line(Mm(hole, f), Mm(hole with { Z = holes.RLevel }, f), rapid: true, block.Line));
            into.Add(PathSegment.Line(Mm(hole with { Z = holes.RLevel }, f), Mm(hole with { Z = holes.Bottom }, f), rapid: false, block.Line));
            into.Add(PathSegment.Line(Mm(hole with { Z = holes.Bottom }, f), Mm(hole with { Z = retract }, f), rapid: true, block.Line));
            at = hole with { Z = retract };
        }

        return 4 * holes.Count;
    }

    private static Point3 Mm(Point3 p, double f) => new(p.X * f, p.Y * f, p.Z * f);
}
