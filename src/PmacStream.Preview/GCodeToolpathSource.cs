using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>
/// Streams the moves of a G-code file through <see cref="GCodeReader"/> and the <see cref="Interpreter"/>, drawing what
/// its canonical calls say (<see cref="CanonToolpath"/>): one line and the modal state in memory, so it can be walked
/// twice for a program of any size. Coordinates are converted to
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
        var canon = new CanonToolpath();
        var interpreter = new Interpreter(_profile) { Canon = canon };
        var builder = new ToolpathBuilder();
        var diags = new List<Diagnostic>(4);
        var segments = new List<PathSegment>(4);
        // G41/G42: the move held and the plunges queued behind it, until the next XY move says where they end.
        var held = new HeldMoves<PathSegment>((s, crossing, first) => first
            ? s with { End = AmendedMove.MovedTo(s.End, crossing) }
            : s with { Start = AmendedMove.MovedTo(s.Start, crossing), End = AmendedMove.MovedTo(s.End, crossing) });
        var final = new List<PathSegment>(4);
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
            IssueCount += block.UnlistedErrors;
            foreach (var d in block.LexicalDiagnostics)
            {
                AddIssue(d);
            }

            diags.Clear();
            var taken = interpreter.Execute(block, diags);
            foreach (var d in diags)
            {
                AddIssue(d);
            }

            if (taken)
            {
                builder.Add(canon.Block, segments);
                held.Take(canon.Hold, canon.AmendedEnd, segments, final);
                segments.Clear();
                foreach (var segment in final)
                {
                    yield return segment;
                }

                final.Clear();
            }
        }

        held.Flush(final);
        foreach (var segment in final)
        {
            yield return segment;
        }

        _position = _length;
        LineCount = lines;
        RotaryAxes = string.Concat("ABC".Where((_, i) => (canon.Rotary & (1 << i)) != 0));
        Units = builder.Units;
        MixedUnits = builder.MixedUnits;
    }

    /// <inheritdoc />
    public string RotaryAxes { get; private set; } = string.Empty;

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
