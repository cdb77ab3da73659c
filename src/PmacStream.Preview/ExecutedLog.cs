using System.Globalization;
using PmacStream.GCode;
using PmacStream.Pmac;

namespace PmacStream.Preview;

/// <summary>One row of the simulator's executed-move log (<c>sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block</c>).</summary>
/// <param name="Sequence">Running number of the executed move.</param>
/// <param name="Line">Source line the controller was tracking for the move.</param>
/// <param name="StartSeconds">Virtual time the move started.</param>
/// <param name="EndSeconds">Virtual time the move ended.</param>
/// <param name="End">Where the move ended (mm, machine coordinates).</param>
/// <param name="Kind">Move kind as the simulator names it (rapid, linear, circle, dwell ...).</param>
public readonly record struct ExecutedLogRow(long Sequence, long Line, double StartSeconds, double EndSeconds, Point3 End, string Kind)
{
    /// <summary>A, B, C at the end (degrees; 0 in a log written before the rotary columns).</summary>
    public (double A, double B, double C) Rotary { get; init; }

    /// <summary>True when the move starts a block (its synchronous tracking assignment fired); null in a log written before the block column.</summary>
    public bool? BlockStart { get; init; }
}

/// <summary>
/// Streams an executed-move log CSV row by row (a log as long as the program never sits in memory). Bad input is
/// reported as <see cref="InvalidDataException"/> naming the file, line and column.
/// </summary>
public static class ExecutedLogReader
{
    /// <summary>The header the simulator writes.</summary>
    public const string BlockHeader = "sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block";

    /// <summary>The header of logs written before the block column (still read).</summary>
    public const string Header = "sequence,line,start_s,end_s,x,y,z,a,b,c,kind";

    /// <summary>The header of logs written before the rotary columns (still read).</summary>
    public const string LinearHeader = "sequence,line,start_s,end_s,x,y,z,kind";

    private static readonly string[] Columns = Header.Split(',');
    private static readonly string[] LinearColumns = LinearHeader.Split(',');

    /// <summary>Reads every row of the log at <paramref name="path"/>.</summary>
    public static IEnumerable<ExecutedLogRow> Read(string path, CancellationToken cancellationToken = default)
    {
        using var reader = new StreamReader(path, System.Text.Encoding.UTF8, true, 1 << 16);
        var name = Path.GetFileName(path);
        var header = reader.ReadLine();
        var trimmed = header?.Trim().TrimStart('\uFEFF');
        var block = string.Equals(trimmed, BlockHeader, StringComparison.OrdinalIgnoreCase);
        var rotary = block || string.Equals(trimmed, Header, StringComparison.OrdinalIgnoreCase);
        if (!rotary && !string.Equals(trimmed, LinearHeader, StringComparison.OrdinalIgnoreCase))
        {
            throw new InvalidDataException($"{name}:1:1: expected the header '{BlockHeader}', found '{header ?? "<empty file>"}'");
        }

        var lineNo = 1L;
        string? text;
        while ((text = reader.ReadLine()) is not null)
        {
            lineNo++;
            if ((lineNo & 0xFFF) == 0)
            {
                cancellationToken.ThrowIfCancellationRequested();
            }

            if (text.Length == 0)
            {
                continue;
            }

            yield return block ? ParseBlockRow(text, name, lineNo) : ParseRow(text, name, lineNo, rotary);
        }
    }

    /// <summary>Parses one data row (exposed for tests); <paramref name="rotary"/>: the row has the a, b, c columns.</summary>
    internal static ExecutedLogRow ParseRow(string text, string name, long lineNo, bool rotary = true)
    {
        var columns = rotary ? Columns : LinearColumns;
        Span<Range> parts = stackalloc Range[12];
        var span = text.AsSpan();
        var n = span.Split(parts, ',');
        if (n != columns.Length)
        {
            throw new InvalidDataException($"{name}:{lineNo}:1: expected {columns.Length} comma-separated fields ({string.Join(',', columns)}), found {Math.Min(n, columns.Length + 1)}{(n > columns.Length ? " or more" : string.Empty)}");
        }

        var row = new ExecutedLogRow(
            Int(text, parts, 0, name, lineNo, 0), Int(text, parts, 1, name, lineNo, long.MinValue), Num(text, parts, 2, name, lineNo), Num(text, parts, 3, name, lineNo),
            new Point3(Num(text, parts, 4, name, lineNo), Num(text, parts, 5, name, lineNo), Num(text, parts, 6, name, lineNo)),
            span[parts[columns.Length - 1]].Trim().ToString());
        return rotary ? row with { Rotary = (Num(text, parts, 7, name, lineNo), Num(text, parts, 8, name, lineNo), Num(text, parts, 9, name, lineNo)) } : row;
    }

    /// <summary>Parses a data row of a log with the block column: the row before it, and the mark (1 or 0).</summary>
    private static ExecutedLogRow ParseBlockRow(string text, string name, long lineNo)
    {
        var comma = text.LastIndexOf(',');
        var mark = comma < 0 ? string.Empty : text[(comma + 1)..].Trim();
        if (mark is not ("0" or "1"))
        {
            throw new InvalidDataException($"{name}:{lineNo}:{comma + 2}: column 'block' expects 1 or 0, found '{mark}'");
        }

        return ParseRow(text[..comma], name, lineNo) with { BlockStart = mark == "1" };
    }

