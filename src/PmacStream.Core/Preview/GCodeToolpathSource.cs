using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>A problem found while turning a program into moves for the preview (the block is not drawn).</summary>
/// <param name="Line">1-based source line.</param>
/// <param name="Column">1-based column (1 when it concerns the whole block).</param>
/// <param name="Message">What is wrong and what was expected.</param>
public readonly record struct PreviewIssue(long Line, int Column, string Message)
{
    /// <inheritdoc />
    public override string ToString() => $"{Line}:{Column}: {Message}";
}

/// <summary>
/// Streams the moves of a G-code file with <see cref="GCodeReader"/>: one line in memory at a time, so it can be
/// walked twice for a program of any size. Decodes the subset that shapes a toolpath (G00-G03 with I/J/K or R,
/// G17-G19, G20/G21, G90/G91); other codes are ignored. An axis stays unknown until the program sets it, so no
/// made-up move from the origin is drawn.
/// </summary>
public sealed class GCodeToolpathSource : IToolpathSource
{
    /// <summary>At most this many issues are kept (the rest are only counted).</summary>
    public const int MaxIssuesKept = 50;

    private readonly string _path;
    private readonly List<PreviewIssue> _issues = new();
    private long _length = 1;
    private long _position;

    /// <summary>Reads the program at <paramref name="path"/> (opened anew for each pass).</summary>
    public GCodeToolpathSource(string path)
    {
        _path = path;
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

    /// <summary>Issues of the last complete pass (the first <see cref="MaxIssuesKept"/>).</summary>
    public IReadOnlyList<PreviewIssue> Issues => _issues;

    /// <summary>How many issues the last pass found in all.</summary>
    public long IssueCount { get; private set; }

    /// <summary>Source lines of the last pass (including empty ones).</summary>
    public long LineCount { get; private set; }

    /// <inheritdoc />
    public IEnumerable<PathSegment> ReadSegments(CancellationToken cancellationToken = default)
    {
        using var reader = GCodeReader.Open(_path);
        _length = Math.Max(1, new FileInfo(_path).Length);
        _issues.Clear();
        IssueCount = 0;
        var decoder = new PreviewDecoder(AddIssue);
        var lines = 0L;
        while (reader.Read())
        {
            if ((++lines & 0xFFF) == 0)
            {
                cancellationToken.ThrowIfCancellationRequested();
                _position = reader.Position;
            }

            if (decoder.Decode(reader.Current, out var segment))
            {
                yield return segment;
            }
        }

        _position = _length;
        LineCount = lines;
        Units = decoder.Units;
        MixedUnits = decoder.MixedUnits;
    }

    private void AddIssue(PreviewIssue issue)
    {
        IssueCount++;
        if (_issues.Count < MaxIssuesKept)
        {
            _issues.Add(issue);
        }
    }
}

/// <summary>
/// The modal state a toolpath needs, applied block by block. Kept small on purpose: the full interpreter (modal
/// groups, profiles, offsets) lives in <c>GCode/</c>; this only has to place moves.
/// </summary>
internal sealed class PreviewDecoder(Action<PreviewIssue> report)
{
    private const double InchToMm = 25.4;
    private readonly double[] _pos = new double[3];
    private readonly bool[] _known = new bool[3];
    private int _motion = -1;
    private ArcPlane _plane = ArcPlane.XY;
    private bool _incremental;
    private bool _unitsSeen;

    public LengthUnits Units { get; private set; } = LengthUnits.Millimetres;

    public bool MixedUnits { get; private set; }

    private double Scale => Units == LengthUnits.Inches ? InchToMm : 1.0;

