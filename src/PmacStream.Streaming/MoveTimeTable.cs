using PmacStream.GCode;

namespace PmacStream.Streaming;

/// <summary>
/// Move times by tracked source line as prefix sums: O(log n) for any span, 16 bytes a sample. Every block is a
/// sample up to <see cref="DefaultMaxSamples"/> blocks; beyond that only every k-th block is kept (k doubles as the
/// program grows) and spans inside a sampling interval are interpolated by line number, so a gigabyte program still
/// gets an ETA from the interpreter's times in a few megabytes.
/// </summary>
public sealed class MoveTimeTable : IMoveTimes
{
    /// <summary>
    /// Move times of every motion block of a source, from the interpreter (seconds at programmed feed), for the ETA
    /// and the adaptive lead. Memory stays bounded for any size: past <paramref name="maxSamples"/> blocks the table
    /// keeps every k-th block and interpolates between (see the class).
    /// </summary>
    public static MoveTimeTable FromProgram(string sourcePath, int maxSamples = DefaultMaxSamples, MachineProfile? profile = null)
    {
        return new MoveTimeTable(Moves(sourcePath, profile ?? MachineProfile.Default), maxSamples);

        static IEnumerable<(int, double, double)> Moves(string path, MachineProfile profile)
        {
            var motions = new LastMotion();
            var interp = new Interpreter(profile) { Canon = motions };
            using var reader = GCode.Expansion.ProgramExpansion.OpenReader(path, profile);
            // G41/G42: the move held and the plunges queued behind it; an inside corner at the next XY move shortens
            // the held one (the queued ones keep their length: they run at the crossing instead).
            var held = new HeldMoves<CanonMotion>((m, crossing, first) => first
                ? Amended(m, AmendedMove.MovedTo(m.End, crossing))
                : m with { Start = AmendedMove.MovedTo(m.Start, crossing), End = AmendedMove.MovedTo(m.End, crossing) });
            var moves = new List<CanonMotion>(1);
            var final = new List<CanonMotion>(2);
            while (reader.Read())
            {
                // The interpreter's allocation-free step: a gigabyte program is tens of millions of blocks.
                if (interp.Execute(reader.Current))
                {
                    moves.Clear();
                    if (motions.Take() is { } m)
                    {
                        moves.Add(m);
                    }

                    held.Take(motions.Hold, motions.AmendedEnd, moves, final);
                    foreach (var f in final)
                    {
                        yield return Sample(f);
                    }

                    final.Clear();
                }
            }

            held.Flush(final);
            foreach (var f in final)
            {
                yield return Sample(f);
            }
        }

        static (int, double, double) Sample(CanonMotion m) => MoveTimeTable.Sample(m.Line, m.Kind, m.Seconds, m.Feed);
    }

    /// <summary>
    /// Move times of blocks the interpreter decided earlier (a stored revision's blocks: line, kind, seconds at
    /// programmed feed with inside corners already applied, feed in force), in source order: the same table
    /// <see cref="FromProgram"/> builds from those blocks, without interpreting the source again.
    /// </summary>
    public static MoveTimeTable FromMoves(IEnumerable<(int Line, MotionKind Kind, double Seconds, double? Feed)> moves, int maxSamples = DefaultMaxSamples)
    {
        ArgumentNullException.ThrowIfNull(moves);
        return new MoveTimeTable(moves.Where(m => m.Kind != MotionKind.None).Select(m => Sample(m.Line, m.Kind, m.Seconds, m.Feed)), maxSamples);
    }

    private static (int, double, double) Sample(int line, MotionKind kind, double seconds, double? feed)
    {
        var s = kind is MotionKind.Linear or MotionKind.ArcCw or MotionKind.ArcCcw
            ? Math.Max(seconds, MinimumMoveSeconds) // the controller's shortest blended move
            : seconds;
        return (line, s, feed ?? double.NaN);
    }

    /// <summary>
    /// A compensated move whose end a G41/G42 inside corner moved back to where the offset paths cross: the controller
    /// runs it that much shorter, at the same feed (a line by its length, an arc by the angle it sweeps).
    /// </summary>
    internal static CanonMotion Amended(CanonMotion m, Point3 end)
    {
        var part = AmendedMove.Fraction(m.Kind, m.Start, m.End, m.Centre, end);
        return m with { End = end, Length = m.Length * part, Seconds = m.Seconds * part };
    }

    /// <summary>
    /// The motion of the block the interpreter took last, if it moved, and the inside corner it decided at that block
    /// (its canonical moves: nothing is asked of the interpreter).
    /// </summary>
    private sealed class LastMotion : ICanonicalMoves
    {
        private CanonMotion _motion;
        private bool _moved;

        /// <summary>Where the move before the last block ends instead, at a G41/G42 inside corner (<see cref="CanonBlock.AmendedEnd"/>).</summary>
        public Point3? AmendedEnd { get; private set; }

        /// <summary>The last block's part in the moves held under G41/G42 (<see cref="CanonBlock.Hold"/>).</summary>
        public CompensationHold Hold { get; private set; }

        public void StartBlock(in CanonStart start) => (_moved, AmendedEnd, Hold) = (false, null, CompensationHold.None);

        public void Step(in HostMove step)
        {
        }

        public void Motion(in CanonMotion motion) => (_motion, _moved) = (motion, true);

        public void EndBlock(in CanonBlock block) => (AmendedEnd, Hold) = (block.AmendedEnd, block.Hold);

        public CanonMotion? Take() => _moved ? _motion : null;
    }

    /// <summary>Samples kept before the table starts thinning (2 MB of samples).</summary>
    public const int DefaultMaxSamples = 131_072;