    private static double Num(string text, ReadOnlySpan<Range> parts, int i, string name, long lineNo)
    {
        var field = text.AsSpan()[parts[i]].Trim();
        if (!double.TryParse(field, NumberStyles.Float, CultureInfo.InvariantCulture, out var v) || !double.IsFinite(v))
        {
            throw new InvalidDataException($"{name}:{lineNo}:{parts[i].Start.GetOffset(text.Length) + 1}: column '{Columns[i]}' expects a number, found '{field.ToString()}'");
        }

        return v;
    }

    private static long Int(string text, ReadOnlySpan<Range> parts, int i, string name, long lineNo, long min)
    {
        var field = text.AsSpan()[parts[i]].Trim();
        if (!long.TryParse(field, NumberStyles.Integer, CultureInfo.InvariantCulture, out var v) || v < min)
        {
            var what = min == 0 ? "a whole number >= 0" : "a whole number";
            throw new InvalidDataException($"{name}:{lineNo}:{parts[i].Start.GetOffset(text.Length) + 1}: column '{Columns[i]}' expects {what}, found '{field.ToString()}'");
        }

        return v;
    }
}

/// <summary>
/// How often each source line was executed (saturating at 255), one byte per line number. A log with the block column
/// counts the blocks its marks start (<see cref="BlockStarts"/>: a one-move block run twice in a row counts twice, a
/// block's further moves not at all; a block the host expands into several controller lines, each with its tracking
/// assignment, counts once per <c>expandedBlocks</c> assignments). A log without it folds consecutive rows of one line
/// into one execution (one block may become several controller moves; running it again after other lines is what
/// counts twice). Lines of 0 or less (no tracking value yet) are not counted.
/// </summary>
/// <param name="expandedBlocks">
/// The blocks that carry more than one tracking assignment, by source line, with how many (<see cref="BlockStarts"/>);
/// <see cref="int.MaxValue"/> folds a line's consecutive marks into one execution. Null: every block has one.
/// </param>
public sealed class ExecutionCounts(IReadOnlyDictionary<int, int>? expandedBlocks = null)
{
    private const long MaxCountedLine = int.MaxValue - 64;
    private readonly BlockStarts _starts = new(expandedBlocks);
    private byte[] _counts = new byte[1024];
    private long _previous = long.MinValue;

    /// <summary>Rows counted.</summary>
    public long Rows { get; private set; }

    /// <summary>Highest line number seen.</summary>
    public long MaxLine { get; private set; }

    /// <summary>
    /// Counts one log row of <paramref name="line"/>; <paramref name="blockStart"/> is the row's block mark (null: a
    /// log without the block column, whose consecutive rows of one line are folded).
    /// </summary>
    public void Add(long line, bool? blockStart = null)
    {
        Rows++;
        var same = line == _previous;
        _previous = line;
        if (line <= 0 || line > MaxCountedLine)
        {
            return;
        }

        var starts = blockStart is { } mark ? _starts.Next((int)line, mark) : !same;
        if (!starts)
        {
            return;
        }

        if (line >= _counts.Length)
        {
            var size = _counts.Length;
            while (size <= line)
            {
                size = (int)Math.Min(MaxCountedLine, size * 2L);
            }

            Array.Resize(ref _counts, size);
        }

        if (_counts[line] < 255)
        {
            _counts[line]++;
        }

        MaxLine = Math.Max(MaxLine, line);
    }

    /// <summary>Times <paramref name="line"/> was executed (255 means 255 or more).</summary>
    public int this[long line] => line >= 0 && line < _counts.Length ? _counts[line] : 0;
}

/// <summary>A run of consecutive source lines (as listed in the report), with how often they ran.</summary>
/// <param name="First">First line of the run.</param>
/// <param name="Last">Last line of the run.</param>
/// <param name="Times">Executions of each line in the run (0 for a gap).</param>
public readonly record struct LineRun(long First, long Last, int Times)
{
    /// <inheritdoc />
    public override string ToString() => First == Last ? $"line {First}" : $"lines {First}-{Last}";
}

/// <summary>What the executed log says about the program: motion lines never executed, and lines executed twice or more.</summary>
public sealed class ExecutionReport
{
    /// <summary>At most this many runs are listed per kind (the rest are only counted).</summary>
    public const int MaxRuns = 200;

    internal readonly List<LineRun> MissingList = new();
    internal readonly List<LineRun> RepeatedList = new();

    /// <summary>Rows in the log.</summary>
    public long LogRows { get; internal set; }

    /// <summary>Drawn motion lines of the program that the log never executed.</summary>
    public long MissingLines { get; internal set; }

    /// <summary>Lines the log executed more than once.</summary>
    public long RepeatedLines { get; internal set; }

    /// <summary>The never-executed lines as runs of consecutive motion lines (first <see cref="MaxRuns"/>).</summary>
    public IReadOnlyList<LineRun> Missing => MissingList;

    /// <summary>The repeated lines as runs of consecutive lines with equal counts (first <see cref="MaxRuns"/>).</summary>
    public IReadOnlyList<LineRun> Repeated => RepeatedList;

    /// <summary>True when every drawn motion line ran exactly once.</summary>
    public bool IsExact => MissingLines == 0 && RepeatedLines == 0;

    internal static void AddRun(List<LineRun> list, long line, int times, long previousLine)
    {
        if (list.Count > 0)
        {
            var last = list[^1];
            if (last.Times == times && last.Last == previousLine)
            {
                list[^1] = last with { Last = line };
                return;
            }
        }

        if (list.Count < MaxRuns)
        {
            list.Add(new LineRun(line, line, times));
        }
    }
}
