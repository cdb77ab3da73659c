using System.Globalization;
using System.Text;

namespace PmacStream.GCode.Expansion;

/// <summary>
/// Expands a program's subprograms, macros and loops (FANUC/Haas subprograms and Custom Macro B, or LinuxCNC o-words)
/// into the flat lines the reader, the checker and the splitter already take, a buffer at a time: the source files are
/// held (loops and calls go back to their lines), the expansion never is. Lines without expressions are emitted byte
/// for byte as written; every emitted line is mapped to its origin (<see cref="Map"/>). A refusal (an endless loop, a
/// probe result read, <c>#3000</c> ...) ends the output and is kept in <see cref="Error"/>.
/// </summary>
public sealed partial class MacroExpander : IMacroVariables
{
    private const int LocalCount = 34;

    private readonly ExpansionOptions _o;
    private readonly MacroDialect _dialect;
    private readonly MachineProfile _profile;
    private readonly List<ProgramSource> _sources = [];
    private readonly Dictionary<string, ProgramSource> _byPath = new(StringComparer.Ordinal);
    private readonly double[] _globals = new double[10000];
    private readonly Dictionary<string, double> _globalNames = new(StringComparer.Ordinal);
    private readonly StringBuilder _text = new();
    private readonly Frame _main;
    private readonly Interpreter? _shadow;
    private byte[] _out = new byte[1 << 16];
    private int _outLen;
    private int _depth;
    private Frame _frame;
    private bool _done;
    private bool _emittedBlock;
    private MacroLine? _evaluating;
    private Frame _curFrame;   // the frame and line being run: where a refusal in an expression is reported
    private int _curLine;

    /// <summary>Starts the expansion of <paramref name="path"/> (nothing is read from it beyond the file itself yet).</summary>
    public MacroExpander(string path, ExpansionOptions options, ExpansionMap? map = null)
    {
        _o = options;
        _dialect = options.Dialect;
        _profile = options.Profile ?? MachineProfile.Default;
        Map = map ?? new ExpansionMap(1 << 16);
        Array.Fill(_globals, _dialect == MacroDialect.Fanuc ? double.NaN : 0);
        var main = Source(Path.GetFullPath(path));
        _main = _frame = _curFrame = new Frame(main, 0, NewLocals(), null, 0) { Name = string.Empty, Named = [] };
        if (options.PersistentVariablesFile is { } file)
        {
            foreach (var (k, v) in PersistentVariables.Load(file))
            {
                _globals[k] = v;
            }
        }

        // Positions at block end and the modal state are known only by interpreting the lines emitted: done only for
        // programs that read them (the interpreter costs as much again as the expansion).
        if (ReadsMachineState(main))
        {
            _shadow = new Interpreter(_profile) { MeasureMoves = false, RecordBlocks = false };
        }
    }

    /// <summary>Where each emitted line came from.</summary>
    public ExpansionMap Map { get; }

    /// <summary>The refusal that ended the expansion, null while none did.</summary>
    public ExpansionException? Error { get; private set; }

    /// <summary>True once the program has ended (or was refused).</summary>
    public bool Done => _done;

    /// <summary>Lines emitted so far.</summary>
    public long ExpandedLines => Map.Lines;

    /// <summary>
    /// True when the program needs the expander under <paramref name="dialect"/>: some line holds an expression, a
    /// variable, a call or flow (one look at each line; most programs have none and are read as they are).
    /// </summary>
    public static bool Needs(string path, MacroDialect dialect)
    {
        if (dialect == MacroDialect.None)
        {
            return false;
        }

        using var s = new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        return Needs(s, dialect);
    }

    /// <summary>
    /// The same for a stream (read to its end or to the first line that needs it). Fast on programs without macros:
    /// the buffer is searched for what can start a statement (<c>#</c>, <c>[</c>, <c>M98</c>, <c>G65</c>, <c>GOTO</c>,
    /// an o-word ...), and only lines holding one are compiled.
    /// </summary>
    public static bool Needs(Stream s, MacroDialect dialect)
    {
        var buffer = new byte[1 << 16];
        var have = 0;
                while (true)
        {
            var n = s.Read(buffer, have, buffer.Length - have);
            var end = have + n;
            var data = buffer.AsSpan(0, end);
            // Whole lines only, unless the input ended (or one line fills the buffer).
            var cut = n == 0 ? end : data.LastIndexOfAny((byte)'\n', (byte)'\r') + 1;
            if (cut <= 0)
            {
                cut = end;
            }

            if (Candidates(buffer.AsSpan(0, cut), dialect))
            {
                return true;
            }

            if (n == 0)
            {
                return false;
            }

            buffer.AsSpan(cut, end - cut).CopyTo(buffer);
            have = end - cut;
            if (have == buffer.Length)
            {
                Array.Resize(ref buffer, buffer.Length * 2);
            }
        }
    }

