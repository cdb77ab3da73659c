using System.Globalization;

namespace PmacStream.Plc;

/// <summary>
/// A small, independent interpreter for the subset of Turbo PMAC syntax the generator writes: M-variable definitions
/// <c>Mn->X|Y:$addr,offset[,width]</c>, and one PLC body of <c>Mn=expr</c> statements with <c>+ - * / &amp; | ^</c> and
/// brackets. Used by tests to check generated programs without the simulator, and to compare expressions by truth
/// table. Precedence as the Turbo PMAC manual gives it: <c>* / &amp;</c> bind tighter than <c>+ - | ^</c>, left to right.
/// </summary>
internal sealed class PlcEvaluator
{
    private readonly Dictionary<int, (char Mem, int Addr, int Offset, int Width)> _defs = [];
    private readonly Dictionary<(char, int), long> _memory = [];
    private readonly Dictionary<int, long> _free = [];
    private readonly List<(int Target, Node Expr)> _body = [];

    /// <summary>Loads download lines: definitions go into the table, the lines between OPEN PLC and CLOSE become the scan.</summary>
    public static PlcEvaluator Load(IEnumerable<string> lines)
    {
        var ev = new PlcEvaluator();
        var inPlc = false;
        foreach (var raw in lines)
        {
            var line = raw.Trim();
            var upper = line.ToUpperInvariant();
            if (upper.StartsWith("OPEN PLC", StringComparison.Ordinal))
            {
                inPlc = true;
                continue;
            }

            if (upper == "CLOSE")
            {
                inPlc = false;
                continue;
            }

            if (upper.StartsWith("ENABLE", StringComparison.Ordinal) || upper.StartsWith("DISABLE", StringComparison.Ordinal))
            {
                continue;
            }

            if (line.Contains("->", StringComparison.Ordinal))
            {
                ev.Define(line);
            }
            else if (inPlc)
            {
                ev._body.Add(ParseStatement(line));
            }
            else
            {
                throw new FormatException($"unexpected line outside the PLC: {line}");
            }
        }

        return ev;
    }

    private void Define(string line)
    {
        var arrow = line.IndexOf("->", StringComparison.Ordinal);
        var m = int.Parse(line.AsSpan(1, arrow - 1), CultureInfo.InvariantCulture);
        var spec = line[(arrow + 2)..];
        var mem = char.ToUpperInvariant(spec[0]);
        var parts = spec[3..].Split(',');
        var addr = int.Parse(parts[0], NumberStyles.AllowHexSpecifier, CultureInfo.InvariantCulture);
        var off = int.Parse(parts[1], CultureInfo.InvariantCulture);
        var width = parts.Length > 2 ? int.Parse(parts[2], CultureInfo.InvariantCulture) : 1;
        _defs[m] = (mem, addr, off, width);
    }

    /// <summary>Runs one scan: every statement of the PLC body in order.</summary>
    public void Scan()
    {
        foreach (var (target, expr) in _body)
        {
            Set(target, expr.Eval(this));
        }
    }

    /// <summary>Reads an M-variable (an undefined one is a free 0-initialised variable).</summary>
    public long Get(int m)
    {
        if (!_defs.TryGetValue(m, out var d))
        {
            return _free.GetValueOrDefault(m);
        }

        var word = _memory.GetValueOrDefault((d.Mem, d.Addr));
        return (word >> d.Offset) & ((1L << d.Width) - 1);
    }

    /// <summary>Writes an M-variable: only its bits of the word change.</summary>
    public void Set(int m, long value)
    {
        if (!_defs.TryGetValue(m, out var d))
        {
            _free[m] = value;
            return;
        }

        var mask = ((1L << d.Width) - 1) << d.Offset;
        var word = _memory.GetValueOrDefault((d.Mem, d.Addr));
        _memory[(d.Mem, d.Addr)] = (word & ~mask) | ((value << d.Offset) & mask);
    }

