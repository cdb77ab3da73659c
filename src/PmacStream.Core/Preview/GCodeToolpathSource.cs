using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>
/// Streams the moves of a G-code file through <see cref="GCodeReader"/> and the <see cref="Interpreter"/>: one line
/// and the modal state in memory, so it can be walked twice for a program of any size. Coordinates are converted to
/// millimetres. An axis counts as unknown until the program sets it absolutely, so no made-up move from the
/// interpreter's origin is drawn; the first positioning moves only establish where the tool is.
/// </summary>
public sealed class GCodeToolpathSource : IToolpathSource
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
        using var reader = GCodeReader.Open(_path);
        _length = Math.Max(1, new FileInfo(_path).Length);
        _issues.Clear();
        IssueCount = 0;
        var interpreter = new Interpreter(_profile);
        var adapter = new DecodedBlockAdapter();
        var diags = new List<Diagnostic>(4);
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

            if (decoded is not null && adapter.TryConvert(decoded, out var segment))
            {
                yield return segment;
            }
        }

        _position = _length;
        LineCount = lines;
        Units = adapter.Units;
        MixedUnits = adapter.MixedUnits;
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
/// position has not been set yet.
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

    /// <summary>A segment for a move whose moving axes start from known positions; false for non-moves and first positionings.</summary>
    public bool TryConvert(DecodedBlock block, out PathSegment segment)
    {
        segment = default;
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

        // A move is drawn when every axis it moves started from a known position. An axis the program never sets
        // (Z in a 2D program) does not move, so it does not withhold the moves of the others.
        var known = (!block.X.HasValue || _x) && (!block.Y.HasValue || _y) && (!block.Z.HasValue || _z);
        if (block.Modal.Absolute)
        {
            _x |= block.X.HasValue;
            _y |= block.Y.HasValue;
            _z |= block.Z.HasValue;
        }

        if (!known || block.Motion is MotionKind.None or MotionKind.Dwell)
        {
            return false;
        }

        // The interpreter's positions are millimetres already, whatever the program's units.
        const double f = 1.0;
        var start = Mm(block.Start, f);
        var end = Mm(block.End, f);
        switch (block.Motion)
        {
            case MotionKind.Rapid:
            case MotionKind.Linear:
                segment = PathSegment.Line(start, end, block.Motion == MotionKind.Rapid, block.Line);
                return true;
            default:
                if (block.Center is not { } c)
                {
                    return false; // the interpreter could not place the centre; the error is reported
                }

                segment = PathSegment.Arc(start, end, Mm(c, f), (ArcPlane)block.Modal.Plane, block.Motion == MotionKind.ArcCw, block.Line);
                return true;
        }
    }

    private static Point3D Mm(Point3 p, double f) => new(p.X * f, p.Y * f, p.Z * f);
}
