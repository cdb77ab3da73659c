using System.Globalization;

namespace PmacStream.GCode.Expansion;

/// <summary>Which subprogram and macro language a program is expanded in.</summary>
public enum MacroDialect
{
    /// <summary>None: the program is read as it is written.</summary>
    None,

    /// <summary>FANUC/Haas: <c>M98 P L</c>/<c>K</c>, <c>M99</c>, <c>M97</c>, <c>G65</c>, Custom Macro B.</summary>
    Fanuc,

    /// <summary>LinuxCNC RS274/NGC: o-word subroutines and flow, numbered and named parameters.</summary>
    LinuxCnc,
}

/// <summary>What a source line does in the expansion.</summary>
internal enum LineKind
{
    /// <summary>Emitted as written (no expression, no flow): blocks, comments, blank lines.</summary>
    Raw,

    /// <summary>A block with expressions: emitted with their values.</summary>
    Words,

    /// <summary>Only assignments (nothing emitted).</summary>
    Assign,

    /// <summary><c>%</c>.</summary>
    TapeMark,

    /// <summary>FANUC <c>O1234</c>: the start of a program.</summary>
    ProgramNumber,

    /// <summary>FANUC <c>IF [c] GOTO n</c>.</summary>
    IfGoto,

    /// <summary>FANUC <c>IF [c] THEN statement</c>.</summary>
    IfThen,

    /// <summary>FANUC <c>GOTO n</c>.</summary>
    Goto,

    /// <summary>FANUC <c>WHILE [c] DOm</c> (or a bare <c>DOm</c>: an endless loop).</summary>
    While,

    /// <summary>FANUC <c>ENDm</c>.</summary>
    End,

    /// <summary>FANUC <c>M98</c>, <c>M97</c>, <c>G65</c>.</summary>
    Call,

    /// <summary>FANUC <c>M99</c> (with <c>P</c>: return to that N).</summary>
    Return,

    /// <summary>An RS274/NGC o-word statement.</summary>
    OWord,

    /// <summary>FANUC <c>G66 P L</c> with arguments: the macro is called after every move block until <c>G67</c>.</summary>
    ModalCall,

    /// <summary>FANUC <c>G67</c>: the modal call ends.</summary>
    ModalCancel,
}

/// <summary>How a FANUC call calls.</summary>
internal enum CallKind
{
    /// <summary><c>M98 P</c>: a subprogram, sharing the caller's locals.</summary>
    M98,

    /// <summary><c>M97 P</c>: a local subprogram at N P of the same program (Haas).</summary>
    M97,

    /// <summary><c>G65 P</c>: a macro with its own locals from the argument table.</summary>
    G65,
}

/// <summary>One word of a block: its letter and its value (constant or computed).</summary>
internal readonly record struct MacroWord(char Letter, MacroExpr Value, bool IsConst);

/// <summary>One assignment: the variable (numbered, indirect or named) and its new value.</summary>
internal readonly record struct MacroAssign(MacroExpr Target, MacroExpr Value);

/// <summary>A compiled source line: what it does in the expansion, computed once however often a loop runs it.</summary>
internal sealed class MacroLine
{
    public LineKind Kind;

    /// <summary>The line's N number (for GOTO and M99 P), NaN when none.</summary>
    public double N = double.NaN;

    public bool BlockDelete;

    /// <summary>Words of a Words block (also the other words of a call block, emitted before the call).</summary>
    public MacroWord[] Words = [];

    public MacroAssign[] Assigns = [];

    /// <summary>Condition (IF, WHILE, o-word if/elseif/while/repeat count).</summary>
    public MacroExpr? Condition;

    /// <summary>GOTO target, the program a call names, M99's P.</summary>
    public MacroExpr? Target;

    /// <summary>Repeat count of a call (L or K), null for once.</summary>
    public MacroExpr? Count;

    /// <summary>DO/END number of FANUC loops.</summary>
    public int LoopId;

    /// <summary>The statement after THEN.</summary>
    public MacroLine? Then;

    public CallKind Call;

    /// <summary>G65 arguments: variable number (1-26) and value.</summary>
    public (int Variable, MacroExpr Value)[] Arguments = [];

    /// <summary>M02/M30 in the block: the end of the main program.</summary>
    public bool EndsProgram;

