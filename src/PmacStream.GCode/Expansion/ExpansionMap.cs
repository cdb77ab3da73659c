using System.Globalization;
using System.Text;

namespace PmacStream.GCode.Expansion;

/// <summary>One call in an expansion: which program ran, from which line of its caller, and which of its repeats.</summary>
/// <param name="Id">Its number (0 is the main program).</param>
/// <param name="Parent">The caller's frame.</param>
/// <param name="File">The file (index into <see cref="ExpansionMap.Files"/>) holding the called program.</param>
/// <param name="Program">What was called (<c>O1002</c>, <c>N500</c> for M97, <c>o&lt;name&gt;</c>).</param>
/// <param name="CallLine">The calling line in the caller's file (1-based).</param>
/// <param name="Call">Which repeat this is (1-based).</param>
/// <param name="Calls">Repeats the call asked for.</param>
public readonly record struct ExpansionFrame(int Id, int Parent, int File, string Program, int CallLine, int Call, int Calls);

/// <summary>Where an expanded line came from.</summary>
/// <param name="File">Index into <see cref="ExpansionMap.Files"/>.</param>
/// <param name="Line">1-based line in that file.</param>
/// <param name="Frame">The call it ran in (0: the main program).</param>
/// <param name="Iteration">The innermost loop's iteration (1-based; 0 outside loops).</param>
public readonly record struct SourceOrigin(int File, int Line, int Frame, long Iteration);

/// <summary>
/// The map from expanded lines (what <c>M0==</c> indexes in an expanded program) back to the source: file, line, call
/// stack and iteration, kept as runs of consecutive lines. Written beside a split as <see cref="FileName"/>; held in
/// memory while checking only for the most recent <c>capacity</c> runs and frames, so memory stays bounded.
/// </summary>
public sealed class ExpansionMap
{
    /// <summary>The side file's name in a split's folder.</summary>
    public const string FileName = "expansion.map";

    private const string Magic = "pmacstream-expansion 1";

    private readonly int _capacity;
    private readonly List<Run> _runs = [];
    private readonly List<ExpansionFrame> _frames = [];
    private readonly List<string> _files = [];
    private long _runsDropped;
    private int _framesDropped;
    private TextWriter? _writer;

    /// <summary>A map holding at most about <paramref name="capacity"/> recent runs and frames (int.MaxValue: all).</summary>
    public ExpansionMap(int capacity = int.MaxValue)
    {
        _capacity = capacity;
        _frames.Add(new ExpansionFrame(0, -1, 0, string.Empty, 0, 1, 1));
    }

    /// <summary>The files of the expansion: 0 is the program, the others subprogram files.</summary>
    public IReadOnlyList<string> Files => _files;

    /// <summary>Expanded lines mapped so far.</summary>
    public long Lines { get; private set; }

    /// <summary>Also writes every file, frame and run to <paramref name="writer"/> (the side file of a split).</summary>
    public void WriteTo(TextWriter writer)
    {
        _writer = writer;
        writer.Write(Magic);
        writer.Write('\n');
    }

    internal void AddFile(string path)
    {
        _files.Add(path);
        _writer?.Write(FormattableString.Invariant($"F {_files.Count - 1} {path}\n"));
    }

    internal int AddFrame(int parent, int file, string program, int callLine, int call, int calls)
    {
        var id = _framesDropped + _frames.Count;
        _frames.Add(new ExpansionFrame(id, parent, file, program, callLine, call, calls));
        _writer?.Write(FormattableString.Invariant($"C {id} {parent} {file} {callLine} {call} {calls} {program}\n"));
        if (_frames.Count > 2 * _capacity)
        {
            _frames.RemoveRange(1, _capacity); // the main frame stays
            _framesDropped += _capacity;
        }

        return id;
    }

    /// <summary>Maps the next expanded line to its origin (joined to the run before when it continues it).</summary>
    internal void Add(in SourceOrigin o)
    {
        Lines++;
        if (_runs.Count > 0)
        {
            var last = _runs[^1];
            if (last.File == o.File && last.Frame == o.Frame && last.Iteration == o.Iteration && last.Line + last.Count == o.Line)
            {
                _runs[^1] = last with { Count = last.Count + 1 };
                return;
            }

            Flush(last);
        }

        _runs.Add(new Run(Lines, 1, o.File, o.Line, o.Frame, o.Iteration));
        if (_runs.Count > 2 * _capacity)
        {
            _runs.RemoveRange(0, _capacity);
            _runsDropped += _capacity;
        }
    }

    /// <summary>Writes the last run out (the end of the expansion).</summary>
    internal void Complete()
    {
        if (_runs.Count > 0)
        {
            Flush(_runs[^1]);
        }

        _writer?.Flush();
    }

    private void Flush(in Run r) =>
        _writer?.Write(FormattableString.Invariant($"R {r.Start} {r.Count} {r.File} {r.Line} {r.Frame} {r.Iteration}\n"));

    /// <summary>Where expanded line <paramref name="line"/> came from; null when the map no longer holds it.</summary>
    public SourceOrigin? Find(long line)
    {
        int lo = 0, hi = _runs.Count - 1;
        while (lo <= hi)
        {
            var mid = (lo + hi) >>> 1;
            var r = _runs[mid];
            if (line < r.Start)
            {
                hi = mid - 1;
            }
            else if (line >= r.Start + r.Count)
            {
                lo = mid + 1;
            }
            else
            {
                return new SourceOrigin(r.File, r.Line + (int)(line - r.Start), r.Frame, r.Iteration);
            }
        }

        return null;
    }

