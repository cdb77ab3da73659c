namespace PmacStream.Plc;

/// <summary>A blank-separated word of a line, with its 1-based line and column.</summary>
internal readonly record struct LadderWord(string Text, int Line, int Column);

/// <summary>The kinds of rung tokens.</summary>
internal enum LadderTokenKind
{
    Name,
    Assign,
    And,
    Or,
    Not,
    Open,
    Close,
    End,
}

/// <summary>A rung token, with its 1-based line and column.</summary>
internal readonly record struct LadderToken(LadderTokenKind Kind, string Text, int Line, int Column);

/// <summary>
/// The ladder format's lines: code and comment apart, blank-separated words (directives, declarations), rung tokens
/// (names, <c>=</c>, <c>&amp;</c>, <c>|</c>, <c>!</c>, brackets), and whether a rung goes on on the next line.
/// </summary>
internal static class LadderLexer
{
    /// <summary>True while a rung is not finished: a bracket is open or it ends with an operator (or is empty).</summary>
    public static bool NeedsContinuation(List<LadderToken> tokens)
    {
        if (tokens.Count == 0)
        {
            return true;
        }

        var depth = 0;
        foreach (var t in tokens)
        {
            depth += t.Kind == LadderTokenKind.Open ? 1 : t.Kind == LadderTokenKind.Close ? -1 : 0;
        }

        var last = tokens[^1].Kind;
        return depth > 0 || last is LadderTokenKind.And or LadderTokenKind.Or or LadderTokenKind.Not or LadderTokenKind.Open;
    }

    /// <summary>A line's code and its comment (after <c>#</c> or <c>;</c>; null when none or blank).</summary>
    public static (string Code, string? Comment) SplitComment(string raw)
    {
        var cut = raw.IndexOfAny(['#', ';']);
        if (cut < 0)
        {
            return (raw, null);
        }

        var comment = raw[(cut + 1)..].Trim();
        return (raw[..cut], comment.Length == 0 ? null : comment);
    }

    /// <summary>The blank-separated words of a line's code, with their columns (directives and declarations).</summary>
    public static List<LadderWord> SplitWords(string code, int line)
    {
        var words = new List<LadderWord>();
        var i = 0;
        while (i < code.Length)
        {
            if (char.IsWhiteSpace(code[i]))
            {
                i++;
                continue;
            }

            var start = i;
            while (i < code.Length && !char.IsWhiteSpace(code[i]))
            {
                i++;
            }

            words.Add(new LadderWord(code[start..i], line, start + 1));
        }

        return words;
    }

    /// <summary>The tokens of a rung's code, added to <paramref name="into"/>; a character that is none is reported to <paramref name="error"/> (line, column, message) and skipped.</summary>
    public static void Tokenize(string code, int line, List<LadderToken> into, Action<int, int, string> error)
    {
        var i = 0;
        while (i < code.Length)
        {
            var c = code[i];
            if (char.IsWhiteSpace(c))
            {
                i++;
                continue;
            }

            var col = i + 1;
            LadderTokenKind? single = c switch
            {
                '=' => LadderTokenKind.Assign,
                '&' => LadderTokenKind.And,
                '|' => LadderTokenKind.Or,
                '!' => LadderTokenKind.Not,
                '(' => LadderTokenKind.Open,
                ')' => LadderTokenKind.Close,
                _ => null,
            };
            if (single is { } k)
            {
                into.Add(new LadderToken(k, c.ToString(), line, col));
                i++;
                continue;
            }

            if (char.IsLetter(c) || c == '_')
            {
                var start = i;
                while (i < code.Length && (char.IsLetterOrDigit(code[i]) || code[i] == '_'))
                {
                    i++;
                }

                into.Add(new LadderToken(LadderTokenKind.Name, code[start..i], line, col));
                continue;
            }

            var hint = c switch
            {
                '^' => " (write a normally-closed contact as !NAME; the generator emits the ^1 form)",
                '~' or '/' => " (write a normally-closed contact as !NAME)",
                '+' => " (write parallel branches with |)",
                '*' => " (write contacts in series with &)",
                _ => "",
            };
            error(line, col, $"unexpected character '{c}'; expected a name, '&', '|', '!', '(' or ')'{hint}");
            i++;
        }
    }
}