    /// <summary>FANUC program number of an O line.</summary>
    public int ProgramNumber;

    /// <summary>o-word label (number as written without leading zeros, or the lower-case name).</summary>
    public string Label = string.Empty;

    /// <summary>o-word keyword (SUB, ENDSUB, CALL, RETURN, IF, ELSEIF, ELSE, ENDIF, WHILE, ENDWHILE, DO, REPEAT, ENDREPEAT, BREAK, CONTINUE).</summary>
    public string Keyword = string.Empty;

    /// <summary>o-word call arguments and the value of endsub/return.</summary>
    public MacroExpr[] OArgs = [];

    /// <summary>Column of the statement (after N), for errors.</summary>
    public int Column = 1;

    /// <summary>The line's first comment, as written (the message of <c>#3000</c> and <c>#3006</c>).</summary>
    public string Comment = string.Empty;
}

/// <summary>Compiles source lines of either dialect into <see cref="MacroLine"/>s.</summary>
internal static class MacroCompiler
{
    /// <summary>FANUC's argument specification I: the letter's local variable (0: not an argument).</summary>
    private static readonly int[] ArgumentTable = Table();

    private static int[] Table()
    {
        var t = new int[26];
        void S(char c, int v) => t[c - 'A'] = v;
        S('A', 1); S('B', 2); S('C', 3); S('I', 4); S('J', 5); S('K', 6); S('D', 7); S('E', 8); S('F', 9); S('H', 11);
        S('M', 13); S('Q', 17); S('R', 18); S('S', 19); S('T', 20); S('U', 21); S('V', 22); S('W', 23); S('X', 24);
        S('Y', 25); S('Z', 26);
        return t;
    }

    private static readonly string[] OKeywords =
        ["ENDSUB", "SUB", "CALL", "RETURN", "ELSEIF", "ELSE", "ENDIF", "IF", "ENDWHILE", "WHILE", "DO", "ENDREPEAT", "REPEAT", "BREAK", "CONTINUE"];

    /// <summary>
    /// True when a line is emitted as written and needs no compiling: no <c>#</c>, <c>[</c> or <c>%</c>, no keyword
    /// (two letters in a row), no call, return or program end (<c>M98 M97 M99 G65-G67 M02 M30</c>), no program number
    /// or o-word first. Most lines of most programs: they are neither compiled nor held.
    /// </summary>
    public static bool IsPlain(ReadOnlySpan<byte> line, MacroDialect dialect)
    {
        var first = true;
        for (var i = 0; i < line.Length; i++)
        {
            var b = line[i];
            switch (b)
            {
                case (byte)'(':
                    var close = line[i..].IndexOf((byte)')');
                    if (close < 0)
                    {
                        return true; // the reader reports the open comment
                    }

                    i += close;
                    continue;
                case (byte)';':
                    return true;
                case (byte)'#' or (byte)'[' or (byte)'%' or (byte)':':
                    return false;
                case (byte)' ' or (byte)'\t' or (byte)'/':
                    continue;
            }

            var u = (byte)(b & ~0x20);
            if (u is < (byte)'A' or > (byte)'Z')
            {
                continue;
            }

            if (i + 1 < line.Length && (byte)(line[i + 1] & ~0x20) is >= (byte)'A' and <= (byte)'Z')
            {
                return false; // a keyword (IF, GOTO, WHILE, END, DO, SUB, CALL ...) or something the reader names
            }

            if (u == 'O' && (first || dialect == MacroDialect.LinuxCnc))
            {
                return false;
            }

            if (u == 'N')
            {
                continue; // a sequence number leaves the next word first
            }

            first = false;
            if (u is (byte)'M' or (byte)'G')
            {
                var k = i + 1;
                while (k < line.Length && line[k] == (byte)' ')
                {
                    k++;
                }

                var v = 0;
                var digits = 0;
                while (k < line.Length && line[k] is >= (byte)'0' and <= (byte)'9' && digits < 6)
                {
                    v = (v * 10) + (line[k++] - '0');
                    digits++;
                }

                if (u == 'M' ? v is 2 or 30 or 97 or 98 or 99 : v is 65 or 66 or 67)
                {
                    return false;
                }
            }
        }

        return true;
    }

