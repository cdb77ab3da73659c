namespace PmacStream.Sim.Parsing;

/// <summary>Reads and writes controller variables for expression evaluation (Q through the current coordinate system).</summary>
internal interface IVariableAccess
{
    double Get(char kind, int index);

    void Set(char kind, int index, double value);
}

/// <summary>A compiled PMAC expression.</summary>
internal abstract class Expr
{
    public abstract double Eval(IVariableAccess v);

    /// <summary>Number of values it costs in a rotary buffer (about one word per value).</summary>
    public virtual int Words => 1;
}

internal sealed class ConstExpr(double value) : Expr
{
    public double Value { get; } = value;

    public override double Eval(IVariableAccess v) => Value;
}

internal sealed class VarExpr(char kind, int index) : Expr
{
    public char Kind { get; } = kind;

    public int Index { get; } = index;

    public override double Eval(IVariableAccess v) => v.Get(Kind, Index);
}

/// <summary><c>P(expression)</c>, <c>Q(...)</c>, <c>M(...)</c>, <c>I(...)</c>: the variable the expression's value numbers (tables indexed from a program).</summary>
internal sealed class IndirectVarExpr(char kind, Expr index) : Expr
{
    public char Kind { get; } = kind;

    public override int Words => 1 + index.Words;

    public override double Eval(IVariableAccess v) => v.Get(Kind, Number(index.Eval(v)));

    /// <summary>The variable number an index expression gives: rounded, 0-8191, else a run-time error.</summary>
    public static int Number(double value)
    {
        var n = Math.Round(value);
        return n is >= 0 and <= 8191 ? (int)n : throw new SimRuntimeException(3);
    }
}

internal sealed class UnaryExpr(char op, Expr operand) : Expr
{
    public override double Eval(IVariableAccess v) => op == '-' ? -operand.Eval(v) : operand.Eval(v);

    public override int Words => operand.Words;
}

internal sealed class BinaryExpr(string op, Expr left, Expr right) : Expr
{
    public override int Words => left.Words + right.Words;

    public override double Eval(IVariableAccess v)
    {
        var a = left.Eval(v);
        switch (op)
        {
            case "AND":
                return a != 0 && right.Eval(v) != 0 ? 1 : 0;
            case "OR":
                return a != 0 || right.Eval(v) != 0 ? 1 : 0;
        }

        var b = right.Eval(v);
        return op switch
        {
            "+" => a + b,
            "-" => a - b,
            "*" => a * b,
            "/" => b == 0 ? 0 : a / b, // PMAC saturates rather than faulting; 0 keeps the simulator running.
            "%" => b == 0 ? 0 : a - (b * Math.Floor(a / b)),
            "&" => (long)a & (long)b,
            "|" => (long)a | (long)b,
            "^" => (long)a ^ (long)b,
            "=" => a == b ? 1 : 0,
            "!=" => a != b ? 1 : 0,
            "<" => a < b ? 1 : 0,
            "!>" => a <= b ? 1 : 0,
            ">" => a > b ? 1 : 0,
            "!<" => a >= b ? 1 : 0,
            "<=" => a <= b ? 1 : 0,
            ">=" => a >= b ? 1 : 0,
            "~" => Math.Abs(a - b) < 1e-9 ? 1 : 0,
            _ => throw new InvalidOperationException(op),
        };
    }
}

internal sealed class FuncExpr(string name, Expr[] args) : Expr
{
    public override int Words => 1 + args.Sum(a => a.Words);

