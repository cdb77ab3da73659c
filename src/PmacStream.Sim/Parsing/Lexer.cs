using System.Globalization;

namespace PmacStream.Sim.Parsing;

internal enum TokenKind
{
    End,
    Number,
    Word,
    Symbol,
    Text,
}

/// <summary>
/// One lexical token of a command line. <see cref="Start"/>/<see cref="End"/> index the (upper-cased) line. Number
/// tokens carry their <see cref="Value"/>; their <see cref="Text"/> is the source text only for <c>$</c> hex numbers
/// and empty otherwise (nothing reads it, and a substring per number was the lexer's main cost).
/// </summary>
internal readonly record struct Token(TokenKind Kind, string Text, double Value, int Start, int End)
{
    public bool Is(string text) => (Kind == TokenKind.Word || Kind == TokenKind.Symbol) && Text == text;

    public bool IsLetter => Kind == TokenKind.Word && Text.Length == 1;
}

/// <summary>
/// Splits a PMAC command line into tokens. PMAC runs words together (<c>&amp;1B0R</c>, <c>X10Y20</c>,
/// <c>F(P500)M0==12</c>) so letter runs are split greedily into the longest known keyword, else single letters.
/// A semicolon starts a comment.
/// </summary>
internal static class Lexer
{
    private static readonly string[] Keywords =
    [
        "ABS", "ACOS", "AND", "ASIN", "ATAN", "ATAN2", "CALL", "CC", "CCR", "CID", "CIRCLE", "CLEAR", "CLOSE", "COS", "DATE", "DEF",
        "DEFINE", "DEL", "DELAY", "DELETE", "DIS", "DISABLE", "DWELL", "ELSE", "ENA", "ENABLE", "ENDI", "ENDIF", "ENDW",
        "ENDWHILE", "EXP", "GAT", "GATHER", "GOSUB", "GOTO", "IF", "INC", "INT", "LINEAR", "LIST", "LN", "NORMAL", "OPEN",
        "OR", "PLC", "PR", "PROG", "RAPID", "READ", "RET", "RETURN", "ROT", "SAVE", "SIN", "SQRT", "STOP", "TA", "TAN",
        "TM", "TS", "TYPE", "VER", "VERSION", "WHILE", "CMD", "SEND", "ROTARY", "PROGRAM", "CTRL",
        "TSEL", "TSELECT", "TINIT", "ADIS", "IDIS", "AROT", "IROT", "TBUF", "HM", "HMZ", "HOME", "HOMEZ", "PMATCH", "SIZE",
    ];

    private static readonly HashSet<string> KeywordSet = new(Keywords, StringComparer.Ordinal);
    private static readonly HashSet<string>.AlternateLookup<ReadOnlySpan<char>> KeywordLookup = KeywordSet.GetAlternateLookup<ReadOnlySpan<char>>();
    private static readonly int MaxKeyword = Keywords.Max(k => k.Length);

    private static readonly string[] SingleLetters = Enumerable.Range('A', 26).Select(c => ((char)c).ToString()).ToArray();

    private const string SingleSymbols = "&#%()+-*/=<>!^|,:~?.";

    // Symbol texts are shared strings: no allocation per symbol token.
    private static readonly string[] SingleSymbolTexts = SingleSymbols.Select(c => c.ToString()).ToArray();

    /// <summary>Tokenizes <paramref name="line"/>, which must already be upper-cased. Throws <see cref="SimSyntaxException"/>.</summary>
    public static List<Token> Tokenize(string line)
    {
        var tokens = new List<Token>(16);
        Tokenize(line, tokens);
        return tokens;
    }

