using System.Text;

namespace PmacStream.GCode.Expansion;

/// <summary>
/// One program file held for the expansion: its bytes and where each line starts (a loop or a call goes back to a
/// line, so the source is held; the expansion is not). Lines are compiled once, when first run.
/// </summary>
internal sealed class ProgramSource
{
    private readonly byte[] _bytes;
    private readonly int[] _starts;   // start of each line; _starts[n] is the end
    private readonly int[] _lengths;
    private readonly MacroLine?[] _compiled;
    private readonly bool[] _plainKnown;
    private Dictionary<(int From, double N), int>? _byN;
    private Dictionary<int, int>? _programs;
    private Dictionary<string, int>? _subs;
    private int[]? _jumps;

    public ProgramSource(string path, int index, byte[] bytes)
    {
        Path = path;
        Index = index;
        _bytes = bytes;
        var starts = new List<int> { 0 };
        var lengths = new List<int>();
        var i = 0;
        while (i < bytes.Length)
        {
            var end = bytes.AsSpan(i).IndexOfAny((byte)'\n', (byte)'\r');
            if (end < 0)
            {
                lengths.Add(bytes.Length - i);
                i = bytes.Length;
                starts.Add(i);
                break;
            }

            lengths.Add(end);
            i += end + 1;
            if (bytes[i - 1] == '\r' && i < bytes.Length && bytes[i] == '\n')
            {
                i++;
            }

            starts.Add(i);
        }

        _starts = [.. starts];
        _lengths = [.. lengths];
        _compiled = new MacroLine?[_lengths.Length];
        _plainKnown = new bool[_lengths.Length];
    }

    /// <summary>The file's full path.</summary>
    public string Path { get; }

    /// <summary>Its number in the expansion map.</summary>
    public int Index { get; }

    /// <summary>Lines in the file.</summary>
    public int LineCount => _lengths.Length;

    /// <summary>Line <paramref name="line"/> (0-based) as bytes, without its line end.</summary>
    public ReadOnlySpan<byte> Line(int line) => _bytes.AsSpan(_starts[line], _lengths[line]);

    /// <summary>The compiled line (null: plain, emitted as written).</summary>
    public MacroLine? Compiled(int line, MacroDialect dialect)
    {
        if (_compiled[line] is { } c)
        {
            return c;
        }

        if (_plainKnown[line])
        {
            return null;
        }

        var bytes = Line(line);
        if (MacroCompiler.IsPlain(bytes, dialect))
        {
            _plainKnown[line] = true;
            return null;
        }

        return _compiled[line] = MacroCompiler.Compile(Encoding.Latin1.GetString(bytes), dialect);
    }

    /// <summary>
    /// The line holding N <paramref name="n"/> in the program starting at line <paramref name="from"/> (up to the next
    /// program number; subprograms of one file often use the same N numbers), -1 when none.
    /// </summary>
    public int FindN(double n, int from, MacroDialect dialect)
    {
        _byN ??= [];
        if (_byN.TryGetValue((from, n), out var found))
        {
            return found;
        }

        var result = -1;
        for (var i = from; i < LineCount; i++)
        {
            var t = Line(i).TrimStart(" \t/"u8);
            if (t.Length > 1 && t[0] is (byte)'N' or (byte)'n')
            {
                try
                {
                    if (MacroCompiler.Compile(Encoding.Latin1.GetString(Line(i)), dialect).N == n)
                    {
                        result = i;
                        break;
                    }
                }
                catch (MacroEvalException)
                {
                    // Reported when the line runs.
                }
            }
            else if (i > from && t.Length > 1 && t[0] is (byte)'O' or (byte)'o' or (byte)':' && t[1] is >= (byte)'0' and <= (byte)'9' && dialect == MacroDialect.Fanuc)
            {
                break; // the next program
            }
        }

        _byN[(from, n)] = result;
        return result;
    }

    /// <summary>FANUC programs in this file: the line of <c>O<paramref name="number"/></c> (-1: none).</summary>
    public int FindProgram(int number)
    {
        if (_programs == null)
        {
            _programs = [];
            for (var i = 0; i < LineCount; i++)
            {
                var t = Line(i).TrimStart(" \t"u8);
                if (t.Length > 1 && t[0] is (byte)'O' or (byte)'o' or (byte)':' && t[1] is >= (byte)'0' and <= (byte)'9')
                {
                    var n = 0;
                    var k = 1;
                    while (k < t.Length && t[k] is >= (byte)'0' and <= (byte)'9' && n < 100_000_000)
                    {
                        n = (n * 10) + (t[k++] - '0');
                    }

                    _programs.TryAdd(n, i);
                }
            }
        }

        return _programs.TryGetValue(number, out var at) ? at : -1;
    }

    /// <summary>RS274/NGC subroutines in this file: the line of <c>o&lt;name&gt; sub</c> (-1: none).</summary>
    public int FindSub(string label)
    {
        if (_subs == null)
        {
            _subs = [];
            for (var i = 0; i < LineCount; i++)
            {
                if (Compiled(i, MacroDialect.LinuxCnc) is { Kind: LineKind.OWord, Keyword: "SUB" } c)
                {
                    _subs.TryAdd(c.Label, i);
                }
            }
        }

        return _subs.TryGetValue(label, out var at) ? at : -1;
    }

    /// <summary>A jump target found once for a flow line (-2: not yet looked up).</summary>
    public ref int Jump(int line)
    {
        _jumps ??= Enumerable.Repeat(-2, LineCount).ToArray();
        return ref _jumps[line];
    }

    /// <summary>Reads a file whole (a program's source is bounded by the file; the limit keeps a mistake from taking all memory).</summary>
    public static ProgramSource Load(string path, int index, long maxBytes)
    {
        var info = new FileInfo(path);
        if (info.Length > maxBytes)
        {
            throw new IOException($"{path}: {info.Length} bytes; a program with subprograms or macros is held whole while it is expanded, at most {maxBytes} bytes");
        }

        return new ProgramSource(info.FullName, index, File.ReadAllBytes(path));
    }
}