    // M98/M97/M99, G65/G66 and GOTO (WHILE and IF always come with a '['): few passes over a program without them.
    private static readonly byte[][] FanucMarks = ["M9"u8.ToArray(), "G6"u8.ToArray(), "GOTO"u8.ToArray(), "m9"u8.ToArray(), "g6"u8.ToArray(), "goto"u8.ToArray()];

    private static readonly byte[][] NgcMarks = ["O"u8.ToArray(), "o"u8.ToArray()];

    /// <summary>Looks at the lines of <paramref name="data"/> holding a mark; true at the first that needs the expander.</summary>
    private static bool Candidates(ReadOnlySpan<byte> data, MacroDialect dialect)
    {
        if (data.IndexOfAny((byte)'#', (byte)'[') >= 0 || AnyMark(data, dialect))
        {
            // Something to look at: line by line (rare for programs without macros).
            var pos = 0;
            while (pos < data.Length)
            {
                var e = data[pos..].IndexOfAny((byte)'\n', (byte)'\r');
                var line = e < 0 ? data[pos..] : data.Slice(pos, e);
                if (line.Length > 0 && (line.IndexOfAny((byte)'#', (byte)'[') >= 0 || AnyMark(line, dialect)) && NeedsLine(line, dialect))
                {
                    return true;
                }

                if (e < 0)
                {
                    break;
                }

                pos += e + 1;
            }

            return false;
        }

        return false;
    }

    private static bool AnyMark(ReadOnlySpan<byte> data, MacroDialect dialect)
    {
        foreach (var m in dialect == MacroDialect.Fanuc ? FanucMarks : NgcMarks)
        {
            if (data.IndexOf(m) >= 0)
            {
                return true;
            }
        }

        return false;
    }

    private static bool NeedsLine(ReadOnlySpan<byte> line, MacroDialect dialect)
    {
        if (MacroCompiler.IsPlain(line, dialect))
        {
            return false;
        }

        try
        {
            var c = MacroCompiler.Compile(Encoding.Latin1.GetString(line), dialect);
            // A program number is the program's own name on its first lines; one further down starts another program.
            // A program number alone needs nothing: only a call reaches the programs after the main one.
            return c.Kind is not (LineKind.Raw or LineKind.TapeMark or LineKind.ProgramNumber);
        }
        catch (MacroEvalException)
        {
            // Not a statement either: the reader names it (E101 for a stray '#' ...), as in a program without macros.
            return false;
        }
    }

    /// <summary>
    /// Expands until at least <paramref name="atLeast"/> bytes are waiting (or the program ended); the bytes are in
    /// <see cref="Output"/>. Never throws on content: a refusal ends the output and sets <see cref="Error"/>.
    /// </summary>
    public void Fill(int atLeast)
    {
        while (_outLen < atLeast && !_done)
        {
            var f = _curFrame = _frame;
            var ln = _curLine = f.Pc;
            try
            {
                if (ln >= f.Source.LineCount)
                {
                    if (f == _main)
                    {
                        Finish();
                        break;
                    }

                    throw Refuse(ExpansionCodes.Flow, 1, f.Source.LineCount > 0 ? $"{Describe(f)} runs to the end of its file without {(_dialect == MacroDialect.Fanuc ? "M99" : "endsub")}" : $"{Describe(f)} is empty", ln > 0 ? ln - 1 : 0);
                }

                var c = f.Source.Compiled(ln, _dialect);
                if (c == null)
                {
                    if (HasWord(f.Source.Line(ln)))
                    {
                        _emittedBlock = f.Started = true;
                    }

                    EmitRaw(f, ln);
                    f.Pc = ln + 1;
                    if (_modalCall != null && f == _modalOwner && MacroCompiler.Compile(Encoding.Latin1.GetString(f.Source.Line(ln)), _dialect) is { EndsProgram: false } plain && MovesAxes(plain.Words))
                    {
                        FanucCall(_modalCall, f, ln); // G66: after the move, the macro
                    }

                    continue;
                }

                Execute(c, f, ln);
            }
            catch (MacroEvalException e)
            {
                Stop(Make(e.Message.Contains("by zero", StringComparison.Ordinal) || e.Message.Contains("not defined", StringComparison.Ordinal) || e.Message.Contains("SQRT", StringComparison.Ordinal) || e.Message.Contains("LN", StringComparison.Ordinal) ? ExpansionCodes.Value : ExpansionCodes.Syntax, e.Column, e.Message, f, ln));
            }
            catch (ExpansionException e)
            {
                Stop(e);
            }
        }
    }

