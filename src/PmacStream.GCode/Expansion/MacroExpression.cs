using System.Globalization;

namespace PmacStream.GCode.Expansion;

/// <summary>
/// What an expression reads its variables from while it is evaluated: the expander (locals of the call in force,
/// commons, named parameters, the system variables the host knows).
/// </summary>
internal interface IMacroVariables
{
    /// <summary>The value of numbered variable <paramref name="number"/> (NaN: vacant, FANUC's null).</summary>
    double Read(int number, MacroExpr at);

    /// <summary>The value of a named LinuxCNC parameter (<c>#&lt;name&gt;</c>, lower case).</summary>
    double ReadNamed(string name, MacroExpr at);
}

/// <summary>A compiled macro expression (FANUC Custom Macro B or RS274/NGC); NaN is the vacant value.</summary>
internal abstract class MacroExpr
{
    /// <summary>Column of the expression's first character (1-based), for errors.</summary>
    public int Column { get; init; }

    /// <summary>The value; vacant variables read as NaN.</summary>
    public abstract double Eval(IMacroVariables v);

    /// <summary>The value where a vacant one counts as 0 (arithmetic, as FANUC computes with &lt;vacant&gt;).</summary>
    public double Num(IMacroVariables v)
    {
        var x = Eval(v);
        return double.IsNaN(x) ? 0 : x;
    }

    /// <summary>A variable number from a value (rounded as FANUC does; negative or huge ones are an error).</summary>
    public static int ToVariableNumber(double v, int column)
    {
        var r = Math.Round(v);
        if (r is < 0 or > 99999 || Math.Abs(r - v) > 1e-6)
        {
            throw new MacroEvalException(column, $"#{v.ToString(CultureInfo.InvariantCulture)} is not a variable number");
        }

        return (int)r;
    }

    /// <summary>The same for an expression being evaluated.</summary>
    public static int ToVariableNumber(double v, MacroExpr at) => ToVariableNumber(v, at.Column);
}

/// <summary>A number written in the program.</summary>
internal sealed class ConstExpr(double value) : MacroExpr
{
    public double Value { get; } = value;

    public override double Eval(IMacroVariables v) => Value;
}

/// <summary><c>#n</c> with a constant n.</summary>
internal sealed class VarExpr(int number) : MacroExpr
{
    public int Number { get; } = number;

    public override double Eval(IMacroVariables v) => v.Read(Number, this);
}

/// <summary><c>#[expr]</c> or <c>##n</c>: the variable an expression names.</summary>
internal sealed class IndirectExpr(MacroExpr index) : MacroExpr
{
    public MacroExpr Index { get; } = index;

    public override double Eval(IMacroVariables v) => v.Read(MacroExpr.ToVariableNumber(Index.Num(v), this), this);
}

/// <summary><c>#&lt;name&gt;</c> (RS274/NGC named parameter; a leading underscore makes it global).</summary>
internal sealed class NamedExpr(string name) : MacroExpr
{
    public string Name { get; } = name;

    public override double Eval(IMacroVariables v) => v.ReadNamed(Name, this);
}

/// <summary>Unary minus, plus and NOT.</summary>
internal sealed class UnaryExpr(char op, MacroExpr operand) : MacroExpr
{
    public override double Eval(IMacroVariables v)
    {
        var x = operand.Eval(v);
        return op switch
        {
            '-' => double.IsNaN(x) ? 0 : -x,
            _ => x,
        };
    }
}

/// <summary>A binary operator: arithmetic, comparison (1/0) or logic.</summary>
internal sealed class BinaryExpr : MacroExpr
{
    private readonly MacroExpr _left;
    private readonly MacroExpr _right;
    private readonly int _op; // index into Ops: a switch on a number, not on the operator's text, in loops run millions of times

    private static readonly string[] Ops = ["+", "-", "*", "/", "**", "MOD", "GT", "GE", "LT", "LE", "AND", "OR", "XOR", "EQ", "NE"];

    public BinaryExpr(string op, MacroExpr left, MacroExpr right)
    {
        _op = Array.IndexOf(Ops, op);
        if (_op < 0)
        {
            throw new ArgumentException($"unknown operator {op}", nameof(op));
        }

        _left = left;
        _right = right;
    }