    /// <summary>A frame by its id; null when no longer held.</summary>
    public ExpansionFrame? Frame(int id) =>
        id == 0 ? _frames[0] : id - _framesDropped is var i && i >= 1 && i < _frames.Count ? _frames[i] : null;

    /// <summary>The line of the main program an expanded line runs for (the outermost call's line), 0 when not held.</summary>
    public int MainLine(long line)
    {
        if (Find(line) is not { } o)
        {
            return 0;
        }

        var l = o.Line;
        for (var f = o.Frame; f != 0;)
        {
            if (Frame(f) is not { } fr)
            {
                return 0;
            }

            l = fr.CallLine;
            f = fr.Parent;
        }

        return l;
    }

    /// <summary>Where an expanded line came from in words: <c>O1002 line 7, call 3 of 4 from line 12</c>.</summary>
    public string Describe(long line)
    {
        if (Find(line) is not { } o)
        {
            return FormattableString.Invariant($"expanded line {line}");
        }

        var sb = new StringBuilder();
        var f = o.Frame;
        var first = Frame(f);
        sb.Append(first is { Id: not 0 } fr0 ? $"{fr0.Program} " : o.File != 0 ? $"{Path.GetFileName(_files[o.File])} " : string.Empty);
        sb.Append(CultureInfo.InvariantCulture, $"line {o.Line}");
        if (o.Iteration > 0)
        {
            sb.Append(CultureInfo.InvariantCulture, $", iteration {o.Iteration}");
        }

        while (f != 0)
        {
            if (Frame(f) is not { } fr)
            {
                sb.Append(", called from a line no longer held");
                break;
            }

            var parent = Frame(fr.Parent);
            sb.Append(CultureInfo.InvariantCulture, $", call {fr.Call} of {fr.Calls} from ");
            if (parent is { Id: not 0 } p)
            {
                sb.Append(p.Program).Append(' ');
            }

            sb.Append(CultureInfo.InvariantCulture, $"line {fr.CallLine}");
            f = fr.Parent;
        }

        return sb.ToString();
    }

    /// <summary>
    /// The expanded lines that ran source line <paramref name="line"/>, in the order they run, with the file each is a
    /// line of (at most <paramref name="max"/>): the first is its first run, the third its third call. With
    /// <paramref name="where"/>, only the lines of that file (its name, with or without extension) or of that called
    /// program (<c>O1002</c>, <c>o&lt;name&gt;</c>, <c>N500</c>), for a line number more than one file has.
    /// </summary>
    public List<(long Expanded, int File)> Occurrences(int line, string? where, int max = int.MaxValue)
    {
        var found = new List<(long, int)>();
        foreach (var r in _runs)
        {
            if (line < r.Line || line >= r.Line + r.Count || (where != null && !Names(r, where)))
            {
                continue;
            }

            found.Add((r.Start + (line - r.Line), r.File));
            if (found.Count >= max)
            {
                break;
            }
        }

        return found;
    }

    private bool Names(in Run r, string name)
    {
        var file = _files.Count > r.File ? _files[r.File] : string.Empty;
        return string.Equals(Path.GetFileName(file), name, StringComparison.OrdinalIgnoreCase) ||
            string.Equals(Path.GetFileNameWithoutExtension(file), name, StringComparison.OrdinalIgnoreCase) ||
            (Frame(r.Frame) is { Id: not 0 } f && string.Equals(f.Program, name, StringComparison.OrdinalIgnoreCase));
    }

    /// <summary>Reads a map a split wrote (all of it).</summary>
    public static ExpansionMap Load(string path)
    {
        using var r = new StreamReader(path, Encoding.UTF8);
        return Read(r, path);
    }

    /// <summary>Reads a map as a split writes it (all of it) from <paramref name="r"/>; <paramref name="name"/> names it in an error.</summary>
    public static ExpansionMap Read(TextReader r, string name)
    {
        ArgumentNullException.ThrowIfNull(r);
        var map = new ExpansionMap();
        if (r.ReadLine() != Magic)
        {
            throw new InvalidDataException($"{name}: not an expansion map");
        }

        while (r.ReadLine() is { } line)
        {
            if (line.Length < 2)
            {
                continue;
            }

            var parts = line.Split(' ', line[0] == 'C' ? 8 : line[0] == 'F' ? 3 : 7);
            var n = (string s) => long.Parse(s, CultureInfo.InvariantCulture);
            switch (line[0])
            {
                case 'F':
                    map._files.Add(parts[2]);
                    break;
                case 'C':
                    map._frames.Add(new ExpansionFrame((int)n(parts[1]), (int)n(parts[2]), (int)n(parts[3]), parts[7], (int)n(parts[4]), (int)n(parts[5]), (int)n(parts[6])));
                    break;
                case 'R':
                    map._runs.Add(new Run(n(parts[1]), (int)n(parts[2]), (int)n(parts[3]), (int)n(parts[4]), (int)n(parts[5]), n(parts[6])));
                    map.Lines = n(parts[1]) + n(parts[2]) - 1;
                    break;
            }
        }

        return map;
    }

    private readonly record struct Run(long Start, int Count, int File, int Line, int Frame, long Iteration);
}
