using System.Globalization;

namespace PmacStream.GCode;

/// <summary>
/// Lexes one line into its words, comments and lexical findings (<see cref="GCodeReader"/> reads the lines): what CAM
/// posts and people write, no spaces (<c>G0X1.Y-2.5</c>), spaces between letter and number, lower case,
/// <c>.5</c>/<c>5.</c>/<c>+5</c>, <c>( )</c> and <c>;</c> comments, <c>%</c> tape marks, <c>/</c> block skip at
/// the start and inside a block, a leading <c>:</c> as the program number.
/// </summary>
public static class LineLexer
{
    /// <summary>Lexes <paramref name="b"/>'s line into its words, comments and findings.</summary>
    internal static void Lex(GBlock b)
    {
        // A word takes two bytes at least: only a longer line can hold more words than are read. The two
        // instantiations are compiled apart, so a line of a program pays nothing for the word limit.
        if (b.Length > 2 * FindingLimits.WordsPerLine)
        {
            Lex<WordLimit>(b);
        }
        else
        {
            Lex<NoWordLimit>(b);
        }
    }

    // Hot loop of a million-line program: compile optimized at once instead of spending the first
    // hundreds of milliseconds in unoptimized tier-0 code waiting for tiering.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveOptimization)]
    private static void Lex<TLimit>(GBlock b)
        where TLimit : struct, IWordLimit
    {
        b.WordList.Clear();
        b.CommentList.Clear();
        b.BlockDelete = false;
        b.IsTapeMark = false;
        b.SkipFrom = -1;
        b.SkipColumn = 0;
        var line = b.Buffer.AsSpan(0, b.Length);
        var i = SkipBlanks(line, 0);
        var reportedLowercase = false;

        if (i < line.Length && line[i] == (byte)'%')
        {
            b.IsTapeMark = true;
            i++;
        }
        else if (i < line.Length && line[i] == (byte)'/')
        {
            b.BlockDelete = true;
            i++;
            // Optional block-delete level (/1../9) is read as part of the marker.
            if (i < line.Length && line[i] is >= (byte)'1' and <= (byte)'9')
            {
                i++;
            }
        }

        while (true)
        {
            i = SkipBlanks(line, i);
            if (i >= line.Length)
            {
                break;
            }

            var c = line[i];
            if (c == (byte)'(')
            {
                var close = line[(i + 1)..].IndexOfAny((byte)')', (byte)'(');
                if (close >= 0 && line[i + 1 + close] == (byte)'(')
                {
                    // Comments do not nest (FANUC, RS274/NGC): say so once, and end the comment at its matching ')'.
                    Add(b, Severity.Error, DiagnosticCodes.NestedComment, i + 2 + close);
                    close = MatchingClose(line, i);
                }

                if (close < 0)
                {
                    b.CommentList.Add((i, line.Length - i));
                    Add(b, Severity.Error, DiagnosticCodes.UnclosedComment, i + 1);
                    break;
                }

                b.CommentList.Add((i, close + 2));
                i += close + 2;
                continue;
            }

            if (c == (byte)';')
            {
                b.CommentList.Add((i, line.Length - i));
                break;
            }

            if (b.IsTapeMark)
            {
                // Text after % on a tape-mark line is ignored by controllers; keep it as a comment.
                b.CommentList.Add((i, line.Length - i));
                break;
            }

            var isLower = c is >= (byte)'a' and <= (byte)'z';
            // ':' is the ISO program number address, so only the first word of a block (FANUC's ":1234" for O1234).
            if ((c is >= (byte)'A' and <= (byte)'Z') || isLower || (c == (byte)':' && b.WordList.Count == 0))
            {
                var letter = c == (byte)':' ? 'O' : (char)(c & 0xDF);
                if (isLower && !reportedLowercase)
                {
                    reportedLowercase = true;
                    Add(b, Severity.Warning, DiagnosticCodes.LowercaseLetter, i + 1, (char)c);
                }

                var column = i + 1;
                var j = SkipBlanks(line, i + 1);
                var numStart = j;
                if (j < line.Length && (line[j] == (byte)'+' || line[j] == (byte)'-'))
                {
                    j++;
                }

                // Scan and convert in one pass: integer digits, then fraction digits, as one integer mantissa scaled
                // once by a power of ten. With at most 15 digits the mantissa and the power are exact doubles, so the
                // one division is correctly rounded: the same value the BCL parser gives, which longer numbers use.
                var negative = j > numStart && line[numStart] == (byte)'-';
                var digitStart = j;
                long mantissa = 0;
                uint digit;
                while (j < line.Length && (digit = (uint)(line[j] - (byte)'0')) <= 9)
                {
                    mantissa = (mantissa * 10) + digit;
                    j++;
                }

                var scale = 0;
                var points = 0;
                if (j < line.Length && line[j] == (byte)'.')
                {
                    points = 1;
                    j++;
                    var fractionStart = j;
                    while (j < line.Length && (digit = (uint)(line[j] - (byte)'0')) <= 9)
                    {
                        mantissa = (mantissa * 10) + digit;
                        j++;
                    }

                    scale = j - fractionStart;
                    // A second point makes it malformed; the whole run of digits and points is one bad token.
                    while (j < line.Length && (line[j] == (byte)'.' || (uint)(line[j] - (byte)'0') <= 9))
                    {
                        points += line[j] == (byte)'.' ? 1 : 0;
                        j++;
                    }
                }

                var digits = j - digitStart - points;
                if (digits == 0 || points > 1)
                {
                    // A run of letters (a word of another language: LinuxCNC's "sub", "call") is one finding, not one per letter.
                    var run = i + 1;
                    while (digits == 0 && run < line.Length && (uint)((line[run] | 0x20) - 'a') <= 'z' - 'a')
                    {
                        run++;
                    }

                    var text = run - i > 1 ? System.Text.Encoding.ASCII.GetString(line[i..run]) : ((char)c).ToString();
                    if (!b.ListsFindings)
                    {
                        b.CountUnlisted(Severity.Error);
                    }
                    else if (IsOWordConstruct(b, text))
                    {
                        // "O100 sub", "O100 call": a subroutine or flow construct of LinuxCNC, not a number gone wrong.
                        var o = b.WordList[^1];
                        b.DiagnosticList.Add(new Diagnostic(Severity.Error, DiagnosticCodes.MalformedNumber, b.LineNumber, column,
                            DiagnosticText.Format(DiagnosticText.OWordKey, $"O{o.Value.ToString(CultureInfo.InvariantCulture)} {text.ToLowerInvariant()}")));
                    }
                    else
                    {
                        Add(b, Severity.Error, DiagnosticCodes.MalformedNumber, column, text);
                    }

                    i = Math.Max(Math.Max(j, run), i + 1);
                    continue;
                }

                double value;
                if (digits <= 15)
                {
                    value = scale == 0 ? mantissa : mantissa / Pow10[scale];
                    if (negative)
                    {
                        value = -value;
                    }
                }
                else
                {
                    value = ParseNumber(line[numStart..j]);
                    if (!double.IsFinite(value) || Math.Abs(value) > 1e15)
                    {
                        // Hundreds of digits: no controller register holds that; report instead of computing with infinity.
                        Add(b, Severity.Error, DiagnosticCodes.MalformedNumber, column, (char)c);
                        i = j;
                        continue;
                    }
                }

                if (TLimit.Applies && b.WordList.Count == FindingLimits.WordsPerLine)
                {
                    // No block has this many words: read no further, so a line of junk costs no more than a block.
                    Add(b, Severity.Error, DiagnosticCodes.TooManyWords, column, FindingLimits.WordsPerLine);
                    break;
                }

                b.WordList.Add(new GWord(letter, value, column, numStart, j - numStart, isLower));
                i = j;
                continue;
            }

            if (c == (byte)'/' && i + 1 < line.Length && line[i + 1] == (byte)'/' && b.WordList.Count > 0)
            {
                // "T1//15.98": a tool-table entry of an older ISO dialect (tool, then its diameter), not block skip.
                if (b.ListsFindings)
                {
                    b.DiagnosticList.Add(new Diagnostic(Severity.Error, DiagnosticCodes.IllegalCharacter, b.LineNumber, i + 1, DiagnosticText.Format(DiagnosticText.DoubleSlashKey)));
                }
                else
                {
                    b.CountUnlisted(Severity.Error);
                }

                break;
            }

            if (c == (byte)'/' && b.WordList.Count > 0)
            {
                // FANUC's optional block skip inside a block: the rest of the block is skipped when block delete is
                // on. Whether the dialect allows it is the profile's to say (the interpreter reports it otherwise).
                if (b.SkipFrom < 0)
                {
                    b.SkipFrom = b.WordList.Count;
                    b.SkipColumn = i + 1;
                }

                i++;
                if (i < line.Length && line[i] is >= (byte)'1' and <= (byte)'9')
                {
                    i++;
                }

                continue;
            }

            // Report the whole run of junk once, not every byte of it.
            if (c == 0)
            {
                Add(b, Severity.Error, DiagnosticCodes.NulByte, i + 1);
            }
            else
            {
                if (b.ListsFindings)
                {
                    Add(b, Severity.Error, DiagnosticCodes.IllegalCharacter, i + 1, Printable(line, i));
                }
                else
                {
                    b.CountUnlisted(Severity.Error);
                }
            }

            i++;
            while (i < line.Length && !IsTokenStart(line[i]))
            {
                i++;
            }
        }
    }

