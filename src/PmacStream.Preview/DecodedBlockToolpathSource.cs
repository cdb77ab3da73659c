using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>What a program's check found, as the preview lists it when it refuses (or, forced, draws) a program with errors.</summary>
public interface IToolpathIssues
{
    /// <summary>Error diagnostics, the first few (as the checker words them).</summary>
    IReadOnlyList<Diagnostic> Issues { get; }

    /// <summary>How many errors there are in all.</summary>
    long IssueCount { get; }
}

/// <summary>
/// The toolpath of blocks interpreted once already (a stored revision's decoded blocks, each with its cycle holes):
/// drawn by the same <see cref="ToolpathBuilder"/> as a file's (each row as the <see cref="DrawnBlock"/> the interpreter
/// decided at import), so the picture is the file's, and nothing is read or interpreted again. Each pass asks <paramref name="blocks"/> for a fresh enumeration (the store streams its rows).
/// </summary>
/// <param name="blocks">A fresh pass over the blocks in program order, with a cycle block's holes.</param>
/// <param name="blockCount">How many blocks a pass yields (for <see cref="PassFraction"/>).</param>
/// <param name="name">The legend's name.</param>
/// <param name="issues">The stored error diagnostics (the first few).</param>
/// <param name="issueCount">How many errors the check found.</param>
public sealed class DecodedBlockToolpathSource(
    Func<IEnumerable<(DecodedBlock Block, CycleHoles? Holes)>> blocks, long blockCount, string name, IReadOnlyList<Diagnostic> issues, long issueCount)
    : IToolpathSource, IToolpathIssues
{
    private long _read;

    /// <inheritdoc />
    public string Name { get; } = name;

    /// <inheritdoc />
    public LengthUnits Units { get; private set; }

    /// <inheritdoc />
    public bool MixedUnits { get; private set; }

    /// <inheritdoc />
    public double PassFraction => Math.Clamp((double)_read / Math.Max(1, blockCount), 0, 1);

    /// <inheritdoc />
    public IReadOnlyList<Diagnostic> Issues { get; } = issues;

    /// <inheritdoc />
    public long IssueCount { get; } = issueCount;

    /// <summary>Cycle blocks of the last pass that came without their holes (stored before schema 9): not drawn.</summary>
    public long CyclesWithoutHoles { get; private set; }

    /// <inheritdoc />
    public IEnumerable<PathSegment> ReadSegments(CancellationToken cancellationToken = default)
    {
        var builder = new ToolpathBuilder();
        var segments = new List<PathSegment>(4);
        _read = 0;
        var missing = 0L;
        foreach (var (block, holes) in blocks())
        {
            if ((++_read & 0xFFF) == 0)
            {
                cancellationToken.ThrowIfCancellationRequested();
            }

            if (block.Motion == MotionKind.Cycle && holes is null)
            {
                missing++;
            }

            if (builder.Add(DrawnBlock.Of(block, holes), segments) > 0)
            {
                foreach (var segment in segments)
                {
                    yield return segment;
                }

                segments.Clear();
            }
        }

        _read = blockCount;
        CyclesWithoutHoles = missing;
        Units = builder.Units;
        MixedUnits = builder.MixedUnits;
    }
}