    /// <summary>Reads a whole memory word.</summary>
    public long ReadWord(char mem, int addr) => _memory.GetValueOrDefault((char.ToUpperInvariant(mem), addr));

    /// <summary>Writes a whole memory word (the test's hand on the terminal block).</summary>
    public void WriteWord(char mem, int addr, long value) => _memory[(char.ToUpperInvariant(mem), addr)] = value & 0xFFFFFF;

    /// <summary>Parses <c>Mn=expr</c>.</summary>
    public static (int Target, Node Expr) ParseStatement(string line)
    {
        var eq = line.IndexOf('=', StringComparison.Ordinal);
        if (eq < 2 || char.ToUpperInvariant(line[0]) != 'M')
        {
            throw new FormatException($"expected Mn=expr: {line}");
        }

        var target = int.Parse(line.AsSpan(1, eq - 1), CultureInfo.InvariantCulture);
        return (target, ParseExpression(line[(eq + 1)..]));
    }

    /// <summary>Parses a PMAC expression over M-variables and integer constants.</summary>
    public static Node ParseExpression(string text)
    {
        var p = new Parser(text.Replace(" ", "", StringComparison.Ordinal));
        var n = p.Low();
        if (p.Pos != p.Text.Length)
        {
            throw new FormatException($"unexpected '{p.Text[p.Pos]}' at {p.Pos + 1} in {text}");
        }

        return n;
    }

    internal abstract record Node
    {
        public abstract long Eval(PlcEvaluator ev);
    }

    private sealed record Const(long Value) : Node
    {
        public override long Eval(PlcEvaluator ev) => Value;
    }

    private sealed record Var(int M) : Node
    {
        public override long Eval(PlcEvaluator ev) => ev.Get(M);
    }

    private sealed record Neg(Node Inner) : Node
    {
        public override long Eval(PlcEvaluator ev) => -Inner.Eval(ev);
    }

    private sealed record Bin(char Op, Node L, Node R) : Node
    {
        public override long Eval(PlcEvaluator ev)
        {
            var a = L.Eval(ev);
            var b = R.Eval(ev);
            return Op switch
            {
                '+' => a + b,
                '-' => a - b,
                '*' => a * b,
                '/' => b == 0 ? 0 : a / b,
                '&' => a & b,
                '|' => a | b,
                '^' => a ^ b,
                _ => throw new InvalidOperationException(Op.ToString()),
            };
        }
    }

    private sealed class Parser(string text)
    {
        public string Text { get; } = text;

        public int Pos { get; private set; }

        private char Peek => Pos < Text.Length ? Text[Pos] : '\0';

        public Node Low()
        {
            var n = High();
            while (Peek is '+' or '-' or '|' or '^')
            {
                var op = Text[Pos++];
                n = new Bin(op, n, High());
            }

            return n;
        }

        private Node High()
        {
            var n = Unary();
            while (Peek is '*' or '/' or '&')
            {
                var op = Text[Pos++];
                n = new Bin(op, n, Unary());
            }

            return n;
        }

        private Node Unary()
        {
            if (Peek == '-')
            {
                Pos++;
                return new Neg(Unary());
            }

            if (Peek == '(')
            {
                Pos++;
                var n = Low();
                if (Peek != ')')
                {
                    throw new FormatException($"expected ')' at {Pos + 1} in {Text}");
                }

                Pos++;
                return n;
            }

            var isVar = Peek is 'M' or 'm';
            if (isVar)
            {
                Pos++;
            }

            var start = Pos;
            while (char.IsAsciiDigit(Peek))
            {
                Pos++;
            }

            if (Pos == start)
            {
                throw new FormatException($"expected a number or M-variable at {Pos + 1} in {Text}");
            }

            var value = long.Parse(Text.AsSpan(start, Pos - start), CultureInfo.InvariantCulture);
            return isVar ? new Var((int)value) : new Const(value);
        }
    }
}