    public string Op => Ops[_op];

    public override double Eval(IMacroVariables v)
    {
        if (_op >= 13)
        {
            // FANUC: <vacant> EQ #0 is true and <vacant> EQ 0 false; comparisons other than EQ/NE take vacant as 0.
            var a = _left.Eval(v);
            var b = _right.Eval(v);
            var eq = double.IsNaN(a) || double.IsNaN(b) ? double.IsNaN(a) && double.IsNaN(b) : Math.Abs(a - b) < 1e-9;
            return (_op == 13) == eq ? 1 : 0;
        }

        var x = _left.Num(v);
        var y = _right.Num(v);
        return _op switch
        {
            0 => x + y,
            1 => x - y,
            2 => x * y,
            3 => y == 0 ? throw new MacroEvalException(Column, "division by zero") : x / y,
            4 => Math.Pow(x, y),
            5 => y == 0 ? throw new MacroEvalException(Column, "MOD by zero") : x - (y * Math.Floor(x / y)),
            6 => x > y + 1e-9 ? 1 : 0,
            7 => x >= y - 1e-9 ? 1 : 0,
            8 => x < y - 1e-9 ? 1 : 0,
            9 => x <= y + 1e-9 ? 1 : 0,
            10 => x != 0 && y != 0 ? 1 : 0,
            11 => x != 0 || y != 0 ? 1 : 0,
            _ => (x != 0) ^ (y != 0) ? 1 : 0,
        };
    }
}

/// <summary>A function: SIN COS TAN ASIN ACOS ATAN SQRT ABS ROUND FIX FUP LN EXP EXISTS (angles in degrees).</summary>
internal sealed class FunctionExpr(string name, MacroExpr arg, MacroExpr? second) : MacroExpr
{
    public override double Eval(IMacroVariables v)
    {
        if (name == "EXISTS")
        {
            return arg is NamedExpr n && v is MacroExpander e && e.NamedExists(n.Name) ? 1 : 0;
        }

        var x = arg.Num(v);
        const double deg = Math.PI / 180;
        return name switch
        {
            "SIN" => Math.Sin(x * deg),
            "COS" => Math.Cos(x * deg),
            "TAN" => Math.Tan(x * deg),
            "ASIN" => Math.Asin(x) / deg,
            "ACOS" => Math.Acos(x) / deg,
            // ATAN[y]/[x] (FANUC, RS274/NGC) or ATAN[y,x] (FANUC 30i): 0..360 as FANUC gives it.
            "ATAN" => second == null ? Math.Atan(x) / deg : Normalize(Math.Atan2(x, second.Num(v)) / deg),
            "SQRT" => x < 0 ? throw new MacroEvalException(Column, $"SQRT of a negative number ({x.ToString(CultureInfo.InvariantCulture)})") : Math.Sqrt(x),
            "ABS" => Math.Abs(x),
            "ROUND" => Math.Round(x, MidpointRounding.AwayFromZero),
            "FIX" => Math.Floor(x),
            "FUP" => Math.Ceiling(x),
            "LN" => x <= 0 ? throw new MacroEvalException(Column, "LN of a number not above 0") : Math.Log(x),
            "EXP" => Math.Exp(x),
            "BIN" => Bin(x),
            "BCD" => Bcd(x),
            _ => throw new MacroEvalException(Column, $"unknown function {name}"),
        };
    }

    private static double Normalize(double a) => a < 0 ? a + 360 : a;

    private static double Bin(double bcd)
    {
        long b = (long)bcd, r = 0, m = 1;
        for (; b > 0; b >>= 4, m *= 10)
        {
            r += (b & 15) * m;
        }

        return r;
    }

    private static double Bcd(double bin)
    {
        long b = (long)bin, r = 0;
        for (var s = 0; b > 0; b /= 10, s += 4)
        {
            r |= (b % 10) << s;
        }

        return r;
    }
}

