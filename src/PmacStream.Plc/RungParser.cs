namespace PmacStream.Plc;

/// <summary>
/// Recursive descent over one rung's tokens: <c>|</c> (parallel branches) is lowest, then <c>&amp;</c> (contacts in
/// series), then <c>!</c> (normally closed) and brackets. Reports the first error only (what follows it would be noise).
/// </summary>
internal sealed class RungParser(List<LadderToken> tokens, Dictionary<string, LadderSymbol> names, Action<int, int, string> error, int line)
{
    private int _pos;
    private bool _failed;

    private LadderToken Peek => _pos < tokens.Count ? tokens[_pos] : EndToken;

    private LadderToken EndToken => tokens.Count > 0
        ? new LadderToken(LadderTokenKind.End, "", tokens[^1].Line, tokens[^1].Column + tokens[^1].Text.Length)
        : new LadderToken(LadderTokenKind.End, "", line, 1);

    /// <summary>The rung's network; null (the first error reported) when it does not parse.</summary>
    public LadderExpr? ParseRung()
    {
        var e = Parallel();
        if (!_failed && Peek.Kind != LadderTokenKind.End)
        {
            var t = Peek;
            Fail(t, t.Kind == LadderTokenKind.Close
                ? "unmatched ')'"
                : $"expected '&', '|' or the end of the rung, found {Describe(t)}");
        }

        return _failed ? null : e;
    }

    private void Fail(LadderToken t, string message)
    {
        if (!_failed)
        {
            error(t.Line, t.Column, message);
        }

        _failed = true;
    }

    private static string Describe(LadderToken t) => t.Kind == LadderTokenKind.End ? "the end of the rung" : $"'{t.Text}'";

    private LadderExpr? Parallel() => Chain(LadderTokenKind.Or, Series, parallel: true);

    private LadderExpr? Series() => Chain(LadderTokenKind.And, Factor, parallel: false);

    /// <summary>Operands joined by <paramref name="op"/>: one list, nested lists of the same kind spliced in.</summary>
    private LadderExpr? Chain(LadderTokenKind op, Func<LadderExpr?> operand, bool parallel)
    {
        var first = operand();
        if (first is null)
        {
            return null;
        }

        List<LadderExpr>? items = null;
        while (!_failed && Peek.Kind == op)
        {
            _pos++;
            var next = operand();
            if (next is null)
            {
                return null;
            }

            items ??= [.. Splice(first, parallel)];
            items.AddRange(Splice(next, parallel));
        }

        return items is null ? first : parallel ? new LadderParallel(items) : new LadderSeries(items);
    }

    private static IEnumerable<LadderExpr> Splice(LadderExpr e, bool parallel) => e switch
    {
        LadderSeries s when !parallel => s.Items,
        LadderParallel p when parallel => p.Items,
        _ => [e],
    };

    private LadderExpr? Factor()
    {
        var t = Peek;
        switch (t.Kind)
        {
            case LadderTokenKind.Not:
                _pos++;
                var inner = Factor();
                return inner switch
                {
                    null => null,
                    LadderContact c => c with { NormallyClosed = !c.NormallyClosed },
                    LadderNot n => n.Inner,
                    _ => new LadderNot(inner),
                };
            case LadderTokenKind.Open:
                _pos++;
                var group = Parallel();
                if (group is null)
                {
                    return null;
                }

                if (Peek.Kind != LadderTokenKind.Close)
                {
                    Fail(Peek, $"expected ')' to close the '(' at column {t.Column}{(t.Line != Peek.Line ? $" of line {t.Line}" : "")}, found {Describe(Peek)}");
                    return null;
                }

                _pos++;
                return group;
            case LadderTokenKind.Name:
                _pos++;
                if (!names.TryGetValue(t.Text, out var sym))
                {
                    Fail(t, $"'{t.Text}' is not declared; declare it with input, output or internal");
                    return null;
                }

                return new LadderContact(sym, false);
            default:
                Fail(t, $"expected a contact name, '!' or '(', found {Describe(t)}");
                return null;
        }
    }
}