    /// <summary>Compiles one line; throws <see cref="MacroEvalException"/> for what cannot be read.</summary>
    public static MacroLine Compile(string text, MacroDialect dialect)
    {
        var s = Blanked(text, out var comment);
        var line = new MacroLine { Comment = comment ?? string.Empty };
        var p = new MacroParser(s, 0);
        if (p.AtEnd)
        {
            return line;
        }

        if (p.Peek() == '%')
        {
            line.Kind = LineKind.TapeMark;
            return line;
        }

        Prefix(ref p, line);
        if (dialect == MacroDialect.LinuxCnc && p.Peek() == 'O' && p.PeekAt(1) is '<' or (>= '0' and <= '9'))
        {
            CompileOWord(ref p, line);
            return line;
        }

        if (dialect == MacroDialect.Fanuc && FanucStatement(ref p, line, s) is { } statement)
        {
            return statement;
        }

        CompileBlock(ref p, line, dialect);
        return line;
    }

    /// <summary>
    /// The line in upper case with its comments as blanks (columns stay those of the source; names in #&lt;...&gt; are
    /// kept as they are), and its first comment as written.
    /// </summary>
    private static string Blanked(string text, out string? comment)
    {
        comment = null;
        var chars = text.ToCharArray();
        for (var i = 0; i < chars.Length; i++)
        {
            var c = chars[i];
            if (c == '#' && i + 1 < chars.Length && chars[i + 1] == '<')
            {
                var close = Array.IndexOf(chars, '>', i);
                i = close < 0 ? chars.Length : close;
                continue;
            }

            if (c == '(')
            {
                var close = Array.IndexOf(chars, ')', i);
                var end = close < 0 ? chars.Length - 1 : close;
                if (comment == null)
                {
                    comment = text[(i + 1)..(close < 0 ? chars.Length : close)].Trim();
                }

                for (var k = i; k <= end; k++)
                {
                    chars[k] = ' ';
                }

                i = end;
            }
            else if (c == ';')
            {
                for (var k = i; k < chars.Length; k++)
                {
                    chars[k] = ' ';
                }

                break;
            }
            else
            {
                chars[i] = char.ToUpperInvariant(c);
            }
        }

        return new string(chars);
    }

    /// <summary>A block delete slash (with its number) and an N word before the statement; the statement's column.</summary>
    private static void Prefix(ref MacroParser p, MacroLine line)
    {
        if (p.Peek() == '/')
        {
            line.BlockDelete = true;
            p.Advance();
            while (p.Peek() is >= '0' and <= '9')
            {
                p.Advance();
            }
        }

        if (p.Peek() == 'N' && (p.PeekAt(1) is >= '0' and <= '9' or ' '))
        {
            p.Advance();
            line.N = p.Number();
        }

        line.Column = p.Position + 1;
    }

    /// <summary>
    /// FANUC's statements (program number, IF ... GOTO / THEN, GOTO, WHILE ... DO, DO, END): the compiled line, or
    /// null when the line is a block (<see cref="CompileBlock"/>). <paramref name="s"/> is the blanked line.
    /// </summary>
    private static MacroLine? FanucStatement(ref MacroParser p, MacroLine line, string s)
    {
        if (p.Peek() is 'O' or ':' && p.PeekAt(1) is >= '0' and <= '9')
        {
            p.Advance();
            line.Kind = LineKind.ProgramNumber;
            line.ProgramNumber = (int)p.Number();
            return End(ref p, line);
        }

        if (p.TryKeyword("IF"))
        {
            p.Expect('[');
            line.Condition = p.Expression();
            p.Expect(']');
            if (p.TryKeyword("GOTO"))
            {
                line.Kind = LineKind.IfGoto;
                line.Target = p.Primary();
            }
            else if (p.TryKeyword("THEN"))
            {
                line.Kind = LineKind.IfThen;
                line.Then = Compile(new string(' ', p.Position) + s[p.Position..], MacroDialect.Fanuc);
                line.Then.Comment = line.Comment;
                return line;
            }
            else
            {
                throw new MacroEvalException(p.Position + 1, "IF [...] without GOTO or THEN");
            }

            return End(ref p, line);
        }

        if (p.TryKeyword("GOTO"))
        {
            line.Kind = LineKind.Goto;
            line.Target = p.Primary();
            return End(ref p, line);
        }

        if (p.TryKeyword("WHILE"))
        {
            p.Expect('[');
            line.Condition = p.Expression();
            p.Expect(']');
            if (!p.TryKeyword("DO"))
            {
                throw new MacroEvalException(p.Position + 1, "WHILE [...] without DO");
            }

            line.Kind = LineKind.While;
            line.LoopId = (int)p.Number();
            return End(ref p, line);
        }

        if (p.PeekLetters() == "DO")
        {
            p.TryKeyword("DO");
            line.Kind = LineKind.While;
            line.LoopId = (int)p.Number();
            return End(ref p, line);
        }

        if (p.PeekLetters() == "END")
        {
            p.TryKeyword("END");
            line.Kind = LineKind.End;
            line.LoopId = (int)p.Number();
            return End(ref p, line);
        }

        return null;
    }