/// <summary>An expression could not be evaluated (division by zero, a vacant variable where a number is needed ...).</summary>
internal sealed class MacroEvalException(int column, string message) : Exception(message)
{
    /// <summary>Column (1-based) in the source line.</summary>
    public int Column { get; } = column;
}

/// <summary>
/// Parses expressions from an upper-cased source line (comments removed). Precedence (RS274/NGC, which FANUC's
/// bracketed conditions agree with): <c>**</c>; <c>* / MOD</c>; <c>+ -</c>; <c>EQ NE GT GE LT LE</c>; <c>AND OR XOR</c>.
/// </summary>
internal ref struct MacroParser
{
    private readonly ReadOnlySpan<char> _s;
    private int _i;

    public MacroParser(ReadOnlySpan<char> s, int start)
    {
        _s = s;
        _i = start;
    }

    public readonly int Position => _i;

    public readonly bool AtEnd
    {
        get
        {
            var i = _i;
            while (i < _s.Length && _s[i] is ' ' or '\t')
            {
                i++;
            }

            return i >= _s.Length;
        }
    }

    public void SkipSpaces()
    {
        while (_i < _s.Length && _s[_i] is ' ' or '\t')
        {
            _i++;
        }
    }

    public char Peek()
    {
        SkipSpaces();
        return _i < _s.Length ? _s[_i] : '\0';
    }

    public char PeekAt(int ahead)
    {
        SkipSpaces();
        return _i + ahead < _s.Length ? _s[_i + ahead] : '\0';
    }

    public void Advance(int n = 1) => _i += n;

    /// <summary>The source text from <paramref name="start"/> to <paramref name="end"/>.</summary>
    public readonly string Text(int start, int end) => _s[start..end].ToString();

    /// <summary>True (and consumed) when the keyword follows here.</summary>
    public bool TryKeyword(string word)
    {
        SkipSpaces();
        if (_i + word.Length <= _s.Length && _s.Slice(_i, word.Length).SequenceEqual(word))
        {
            _i += word.Length;
            return true;
        }

        return false;
    }

    /// <summary>A run of letters (a keyword or function name), not consumed.</summary>
    public readonly string PeekLetters()
    {
        var i = _i;
        while (i < _s.Length && _s[i] is ' ' or '\t')
        {
            i++;
        }

        var j = i;
        while (j < _s.Length && char.IsAsciiLetterUpper(_s[j]))
        {
            j++;
        }

        return _s[i..j].ToString();
    }

    public MacroExpr Expression() => Logic();

    private MacroExpr Logic()
    {
        var left = Relation();
        while (true)
        {
            var at = Col();
            string? op = TryKeyword("AND") ? "AND" : TryKeyword("OR") ? "OR" : TryKeyword("XOR") ? "XOR" : null;
            if (op == null)
            {
                return left;
            }

            left = new BinaryExpr(op, left, Relation()) { Column = at };
        }
    }

    private MacroExpr Relation()
    {
        var left = Additive();
        while (true)
        {
            var at = Col();
            string? op = null;
            foreach (var k in (ReadOnlySpan<string>)["EQ", "NE", "GT", "GE", "LT", "LE"])
            {
                if (TryKeyword(k))
                {
                    op = k;
                    break;
                }
            }

            if (op == null)
            {
                return left;
            }

            left = new BinaryExpr(op, left, Additive()) { Column = at };
        }
    }

    private MacroExpr Additive()
    {
        var left = Multiplicative();
        while (true)
        {
            var c = Peek();
            if (c is not ('+' or '-'))
            {
                return left;
            }

            var at = Col();
            _i++;
            left = new BinaryExpr(c.ToString(), left, Multiplicative()) { Column = at };
        }
    }

    private MacroExpr Multiplicative()
    {
        var left = Power();
        while (true)
        {
            var c = Peek();
            var at = Col();
            if (c == '*' && PeekAt(1) != '*')
            {
                _i++;
                left = new BinaryExpr("*", left, Power()) { Column = at };
            }
            else if (c == '/')
            {
                _i++;
                left = new BinaryExpr("/", left, Power()) { Column = at };
            }
            else if (TryKeyword("MOD"))
            {
                left = new BinaryExpr("MOD", left, Power()) { Column = at };
            }
            else
            {
                return left;
            }
        }
    }

    private MacroExpr Power()
    {
        var left = Unary();
        while (Peek() == '*' && PeekAt(1) == '*')
        {
            var at = Col();
            _i += 2;
            left = new BinaryExpr("**", left, Unary()) { Column = at };
        }

        return left;
    }

    private MacroExpr Unary()
    {
        var c = Peek();
        var at = Col();
        if (c is '-' or '+')
        {
            _i++;
            return new UnaryExpr(c, Unary()) { Column = at };
        }

        return Primary();
    }

    private readonly int Col() => _i + 1;

    /// <summary>A number, a variable, a bracketed expression or a function.</summary>
    public MacroExpr Primary()
    {
        var c = Peek();
        var at = Col();
        if (c == '[')
        {
            _i++;
            var e = Expression();
            Expect(']');
            return e;
        }

        if (c == '#')
        {
            _i++;
            var n = Peek();
            if (n == '<')
            {
                var close = _s[_i..].IndexOf('>');
                if (close < 0)
                {
                    throw new MacroEvalException(at, "named parameter without its closing '>'");
                }

                // RS274/NGC: spaces inside a name are ignored and names are case-insensitive.
                var name = _s.Slice(_i + 1, close - 1).ToString().Replace(" ", string.Empty, StringComparison.Ordinal).Replace("\t", string.Empty, StringComparison.Ordinal).ToLowerInvariant();
                _i += close + 1;
                return new NamedExpr(name) { Column = at };
            }

            var inner = Primary();
            return inner is ConstExpr k ? new VarExpr(ToVariableNumber(k.Value, this.Col())) { Column = at } : new IndirectExpr(inner) { Column = at };
        }

        if (c is >= '0' and <= '9' or '.')
        {
            return new ConstExpr(Number()) { Column = at };
        }

        if (char.IsAsciiLetterUpper(c))
        {
            var name = PeekLetters();
            if (name is "SIN" or "COS" or "TAN" or "ASIN" or "ACOS" or "ATAN" or "SQRT" or "SQR" or "ABS" or "ROUND" or "RND" or "FIX" or "FUP" or "LN" or "EXP" or "BIN" or "BCD" or "EXISTS")
            {
                TryKeyword(name);
                if (Peek() != '[')
                {
                    throw new MacroEvalException(at, $"{name} without its [argument]");
                }

                _i++;
                var arg = Expression();
                MacroExpr? second = null;
                if (name == "ATAN" && Peek() == ',')
                {
                    _i++;
                    second = Expression();
                    Expect(']');
                }
                else
                {
                    Expect(']');
                    if (name == "ATAN" && Peek() == '/' && PeekAt(1) == '[')
                    {
                        _i++;
                        second = Primary();
                    }
                }

                name = name switch { "SQR" => "SQRT", "RND" => "ROUND", _ => name };
                return new FunctionExpr(name, arg, second) { Column = at };
            }

            throw new MacroEvalException(at, name.Length > 0 ? $"'{name}' is not a function or operator here" : $"unexpected '{c}'");
        }

        throw new MacroEvalException(at, c == '\0' ? "expression ends too early" : $"unexpected '{c}' in an expression");
    }

    /// <summary>An unsigned decimal number.</summary>
    public double Number()
    {
        SkipSpaces();
        var start = _i;
        while (_i < _s.Length && (_s[_i] is >= '0' and <= '9' or '.'))
        {
            _i++;
        }

        if (!double.TryParse(_s[start.._i], NumberStyles.AllowDecimalPoint, CultureInfo.InvariantCulture, out var v))
        {
            throw new MacroEvalException(start + 1, $"malformed number '{_s[start.._i].ToString()}'");
        }

        return v;
    }

    public void Expect(char c)
    {
        if (Peek() != c)
        {
            throw new MacroEvalException(Col(), Peek() == '\0' ? $"'{c}' missing at the end of the line" : $"'{c}' expected, found '{Peek()}'");
        }

        _i++;
    }

    private static int ToVariableNumber(double v, int column) => MacroExpr.ToVariableNumber(v, column);
}