    /// <summary>Applies one block; true with a segment when it moves from a fully known position.</summary>
    public bool Decode(GBlock block, out PathSegment segment)
    {
        segment = default;
        if (block.IsEmpty || block.IsTapeMark)
        {
            return false;
        }

        var motion = -1;
        var axisConsumer = false; // G04/G10/G28/G30/G92... take axis words that are not a move
        double? x = null, y = null, z = null, i = null, j = null, k = null, r = null;
        foreach (var w in block.Words)
        {
            switch (w.Letter)
            {
                case 'G':
                    switch (w.CodeTimesTen)
                    {
                        case 0: motion = 0; break;
                        case 10: motion = 1; break;
                        case 20: motion = 2; break;
                        case 30: motion = 3; break;
                        case 170: _plane = ArcPlane.XY; break;
                        case 180: _plane = ArcPlane.ZX; break;
                        case 190: _plane = ArcPlane.YZ; break;
                        case 200: SetUnits(LengthUnits.Inches); break;
                        case 210: SetUnits(LengthUnits.Millimetres); break;
                        case 900: _incremental = false; break;
                        case 910: _incremental = true; break;
                        case 40 or 100 or 280 or 300 or 920 or 520: axisConsumer = true; break;
                        case 800: _motion = -1; break;
                    }

                    break;
                case 'X': x = w.Value; break;
                case 'Y': y = w.Value; break;
                case 'Z': z = w.Value; break;
                case 'I': i = w.Value; break;
                case 'J': j = w.Value; break;
                case 'K': k = w.Value; break;
                case 'R': r = w.Value; break;
            }
        }

        if (motion >= 0)
        {
            _motion = motion;
        }

        var hasAxis = x.HasValue || y.HasValue || z.HasValue;
        if (axisConsumer || (!hasAxis && !(motion is 2 or 3 && (i.HasValue || j.HasValue || k.HasValue))))
        {
            return false;
        }

        if (_motion < 0)
        {
            report(new PreviewIssue(block.LineNumber, 1, "axis words without a motion mode (expected G00, G01, G02 or G03 first)"));
            return false;
        }

        var startKnown = _known[0] && _known[1] && _known[2];
        var start = new Point3D(_pos[0], _pos[1], _pos[2]);
        Move(0, x);
        Move(1, y);
        Move(2, z);
        var end = new Point3D(_pos[0], _pos[1], _pos[2]);
        if (!startKnown)
        {
            // Where the tool was is unknown: take the target as the start so later moves draw from here.
            return false;
        }

        if (_motion <= 1)
        {
            segment = PathSegment.Line(start, end, _motion == 0, block.LineNumber);
            return true;
        }

        if (!TryArcCentre(block, start, end, i, j, k, r, out var centre))
        {
            return false;
        }

        segment = PathSegment.Arc(start, end, centre, _plane, _motion == 2, block.LineNumber);
        return true;
    }

    private void SetUnits(LengthUnits units)
    {
        if (_unitsSeen && units != Units)
        {
            MixedUnits = true;
        }

        _unitsSeen = true;
        Units = units;
    }

    private void Move(int axis, double? value)
    {
        if (!value.HasValue)
        {
            return;
        }

        var v = value.Value * Scale;
        if (_incremental)
        {
            if (_known[axis])
            {
                _pos[axis] += v;
            }
        }
        else
        {
            _pos[axis] = v;
            _known[axis] = true;
        }
    }

    private bool TryArcCentre(GBlock block, Point3D s, Point3D e, double? i, double? j, double? k, double? r, out Point3D centre)
    {
        var (sa, sb) = ArcGeometry.InPlane(s, _plane);
        var (ea, eb) = ArcGeometry.InPlane(e, _plane);
        // The plane's first and second axes take these offset words: G17 I J, G18 K I, G19 J K.
        var (oa, ob) = _plane switch
        {
            ArcPlane.XY => (i, j),
            ArcPlane.ZX => (k, i),
            _ => (j, k),
        };
        double ca, cb;
        if (oa.HasValue || ob.HasValue)
        {
            ca = sa + ((oa ?? 0) * Scale);
            cb = sb + ((ob ?? 0) * Scale);
        }
        else if (r.HasValue)
        {
            var radius = r.Value * Scale;
            var da = ea - sa;
            var db = eb - sb;
            var d = Math.Sqrt((da * da) + (db * db));
            if (d < 1e-9 || Math.Abs(radius) < 1e-9)
            {
                report(new PreviewIssue(block.LineNumber, 1, "R arc with coincident start and end (a full circle needs I/J/K)"));
                centre = default;
                return false;
            }

            var h = Math.Sqrt(Math.Max(0, (radius * radius) - (d * d / 4)));
            // A CW arc of at most 180 degrees has its centre right of the chord, CCW left; negative R flips it.
            var left = (_motion == 3) == (radius > 0);
            var sign = left ? 1.0 : -1.0;
            ca = ((sa + ea) / 2) - (sign * h * db / d);
            cb = ((sb + eb) / 2) + (sign * h * da / d);
        }
        else
        {
            var words = _plane switch { ArcPlane.XY => "I/J", ArcPlane.ZX => "I/K", _ => "J/K" };
            report(new PreviewIssue(block.LineNumber, 1, $"arc without R or {words} for plane G{(int)_plane}"));
            centre = default;
            return false;
        }

        centre = ArcGeometry.FromPlane(ca, cb, 0, _plane);
        return true;
    }
}