    private static MacroLine End(ref MacroParser p, MacroLine line)
    {
        if (!p.AtEnd)
        {
            throw new MacroEvalException(p.Position + 1, $"unexpected '{p.Peek()}' after the statement");
        }

        return line;
    }

    private static void CompileOWord(ref MacroParser p, MacroLine line)
    {
        p.Advance(); // O
        if (p.Peek() == '<')
        {
            var start = p.Position + 1;
            while (p.Peek() != '>' && p.Peek() != '\0')
            {
                p.Advance();
            }

            var end = p.Position;
            p.Expect('>');
            // RS274/NGC labels are case-insensitive and ignore spaces (kept lower case, as subroutine file names are).
            line.Label = p.Text(start, end).Replace(" ", string.Empty, StringComparison.Ordinal).Replace("\t", string.Empty, StringComparison.Ordinal).ToLowerInvariant();
        }
        else
        {
            line.Label = ((long)p.Number()).ToString(CultureInfo.InvariantCulture);
        }

        var word = p.PeekLetters();
        foreach (var k in OKeywords)
        {
            if (word == k)
            {
                line.Keyword = k;
                p.TryKeyword(k);
                break;
            }
        }

        if (line.Keyword.Length == 0)
        {
            throw new MacroEvalException(p.Position + 1, word.Length == 0 ? "o-word without a keyword (sub, call, if, while ...)" : $"'{word.ToLowerInvariant()}' is not an o-word keyword");
        }

        line.Kind = LineKind.OWord;
        var args = new List<MacroExpr>();
        while (!p.AtEnd)
        {
            if (p.Peek() != '[')
            {
                throw new MacroEvalException(p.Position + 1, $"unexpected '{p.Peek()}' after o{line.Label} {line.Keyword.ToLowerInvariant()}");
            }

            args.Add(p.Primary());
        }

        if (line.Keyword is "IF" or "ELSEIF" or "WHILE" or "REPEAT")
        {
            if (args.Count != 1)
            {
                throw new MacroEvalException(line.Column, $"o{line.Label} {line.Keyword.ToLowerInvariant()} needs one [expression]");
            }

            line.Condition = args[0];
        }
        else
        {
            line.OArgs = [.. args];
        }
    }

    private static void CompileBlock(ref MacroParser p, MacroLine line, MacroDialect dialect)
    {
        var words = new List<MacroWord>();
        var assigns = new List<MacroAssign>();
        var constant = true;
        while (!p.AtEnd)
        {
            var c = p.Peek();
            var col = p.Position + 1;
            if (c == '#')
            {
                var target = p.Primary();
                if (target is not (VarExpr or IndirectExpr or NamedExpr))
                {
                    throw new MacroEvalException(col, "assignment to something that is not a variable");
                }

                p.Expect('=');
                assigns.Add(new MacroAssign(target, p.Expression()));
                if (dialect == MacroDialect.Fanuc && !p.AtEnd)
                {
                    throw new MacroEvalException(p.Position + 1, "a FANUC macro statement takes the whole block");
                }

                continue;
            }

            if (!char.IsAsciiLetterUpper(c))
            {
                throw new MacroEvalException(col, $"unexpected '{c}'");
            }

            p.Advance();
            var value = WordValue(ref p, c, col, out var written);
            constant &= written;
            words.Add(new MacroWord(c, value, value is ConstExpr));
        }

        line.Words = [.. words];
        line.Assigns = [.. assigns];
        if (dialect == MacroDialect.Fanuc && Classify(line, words))
        {
            return;
        }

        foreach (var w in words)
        {
            if (w.Letter == 'M' && w.Value is ConstExpr { Value: 2 or 30 })
            {
                line.EndsProgram = true;
            }
        }

        line.Kind = words.Count == 0 ? (assigns.Count > 0 ? LineKind.Assign : LineKind.Raw) : constant && assigns.Count == 0 ? LineKind.Raw : LineKind.Words;
    }