    /// <summary>The offset after <paramref name="open"/>+1 of the ')' that closes the comment opened there (counting nested ones), or -1.</summary>
    private static int MatchingClose(ReadOnlySpan<byte> line, int open)
    {
        var depth = 0;
        for (var j = open; j < line.Length; j++)
        {
            if (line[j] == (byte)'(')
            {
                depth++;
            }
            else if (line[j] == (byte)')' && --depth == 0)
            {
                return j - open - 1;
            }
        }

        return -1;
    }

    private static bool IsTokenStart(byte c) =>
        c is (byte)'(' or (byte)';' or (byte)' ' or (byte)'\t' or (byte)':' || (c is >= (byte)'A' and <= (byte)'Z') || (c is >= (byte)'a' and <= (byte)'z');

    private static string Printable(ReadOnlySpan<byte> line, int i)
    {
        var c = line[i];
        if (c >= 0x20 && c < 0x7F)
        {
            return ((char)c).ToString();
        }

        return $"0x{c:X2}";
    }

    private static double ParseNumber(ReadOnlySpan<byte> text) =>
        double.TryParse(text, NumberStyles.Float, CultureInfo.InvariantCulture, out var v) ? v : double.NaN;

    /// <summary>The value the lexer gives a number of at most 15 digits: <paramref name="mantissa"/> (its digits) over 10^<paramref name="scale"/> (fraction digits).</summary>
    public static double ShortNumber(long mantissa, int scale, bool negative)
    {
        var value = scale == 0 ? mantissa : mantissa / Pow10[scale];
        return negative ? -value : value;
    }

