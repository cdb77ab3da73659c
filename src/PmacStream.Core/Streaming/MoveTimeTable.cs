namespace PmacStream.Streaming;

/// <summary>Move times by tracked source line as prefix sums: O(log n) for any span, 12 bytes a block.</summary>
public sealed class MoveTimeTable : IMoveTimes
{
    private readonly int[] _lines;
    private readonly double[] _prefix;

    /// <summary>Builds the table from (source line, seconds) pairs in source order.</summary>
    public MoveTimeTable(IEnumerable<(int Line, double Seconds)> moves)
    {
        var lines = new List<int>();
        var prefix = new List<double> { 0 };
        var sum = 0.0;
        foreach (var (line, seconds) in moves)
        {
            if (lines.Count > 0 && line <= lines[^1])
            {
                // Several moves of one block (or out of order): fold into the last entry.
                sum += Math.Max(0, seconds);
                prefix[^1] = sum;
                continue;
            }

            lines.Add(line);
            sum += Math.Max(0, seconds);
            prefix.Add(sum);
        }

        _lines = lines.ToArray();
        _prefix = prefix.ToArray();
    }

    /// <summary>Total seconds of all blocks.</summary>
    public double TotalSeconds => _prefix[^1];

    /// <summary>Number of blocks with a time.</summary>
    public int Count => _lines.Length;

    /// <inheritdoc />
    public double SecondsBetween(int afterLine, int throughLine) =>
        throughLine <= afterLine ? 0 : Through(throughLine) - Through(afterLine);

    /// <summary>Seconds of the blocks up to and including <paramref name="line"/>.</summary>
    public double Through(int line)
    {
        var i = Array.BinarySearch(_lines, line);
        if (i < 0)
        {
            i = ~i - 1;
        }

        return _prefix[i + 1];
    }
}
