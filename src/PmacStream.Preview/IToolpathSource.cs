using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>
/// A program the preview can walk more than once (extents, then drawing) without holding it in memory: each call of
/// <see cref="ReadSegments"/> starts a fresh pass.
/// </summary>
public interface IToolpathSource
{
    /// <summary>Starts a new pass over every move of the program, in program order.</summary>
    IEnumerable<PathSegment> ReadSegments(CancellationToken cancellationToken = default);

    /// <summary>The unit the program was written in (known after a full pass; millimetres before).</summary>
    LengthUnits Units { get; }

    /// <summary>True when the program switched between G20 and G21 (coordinates are still all converted to mm).</summary>
    bool MixedUnits { get; }

    /// <summary>How far the current pass has got, 0..1 (for progress bars).</summary>
    double PassFraction { get; }

    /// <summary>A short name for the legend (file name).</summary>
    string Name { get; }

    /// <summary>
    /// The rotary axes (<c>A</c>, <c>B</c>, <c>C</c>) the program moves, known after a full pass: the picture draws
    /// X, Y and Z only, and the legend says which rotary axes it leaves out. Empty when none (the default).
    /// </summary>
    string RotaryAxes => string.Empty;
}

/// <summary>A toolpath given as a list (tests, the HMI's small jobs).</summary>
public sealed class SegmentListSource(IReadOnlyList<PathSegment> segments, string name = "segments", LengthUnits units = LengthUnits.Millimetres)
    : IToolpathSource
{
    private double _fraction;

    /// <inheritdoc />
    public LengthUnits Units { get; } = units;

    /// <inheritdoc />
    public bool MixedUnits => false;

    /// <inheritdoc />
    public double PassFraction => _fraction;

    /// <inheritdoc />
    public string Name { get; } = name;

    /// <inheritdoc />
    public IEnumerable<PathSegment> ReadSegments(CancellationToken cancellationToken = default)
    {
        for (var i = 0; i < segments.Count; i++)
        {
            cancellationToken.ThrowIfCancellationRequested();
            _fraction = (double)i / segments.Count;
            yield return segments[i];
        }

        _fraction = 1;
    }
}