    /// <summary>The bytes expanded and not yet taken.</summary>
    public ReadOnlySpan<byte> Output => _out.AsSpan(0, _outLen);

    /// <summary>Takes <paramref name="count"/> bytes off the front of <see cref="Output"/>.</summary>
    public void Consume(int count)
    {
        _out.AsSpan(count, _outLen - count).CopyTo(_out);
        _outLen -= count;
    }

    /// <summary>Keeps the persistent variables (FANUC #500-#999) in <see cref="ExpansionOptions.PersistentVariablesFile"/>.</summary>
    public void SavePersistentVariables()
    {
        if (_o.PersistentVariablesFile is { } file)
        {
            PersistentVariables.Save(file, _globals);
        }
    }

    private void Stop(ExpansionException e)
    {
        Error ??= e;
        _done = true;
        Map.Complete();
    }

    private void Finish()
    {
        _done = true;
        Map.Complete();
    }

    private ProgramSource Source(string fullPath)
    {
        if (_byPath.TryGetValue(fullPath, out var s))
        {
            return s;
        }

        s = ProgramSource.Load(fullPath, _sources.Count, _o.MaxSourceBytes);
        _sources.Add(s);
        _byPath[fullPath] = s;
        Map.AddFile(fullPath);
        return s;
    }

    private double[] NewLocals()
    {
        var l = new double[LocalCount];
        Array.Fill(l, _dialect == MacroDialect.Fanuc ? double.NaN : 0);
        return l;
    }

    /// <summary>A source reads positions, modal state or offsets set while it runs: the expansion interprets what it emits.</summary>
    private static bool ReadsMachineState(ProgramSource s)
    {
        for (var i = 0; i < s.LineCount; i++)
        {
            var line = s.Line(i);
            var at = line.IndexOf((byte)'#');
            while (at >= 0 && at + 1 < line.Length)
            {
                var next = line[at + 1];
                if (next is (byte)'4' or (byte)'5' || (next == (byte)'<' && at + 2 < line.Length && line[at + 2] == (byte)'_'))
                {
                    return true;
                }

                var rest = line[(at + 1)..].IndexOf((byte)'#');
                at = rest < 0 ? -1 : at + 1 + rest;
            }
        }

        return false;
    }

    // ------------------------------------------------------------------ output

    /// <summary>A letter outside comments: the line is a block (not a tape mark, a comment or a blank line).</summary>
    private static bool HasWord(ReadOnlySpan<byte> line)
    {
        var inComment = false;
        foreach (var b in line)
        {
            if (inComment)
            {
                inComment = b != (byte)')';
            }
            else if (b == (byte)'(')
            {
                inComment = true;
            }
            else if (b == (byte)';')
            {
                return false;
            }
            else if ((uint)((b | 0x20) - 'a') <= 'z' - 'a')
            {
                return true;
            }
        }

        return false;
    }

    private void EmitRaw(Frame f, int ln)
    {
        CheckSize(ln);
        var bytes = f.Source.Line(ln);
        Reserve(bytes.Length + 1);
        bytes.CopyTo(_out.AsSpan(_outLen));
        _outLen += bytes.Length;
        _out[_outLen++] = (byte)'\n';
        Note(f, ln);
        if (_shadow != null)
        {
            Shadow(bytes);
        }
    }

    private void EmitText(Frame f, int ln)
    {
        CheckSize(ln);
        Reserve(_text.Length + 1);
        for (var i = 0; i < _text.Length; i++)
        {
            _out[_outLen++] = (byte)_text[i];
        }

        _out[_outLen++] = (byte)'\n';
        Note(f, ln);
        if (_shadow != null)
        {
            Shadow(Encoding.Latin1.GetBytes(_text.ToString()));
        }
    }

    private void Shadow(ReadOnlySpan<byte> bytes)
    {
        var block = GCodeReader.LexLine(Encoding.Latin1.GetString(bytes), (int)Math.Min(int.MaxValue, Map.Lines));
        if (block.WordList.Count > 0)
        {
            _shadow!.StepCore(block, null);
        }
    }

    private void Reserve(int n)
    {
        if (_outLen + n > _out.Length)
        {
            Array.Resize(ref _out, Math.Max(_out.Length * 2, _outLen + n));
        }
    }

    private void CheckSize(int ln)
    {
        if (Map.Lines >= _o.MaxExpandedLines)
        {
            throw Refuse(ExpansionCodes.SizeLimit, 1,
                $"the expansion is longer than {_o.MaxExpandedLines.ToString(CultureInfo.InvariantCulture)} lines (the expanded-size limit)", ln);
        }
    }