    /// <summary>Tokenizes <paramref name="line"/> into <paramref name="tokens"/> (cleared first), so a caller can reuse one list.</summary>
    public static void Tokenize(string line, List<Token> tokens)
    {
        tokens.Clear();
        var i = 0;
        while (i < line.Length)
        {
            var c = line[i];
            if (c == ' ' || c == '\t' || c == '\r' || c == '\n')
            {
                i++;
                continue;
            }

            if (c == ';')
            {
                break;
            }

            if (c > 127)
            {
                throw new SimSyntaxException(4);
            }

            if (char.IsAsciiDigit(c) || (c == '.' && i + 1 < line.Length && char.IsAsciiDigit(line[i + 1])))
            {
                var start = i;
                while (i < line.Length && char.IsAsciiDigit(line[i]))
                {
                    i++;
                }

                if (i < line.Length && line[i] == '.' && !(i + 1 < line.Length && line[i + 1] == '.'))
                {
                    i++;
                    while (i < line.Length && char.IsAsciiDigit(line[i]))
                    {
                        i++;
                    }
                }

                var value = double.Parse(line.AsSpan(start, i - start), NumberStyles.AllowDecimalPoint, CultureInfo.InvariantCulture);
                tokens.Add(new Token(TokenKind.Number, string.Empty, value, start, i));
                continue;
            }

            if (c == '$')
            {
                var start = i;
                if (line.AsSpan(i).StartsWith("$$$"))
                {
                    i += 3;
                    if (line.AsSpan(i).StartsWith("***"))
                    {
                        i += 3;
                    }

                    tokens.Add(new Token(TokenKind.Symbol, line[start..i], 0, start, i));
                    continue;
                }

                i++;
                while (i < line.Length && char.IsAsciiHexDigit(line[i]))
                {
                    i++;
                }

                if (i == start + 1)
                {
                    // A lone $ is the motor reset command (#n$), not a hex constant.
                    tokens.Add(new Token(TokenKind.Symbol, "$", 0, start, i));
                    continue;
                }

                // More hex digits than a 64-bit word holds is an illegal constant, not a fault of the controller.
                if (!long.TryParse(line.AsSpan(start + 1, i - start - 1), NumberStyles.AllowHexSpecifier, CultureInfo.InvariantCulture, out var hex))
                {
                    throw new SimSyntaxException(3);
                }

                tokens.Add(new Token(TokenKind.Number, line[start..i], hex, start, i));
                continue;
            }

            if (c == '"')
            {
                var start = i++;
                while (i < line.Length && line[i] != '"')
                {
                    i++;
                }

                tokens.Add(new Token(TokenKind.Text, line[(start + 1)..Math.Min(i, line.Length)], 0, start, Math.Min(i + 1, line.Length)));
                i = Math.Min(i + 1, line.Length);
                continue;
            }

            if (char.IsAsciiLetterUpper(c))
            {
                var start = i;
                while (i < line.Length && char.IsAsciiLetterUpper(line[i]))
                {
                    i++;
                }

                SplitLetters(line, start, i, tokens);
                continue;
            }

            if (i + 1 < line.Length && TwoCharSymbol(c, line[i + 1]) is { } two)
            {
                tokens.Add(new Token(TokenKind.Symbol, two, 0, i, i + 2));
                i += 2;
                continue;
            }

            var symbol = SingleSymbols.IndexOf(c);
            if (symbol >= 0)
            {
                tokens.Add(new Token(TokenKind.Symbol, SingleSymbolTexts[symbol], 0, i, i + 1));
                i++;
                continue;
            }

            throw new SimSyntaxException(c < 32 ? 4 : 3);
        }

        tokens.Add(new Token(TokenKind.End, string.Empty, 0, line.Length, line.Length));
    }

    /// <summary>The two-character symbols: <c>== != &lt;= &gt;= !&lt; !&gt; -&gt; ..</c>.</summary>
    private static string? TwoCharSymbol(char a, char b) => (a, b) switch
    {
        ('=', '=') => "==",
        ('!', '=') => "!=",
        ('<', '=') => "<=",
        ('>', '=') => ">=",
        ('!', '<') => "!<",
        ('!', '>') => "!>",
        ('-', '>') => "->",
        ('.', '.') => "..",
        _ => null,
    };

    private static void SplitLetters(string line, int start, int end, List<Token> tokens)
    {
        var i = start;
        while (i < end)
        {
            var matched = 0;
            string? keyword = null;
            for (var len = Math.Min(MaxKeyword, end - i); len >= 2; len--)
            {
                if (KeywordLookup.TryGetValue(line.AsSpan(i, len), out keyword))
                {
                    matched = len;
                    break;
                }
            }

            if (matched == 0)
            {
                matched = 1;
                keyword = SingleLetters[line[i] - 'A'];
            }

            tokens.Add(new Token(TokenKind.Word, keyword!, 0, i, i + matched));
            i += matched;
        }
    }
}

/// <summary>A command line the controller cannot accept; carries the ERR number to answer.</summary>
internal sealed class SimSyntaxException(int error) : Exception($"ERR{error:000}")
{
    public int Error { get; } = error;
}