    /// <summary>
    /// The value of word <paramref name="letter"/> (at column <paramref name="col"/>, the letter read): a variable or
    /// bracketed expression, one with a sign, or a number (a <see cref="ConstExpr"/>, <paramref name="number"/> true).
    /// </summary>
    private static MacroExpr WordValue(ref MacroParser p, char letter, int col, out bool number)
    {
        var v = p.Peek();
        number = false;
        if (v is '#' or '[')
        {
            return p.Primary();
        }

        if (v is '-' or '+' && p.PeekAt(1) is '#' or '[')
        {
            p.Advance();
            var inner = p.Primary();
            return v == '-' ? new UnaryExpr('-', inner) { Column = inner.Column } : inner;
        }

        var sign = 1.0;
        if (v is '-' or '+')
        {
            sign = v == '-' ? -1 : 1;
            p.Advance();
        }

        if (p.Peek() is not (>= '0' and <= '9' or '.'))
        {
            // Not a word this layer reads: left to the reader, which names it (E102 ...).
            throw new MacroEvalException(col, $"'{letter}' without a value");
        }

        number = true;
        return new ConstExpr(sign * p.Number()) { Column = col };
    }

    /// <summary>The call or return a block makes: 97, 98, 99 (M), 65, 66, 67 (G); -1 for none.</summary>
    private static int KindOf(List<MacroWord> words)
    {
        var kind = -1;
        foreach (var w in words)
        {
            if (w.Value is not ConstExpr k)
            {
                continue;
            }

            if ((w.Letter == 'M' && k.Value is 98 or 97 or 99) || (w.Letter == 'G' && k.Value is 65 or 66 or 67))
            {
                kind = (int)k.Value;
            }
            else if (w.Letter == 'G' && k.Value == 66.1)
            {
                throw new MacroEvalException(w.Value.Column - 1, "G66.1 (a macro call at every block) is not expanded by the host: G66 calls after move blocks");
            }
        }

        return kind;
    }

    /// <summary>FANUC calls and returns: true when the block is one (its other words are emitted before it).</summary>
    private static bool Classify(MacroLine line, List<MacroWord> words)
    {
        var kind = KindOf(words);
        if (kind < 0)
        {
            return false;
        }

        var rest = new List<MacroWord>();
        var args = new List<(int, MacroExpr)>();
        foreach (var w in words)
        {
            var isCode = w.Value is ConstExpr k && ((w.Letter == 'M' && k.Value == kind) || (w.Letter == 'G' && kind is 65 or 66 or 67 && k.Value == kind));
            if (isCode)
            {
                continue;
            }

            switch (w.Letter)
            {
                case 'P' when kind != 67:
                    line.Target = w.Value;
                    continue;
                case 'L' when kind is not (99 or 67):
                    line.Count = w.Value;
                    continue;
                case 'K' when kind is 98 or 97:
                    line.Count = w.Value;
                    continue;
            }

            if (kind is 65 or 66)
            {
                var variable = ArgumentTable[w.Letter - 'A'];
                if (variable == 0)
                {
                    throw new MacroEvalException(w.Value.Column - 1, $"{w.Letter} is not a G{kind} argument (A-Z except G L N O P)");
                }

                args.Add((variable, w.Value));
            }
            else
            {
                rest.Add(w);
            }
        }

        if (kind is not (99 or 67) && line.Target == null)
        {
            throw new MacroEvalException(line.Column, kind is 65 or 66 ? $"G{kind} without P (the macro's program number)" : $"M{kind} without P (the subprogram's number)");
        }

        line.Kind = kind switch { 99 => LineKind.Return, 66 => LineKind.ModalCall, 67 => LineKind.ModalCancel, _ => LineKind.Call };
        line.Call = kind switch { 97 => CallKind.M97, 65 or 66 => CallKind.G65, _ => CallKind.M98 };
        line.Arguments = [.. args];
        line.Words = [.. rest];
        return true;
    }
}