    public override double Eval(IVariableAccess v)
    {
        var a = args[0].Eval(v);
        // PMAC trig works in degrees (I15=0, the default).
        const double Rad = Math.PI / 180.0;
        return name switch
        {
            "SIN" => Math.Sin(a * Rad),
            "COS" => Math.Cos(a * Rad),
            "TAN" => Math.Tan(a * Rad),
            "ASIN" => Math.Asin(a) / Rad,
            "ACOS" => Math.Acos(a) / Rad,
            "ATAN" => Math.Atan(a) / Rad,
            "ATAN2" => Math.Atan2(a, args.Length > 1 ? args[1].Eval(v) : v.Get('Q', 0)) / Rad,
            "LN" => a > 0 ? Math.Log(a) : 0,
            "EXP" => Math.Exp(a),
            "SQRT" => a >= 0 ? Math.Sqrt(a) : 0,
            "ABS" => Math.Abs(a),
            "INT" => Math.Floor(a),
            _ => throw new InvalidOperationException(name),
        };
    }
}

/// <summary>Recursive-descent expression parser over the token list.</summary>
internal sealed class ExprParser(List<Token> tokens)
{
    private static readonly HashSet<string> Functions = ["SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ATAN2", "LN", "EXP", "SQRT", "ABS", "INT"];
    private static readonly HashSet<string> Comparisons = ["=", "!=", "<", ">", "<=", ">=", "!<", "!>", "~"];

    /// <summary>
    /// Deepest nesting of parentheses, functions and signs in one expression. The parser recurses per level, and a
    /// line of thousands of "(" from a client must be an illegal command (ERR003), not a stack overflow that ends
    /// the simulator's process. A simulator limit, far beyond what programs write.
    /// </summary>
    public const int MaxNesting = 64;

    private List<Token> tokens = tokens;
    private int _nesting;

    /// <summary>Starts over on a new token list (one parser reused per simulator: no allocation per line).</summary>
    public void Reset(List<Token> newTokens)
    {
        tokens = newTokens;
        Pos = 0;
        _nesting = 0;
    }

    public int Pos { get; set; }

    public Token Peek => tokens[Pos];

    public Token PeekAt(int offset) => tokens[Math.Min(Pos + offset, tokens.Count - 1)];

    public Token Next() => tokens[Pos < tokens.Count - 1 ? Pos++ : Pos];

    public bool Accept(string text)
    {
        if (Peek.Is(text))
        {
            Pos++;
            return true;
        }

        return false;
    }

    public void Expect(string text)
    {
        if (!Accept(text))
        {
            throw new SimSyntaxException(3);
        }
    }

    /// <summary>A whole-number argument of a command (<c>&amp;2</c>, <c>OPEN PROG 1000</c>) in [min, max]; anything else is ERR003.</summary>
    public int IntArgument(int min, int max)
    {
        var t = Next();
        if (t.Kind != TokenKind.Number || t.Value < min || t.Value > max)
        {
            throw new SimSyntaxException(3);
        }

        return (int)t.Value;
    }

    /// <summary>Parses a full expression; comparisons and AND/OR only when <paramref name="condition"/> is set.</summary>
    public Expr ParseExpression(bool condition = false) => condition ? ParseOr() : ParseAdditive(false);

    /// <summary>A value: signed constant or parenthesised expression (axis words, F, DWELL...).</summary>
    public Expr ParseValue()
    {
        if (Peek.Is("("))
        {
            Pos++;
            var e = ParseAdditive(false);
            Expect(")");
            return e;
        }

        var negative = false;
        if (Peek.Is("-") || Peek.Is("+"))
        {
            negative = Next().Text == "-";
        }

        if (Peek.Kind == TokenKind.Number)
        {
            var v = Next().Value;
            return new ConstExpr(negative ? -v : v);
        }

        if (Peek.Is("("))
        {
            Pos++;
            var e = ParseAdditive(false);
            Expect(")");
            return negative ? new UnaryExpr('-', e) : e;
        }

        throw new SimSyntaxException(3);
    }

    public bool AtValue => Peek.Kind == TokenKind.Number || Peek.Is("(") ||
        ((Peek.Is("-") || Peek.Is("+")) && (PeekAt(1).Kind == TokenKind.Number || PeekAt(1).Is("(")));

    private Expr ParseOr()
    {
        var left = ParseAnd();
        while (Peek.Is("OR"))
        {
            Pos++;
            left = new BinaryExpr("OR", left, ParseAnd());
        }

        return left;
    }