    private void Note(Frame f, int ln)
    {
        Map.Add(new SourceOrigin(f.Source.Index, ln + 1, f.MapId, f.Loops.Count > 0 ? f.Loops[^1].Iterations : 0));
    }

    /// <summary>Writes a block with its computed values (a vacant value leaves its word out, as FANUC does).</summary>
    private void EmitWords(MacroLine c, Frame f, int ln)
    {
        _text.Clear();
        if (c.BlockDelete)
        {
            _text.Append('/');
        }

        if (!double.IsNaN(c.N))
        {
            _text.Append('N');
            Number(c.N);
        }

        foreach (var w in c.Words)
        {
            var v = w.Value.Eval(this);
            if (double.IsNaN(v))
            {
                continue;
            }

            if (_text.Length > 0)
            {
                _text.Append(' ');
            }

            _text.Append(w.Letter);
            Number(v);
        }

        EmitText(f, ln);
    }

    /// <summary>A value as the reader takes it: up to 6 decimals, no exponent.</summary>
    private void Number(double v)
    {
        var scaled = Math.Round(Math.Abs(v) * 1e6);
        if (scaled >= 9e17 || double.IsInfinity(v))
        {
            throw new MacroEvalException(1, $"value {v.ToString(CultureInfo.InvariantCulture)} too large for a word");
        }

        var units = (long)scaled;
        if (v < 0 && units != 0)
        {
            _text.Append('-');
        }

        _text.Append(units / 1_000_000);
        var frac = units % 1_000_000;
        if (frac != 0)
        {
            // Six decimals, trailing zeros dropped; digits written here (a string per value would cost more than the value).
            _text.Append('.');
            var div = 100_000L;
            while (frac != 0)
            {
                var digit = frac / div;
                _text.Append((char)('0' + digit));
                frac -= digit * div;
                div /= 10;
            }
        }
    }

    // ------------------------------------------------------------------ errors and descriptions

    private ExpansionException Refuse(string code, int column, string message, int ln) => Make(code, column, message, _curFrame, ln);

    private ExpansionException Make(string code, int column, string message, Frame f, int ln)
    {
        var outer = f;
        while (outer.Caller is { } caller && caller.Caller != null)
        {
            outer = caller;
        }

        return new(code, f.Source.Path, ln + 1, column, message, Context(f)) { MainLine = f == _main ? ln + 1 : outer.CallLine + 1 };
    }

    private static string Describe(Frame f) => f.Name.Length == 0 ? "the program" : f.Name;

    /// <summary>The calls and loops a line runs in: <c>call 3 of 4 from line 12</c>.</summary>
    private string Context(Frame f)
    {
        var sb = new StringBuilder();
        if (f.Loops.Count > 0)
        {
            sb.Append(CultureInfo.InvariantCulture, $"iteration {f.Loops[^1].Iterations}");
        }

        for (var x = f; x.Caller != null; x = x.Caller)
        {
            if (sb.Length > 0)
            {
                sb.Append(", ");
            }

            sb.Append(CultureInfo.InvariantCulture, $"{x.Name} call {x.CallNumber} of {x.CallCount} from ");
            sb.Append(x.Caller.Source != _main.Source ? $"{Path.GetFileName(x.Caller.Source.Path)} " : string.Empty);
            sb.Append(CultureInfo.InvariantCulture, $"line {x.CallLine + 1}");
        }

        return sb.ToString();
    }

    /// <summary>A call in progress: the program, where it runs, its locals and its loops.</summary>
    private MacroLine? _modalCall; // G66: the macro call made after every move block of _modalOwner, until G67
    private Frame? _modalOwner;

    private sealed class Frame(ProgramSource source, int start, double[] locals, Frame? caller, int callLine)
    {
        public readonly ProgramSource Source = source;
        public readonly int Start = start;
        public readonly double[] Locals = locals;
        public readonly Frame? Caller = caller;
        public readonly int CallLine = callLine;
        public readonly List<Loop> Loops = [];
        public int Pc = start;
        public string Name = string.Empty;
        public int ProgramNumber = -1;
        public Dictionary<string, double>? Named;
        public long CallNumber = 1;
        public long CallCount = 1;
        public int MapId;
        public long BackJumps;
        public string Label = string.Empty;
        public int ProgramStart;
        public bool Started;
    }

    /// <summary>A loop in progress.</summary>
    private sealed class Loop(int head, int id, string label, string kind)
    {
        public readonly int Head = head;
        public readonly int Id = id;
        public readonly string Label = label;
        public readonly string Kind = kind;
        public long Iterations = 1;
        public long Left;
        public int End = -1;
    }
}