    private static readonly double[] Pow10 =
    [
        1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    ];

    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    internal static int SkipBlanks(ReadOnlySpan<byte> line, int i)
    {
        while (i < line.Length && (line[i] == (byte)' ' || line[i] == (byte)'\t' || line[i] == 0x0B || line[i] == 0x0C))
        {
            i++;
        }

        return i;
    }

    /// <summary>LinuxCNC's o-word keywords: subroutines, loops and conditions written as <c>O&lt;n&gt; keyword</c>.</summary>
    private static readonly HashSet<string> OWordKeywords = new(StringComparer.OrdinalIgnoreCase)
    {
        "sub", "endsub", "call", "return", "if", "elseif", "else", "endif", "do", "while", "endwhile", "repeat", "endrepeat", "break", "continue",
    };

    /// <summary>Whether a run of letters is an o-word keyword right after the block's O word.</summary>
    private static bool IsOWordConstruct(GBlock b, string text) =>
        b.WordList.Count > 0 && b.WordList[^1].Letter == 'O' && OWordKeywords.Contains(text);

    private static void Add(GBlock b, Severity severity, string code, int column, params object[] args) =>
        b.AddFinding(severity, code, column, args);

    /// <summary>Whether a line is long enough for <see cref="FindingLimits.WordsPerLine"/> to matter (a constant of each instantiation).</summary>
    private interface IWordLimit
    {
        static abstract bool Applies { get; }
    }

    private readonly struct WordLimit : IWordLimit
    {
        public static bool Applies => true;
    }

    private readonly struct NoWordLimit : IWordLimit
    {
        public static bool Applies => false;
    }
}