    private Expr ParseAnd()
    {
        var left = ParseComparison();
        while (Peek.Is("AND"))
        {
            Pos++;
            left = new BinaryExpr("AND", left, ParseComparison());
        }

        return left;
    }

    private Expr ParseComparison()
    {
        var left = ParseAdditive(true);
        if (Peek.Kind == TokenKind.Symbol && Comparisons.Contains(Peek.Text))
        {
            var op = Next().Text;
            left = new BinaryExpr(op, left, ParseAdditive(true));
        }

        return left;
    }

    // PMAC precedence: * / % & bind tighter than + - | ^.
    private Expr ParseAdditive(bool condition)
    {
        var left = ParseMultiplicative(condition);
        while (Peek.Kind == TokenKind.Symbol && Peek.Text is "+" or "-" or "|" or "^")
        {
            var op = Next().Text;
            left = new BinaryExpr(op, left, ParseMultiplicative(condition));
        }

        return left;
    }

    private Expr ParseMultiplicative(bool condition)
    {
        var left = ParseUnary(condition);
        while (Peek.Kind == TokenKind.Symbol && Peek.Text is "*" or "/" or "%" or "&" && !StartsCommand())
        {
            var op = Next().Text;
            left = new BinaryExpr(op, left, ParseUnary(condition));
        }

        return left;
    }

    private Expr ParseUnary(bool condition)
    {
        if (++_nesting > MaxNesting)
        {
            throw new SimSyntaxException(3);
        }

        try
        {
            if (Peek.Is("-"))
            {
                Pos++;
                return new UnaryExpr('-', ParseUnary(condition));
            }

            if (Peek.Is("+"))
            {
                Pos++;
                return ParseUnary(condition);
            }

            return ParsePrimary(condition);
        }
        finally
        {
            _nesting--;
        }
    }

    private Expr ParsePrimary(bool condition)
    {
        var t = Peek;
        if (t.Kind == TokenKind.Number)
        {
            Pos++;
            return new ConstExpr(t.Value);
        }

        if (t.Is("("))
        {
            Pos++;
            var e = condition ? ParseOr() : ParseAdditive(false);
            Expect(")");
            return e;
        }

        if (t.Kind == TokenKind.Word && Functions.Contains(t.Text) && PeekAt(1).Is("("))
        {
            Pos += 2;
            var args = new List<Expr> { ParseAdditive(false) };
            while (Accept(","))
            {
                args.Add(ParseAdditive(false));
            }

            Expect(")");
            return new FuncExpr(t.Text, [.. args]);
        }

        if (t.Kind == TokenKind.Word && t.Text is "I" or "P" or "Q" or "M" && PeekAt(1).Kind == TokenKind.Number)
        {
            Pos += 2;
            return new VarExpr(t.Text[0], VariableIndex(PeekAt(-1)));
        }

        if (t.Kind == TokenKind.Word && t.Text is "I" or "P" or "Q" or "M" && PeekAt(1).Is("("))
        {
            Pos += 2;
            var index = ParseAdditive(false);
            Expect(")");
            return new IndirectVarExpr(t.Text[0], index);
        }

        throw new SimSyntaxException(3);
    }

    /// <summary>
    /// "P1=2 &amp;1" and "P1=2 %50": a spaced-off &amp; or % glued to a number starts the next command (coordinate
    /// system, feed override) rather than continuing the expression; "M1&amp;M2" and "M1 &amp; M2" stay operators.
    /// </summary>
    private bool StartsCommand()
    {
        var t = Peek;
        var next = PeekAt(1);
        return Pos > 0 && tokens[Pos - 1].End < t.Start && next.Kind == TokenKind.Number && next.Start == t.End;
    }

    public static int VariableIndex(Token number)
    {
        if (number.Kind != TokenKind.Number || number.Value < 0 || number.Value > 8191 || number.Value != Math.Floor(number.Value))
        {
            throw new SimSyntaxException(3);
        }

        return (int)number.Value;
    }
}