    /// <summary>
    /// The shortest a blended feed move takes on a Turbo PMAC set with TA = TS = 0 (0.5 ms, Turbo SRM p. 188;
    /// docs/turbo-pmac-timing.md): a program's tiny segments take at least this, so it runs at most 2,000 blocks/s.
    /// </summary>
    public const double MinimumMoveSeconds = 0.0005;

    private readonly int[] _lines;
    private readonly double[] _prefix;
    private readonly float[]? _feeds;
    private readonly int _stride;

    /// <summary>Builds the table from (source line, seconds) pairs in source order.</summary>
    public MoveTimeTable(IEnumerable<(int Line, double Seconds)> moves)
        : this(moves.Select(m => (m.Line, m.Seconds, double.NaN)), withFeeds: false, DefaultMaxSamples)
    {
    }

    /// <summary>Builds the table from (source line, seconds, programmed feed) in source order; the feeds give the live-feed ratio.</summary>
    public MoveTimeTable(IEnumerable<(int Line, double Seconds, double Feed)> moves)
        : this(moves, withFeeds: true, DefaultMaxSamples)
    {
    }

    /// <summary>As above, keeping at most <paramref name="maxSamples"/> samples (at least 2).</summary>
    public MoveTimeTable(IEnumerable<(int Line, double Seconds, double Feed)> moves, int maxSamples)
        : this(moves, withFeeds: true, maxSamples)
    {
    }

    private MoveTimeTable(IEnumerable<(int Line, double Seconds, double Feed)> moves, bool withFeeds, int maxSamples)
    {
        ArgumentOutOfRangeException.ThrowIfLessThan(maxSamples, 2);
        var lines = new List<int>();
        var prefix = new List<double> { 0 };
        var feeds = withFeeds ? new List<float>() : null;
        var sum = 0.0;
        var stride = 1;
        var blocks = 0;
        int curLine = int.MinValue;
        var curFeed = float.NaN;

        void Close()
        {
            // The block just finished becomes a sample when it is the stride-th one; thinning keeps every other
            // sample, which keeps exactly the blocks on the doubled stride.
            blocks++;
            if (blocks % stride != 0)
            {
                return;
            }

            lines.Add(curLine);
            prefix.Add(sum);
            feeds?.Add(curFeed);
            if (lines.Count > maxSamples)
            {
                Thin(lines, prefix, feeds);
                stride *= 2;
            }
        }

        foreach (var (line, seconds, feed) in moves)
        {
            if (curLine != int.MinValue && line <= curLine)
            {
                // Several moves of one block (or out of order): fold into the current block.
                sum += Math.Max(0, seconds);
                continue;
            }

            if (curLine != int.MinValue)
            {
                Close();
            }

            curLine = line;
            curFeed = (float)feed;
            sum += Math.Max(0, seconds);
        }

        if (curLine != int.MinValue)
        {
            Close();
            if (lines.Count == 0 || lines[^1] != curLine)
            {
                // The last block always ends the table, whatever the stride, so the total is exact.
                lines.Add(curLine);
                prefix.Add(sum);
                feeds?.Add(curFeed);
            }
        }

        BlockCount = blocks;
        _stride = stride;
        _lines = lines.ToArray();
        _prefix = prefix.ToArray();
        _feeds = feeds?.ToArray();
    }

    /// <inheritdoc />
    public double? ProgrammedFeedAt(int line)
    {
        if (_feeds is null || _lines.Length == 0)
        {
            return null;
        }

        var i = Array.BinarySearch(_lines, line);
        if (i < 0)
        {
            i = Math.Max(0, ~i - 1);
        }

        var f = _feeds[i];
        return float.IsFinite(f) && f > 0 ? f : null;
    }

    /// <summary>Total seconds of all blocks.</summary>
    public double TotalSeconds => _prefix[^1];

    /// <summary>Number of blocks with a time.</summary>
    public int Count => BlockCount;

    /// <summary>Number of blocks with a time.</summary>
    public int BlockCount { get; }

    /// <summary>Samples kept (equals <see cref="BlockCount"/> until the program outgrows the sample budget).</summary>
    public int SampleCount => _lines.Length;

    /// <inheritdoc />
    public double SecondsBetween(int afterLine, int throughLine) =>
        throughLine <= afterLine ? 0 : Through(throughLine) - Through(afterLine);

    /// <summary>Seconds of the blocks up to and including <paramref name="line"/> (interpolated inside a sampling interval).</summary>
    public double Through(int line)
    {
        var i = Array.BinarySearch(_lines, line);
        if (i >= 0)
        {
            return _prefix[i + 1];
        }

        var next = ~i;
        if (_stride == 1 || next >= _lines.Length)
        {
            // Every block is a sample (or the line lies past the last): no motion between the sample before and it.
            return _prefix[next];
        }

        var loLine = next == 0 ? 0 : _lines[next - 1];
        var lo = _prefix[next];
        var hi = _prefix[next + 1];
        return lo + ((hi - lo) * (line - loLine) / Math.Max(1, _lines[next] - loLine));
    }

    private static void Thin(List<int> lines, List<double> prefix, List<float>? feeds)
    {
        // Keep samples 1, 3, 5, ... (0-based): the later block of each pair. prefix[0] is the origin and stays.
        var n = lines.Count / 2;
        for (var k = 0; k < n; k++)
        {
            lines[k] = lines[(2 * k) + 1];
            prefix[k + 1] = prefix[(2 * k) + 2];
            if (feeds is not null)
            {
                feeds[k] = feeds[(2 * k) + 1];
            }
        }

        lines.RemoveRange(n, lines.Count - n);
        prefix.RemoveRange(n + 1, prefix.Count - n - 1);
        feeds?.RemoveRange(n, feeds.Count - n);
    }
}
