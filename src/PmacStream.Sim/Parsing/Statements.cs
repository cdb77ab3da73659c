namespace PmacStream.Sim.Parsing;

/// <summary>One compiled motion/PLC program statement.</summary>
internal abstract class Stmt
{
    /// <summary>Rotary-buffer words this statement costs (about one per value, as the manual describes).</summary>
    public virtual int Words => 1;
}

/// <summary>A letter with a value: an axis (X..W), a circle vector (I J K), a radius (R), or an argument for READ.</summary>
internal sealed class WordStmt(char letter, Expr value) : Stmt
{
    public char Letter { get; } = letter;

    public Expr Value { get; } = value;

    public override int Words => Value.Words;
}

/// <summary><c>Gnn</c>, <c>Mnn</c>, <c>Tnn</c>, <c>Dnn</c>: a call into PROG 1000..1003 at label N(nn*1000).</summary>
internal sealed class CodeCallStmt(char letter, Expr code) : Stmt
{
    public char Letter { get; } = letter;

    public Expr Code { get; } = code;
}

/// <summary><c>P1=expr</c>, <c>M0==expr</c> (synchronous: written at the start of the next move), <c>P(expr)=expr</c>.</summary>
internal sealed class AssignStmt(char kind, int index, Expr value, bool synchronous, Expr? indexExpression = null) : Stmt
{
    public char Kind { get; } = kind;

    public int Index { get; } = index;

    /// <summary>The variable this assignment writes now: its number, or the value of its index expression.</summary>
    public int IndexOf(IVariableAccess variables) => indexExpression is null ? Index : IndirectVarExpr.Number(indexExpression.Eval(variables));

    public Expr Value { get; } = value;

    public bool Synchronous { get; } = synchronous;

    public override int Words => 1 + Value.Words;
}

internal enum MotionMode
{
    Rapid,
    Linear,
    Circle1,
    Circle2,
}

internal sealed class ModeStmt(MotionMode mode) : Stmt
{
    public MotionMode Mode { get; } = mode;
}

/// <summary><c>ABS</c>/<c>INC</c>, optionally for listed axes; <c>R</c> in the list sets the arc-centre vector mode.</summary>
internal sealed class AbsIncStmt(bool incremental, string axes) : Stmt
{
    public bool Incremental { get; } = incremental;

    /// <summary>Axes the mode applies to; empty for all axes.</summary>
    public string Axes { get; } = axes;
}

internal enum ParamKind
{
    Feed,
    Ta,
    Ts,
    Tm,
    CutterComp,
    CutterRadius,
}

internal sealed class ParamStmt(ParamKind kind, Expr value) : Stmt
{
    public ParamKind Kind { get; } = kind;

    public Expr Value { get; } = value;

    public override int Words => 1 + Value.Words;
}

/// <summary>The axis transformation matrix statements (<c>TSEL</c>, <c>TINIT</c>, <c>ADIS</c>, <c>IDIS</c>, <c>AROT</c>, <c>IROT</c>).</summary>
internal enum MatrixOp
{
    Select,
    Init,
    AbsoluteDisplacement,
    IncrementalDisplacement,
    AbsoluteRotation,
    IncrementalRotation,
}

/// <summary>A matrix statement and its constant: the matrix number (TSEL) or the first Q-variable (ADIS ...).</summary>
internal sealed class MatrixStmt(MatrixOp op, int argument) : Stmt
{
    public MatrixOp Op { get; } = op;

    public int Argument { get; } = argument;
}

/// <summary><c>NORMAL K-1</c>: the arc plane is perpendicular to the vector.</summary>
internal sealed class NormalStmt(double i, double j, double k) : Stmt
{
    public double I { get; } = i;

    public double J { get; } = j;

    public double K { get; } = k;
}

/// <summary><c>DWELL t</c> (stops lookahead) or <c>DELAY t</c> (does not), t in milliseconds.</summary>
internal sealed class DwellStmt(Expr ms, bool delay) : Stmt
{
    public Expr Milliseconds { get; } = ms;

    public bool Delay { get; } = delay;

    public override int Words => 1 + Milliseconds.Words;
}

internal enum JumpKind
{
    Call,
    Gosub,
    Goto,
}

/// <summary><c>CALL n[.label]</c>, <c>GOSUB label</c>, <c>GOTO label</c>.</summary>
internal sealed class JumpStmt(JumpKind kind, Expr target) : Stmt
{
    public JumpKind Kind { get; } = kind;

    public Expr Target { get; } = target;
}

internal sealed class ReturnStmt : Stmt;

internal sealed class StopStmt : Stmt;

/// <summary><c>READ(X,Y,...)</c>: copies the caller's following letter values into Q(100+n).</summary>
internal sealed class ReadStmt(string letters) : Stmt
{
    public string Letters { get; } = letters;
}

internal sealed class LabelStmt(int label) : Stmt
{
    public int Label { get; } = label;
}

/// <summary><c>IF (cond)</c>: block form, or one-line form when statements follow on the same line.</summary>
internal sealed class IfStmt(Expr condition) : Stmt
{
    public Expr Condition { get; } = condition;

    public bool SingleLine { get; set; }
}

internal sealed class ElseStmt : Stmt;

internal sealed class EndIfStmt : Stmt;

internal sealed class WhileStmt(Expr condition) : Stmt
{
    public Expr Condition { get; } = condition;

    public bool SingleLine { get; set; }
}

internal sealed class EndWhileStmt : Stmt;

/// <summary><c>CMD"..."</c>/<c>SEND"..."</c>: accepted and ignored by the simulator.</summary>
internal sealed class NoOpStmt : Stmt;

/// <summary>Parses program statements (what may be stored in a buffer) from a token stream.</summary>
internal static class ProgramParser
{
    /// <summary>
    /// Parses the statement at the cursor, or returns null (cursor unchanged) when the next tokens are not a program
    /// statement (an online-only command, or the end of the line).
    /// </summary>
    public static Stmt? TryParse(ExprParser p)
    {
        var t = p.Peek;
        if (t.Kind != TokenKind.Word)
        {
            return null;
        }

        var save = p.Pos;
        if (t.IsLetter)
        {
            return LetterStatement(p, t, save);
        }

        p.Pos++;
        if ((MotionStatement(p, t.Text) ?? FlowStatement(p, t.Text)) is { } statement)
        {
            return statement;
        }

        p.Pos = save;
        return null;
    }

    /// <summary>A statement that starts with one letter: an assignment, a code call, a label or an axis word.</summary>
    private static Stmt? LetterStatement(ExprParser p, Token t, int save)
    {
        var letter = t.Text[0];
        var next = p.PeekAt(1);
        if (letter is 'I' or 'P' or 'Q' or 'M' && next.Is("("))
        {
            // P(expression)=value: the variable an expression numbers.
            p.Pos++;
            var index = p.ParseValue();
            if (p.Peek.Is("="))
            {
                p.Pos++;
                return new AssignStmt(letter, -1, p.ParseExpression(), false, index);
            }

            p.Pos = save;
        }

        if (letter is 'I' or 'P' or 'Q' or 'M' && next.Kind == TokenKind.Number)
        {
            var after = p.PeekAt(2);
            if (after.Is("=") || (letter == 'M' && after.Is("==")))
            {
                p.Pos += 3;
                var index = ExprParser.VariableIndex(next);
                return new AssignStmt(letter, index, p.ParseExpression(), after.Text == "==");
            }

            if (after.Is("->") || after.Is(".."))
            {
                return null;
            }

            if (letter == 'M')
            {
                p.Pos++;
                return new CodeCallStmt('M', p.ParseValue());
            }
        }

        p.Pos++;
        if (!p.AtValue)
        {
            p.Pos = save;
            return null;
        }

        return letter switch
        {
            'G' or 'M' or 'T' or 'D' => new CodeCallStmt(letter, p.ParseValue()),
            'F' => new ParamStmt(ParamKind.Feed, p.ParseValue()),
            'N' or 'O' => new LabelStmt(LabelNumber(p)),
            _ => new WordStmt(letter, p.ParseValue()),
        };
    }

    /// <summary>A keyword that shapes motion (modes, move parameters, the axis matrices), or null for another word.</summary>
    private static Stmt? MotionStatement(ExprParser p, string keyword)
    {
        switch (keyword)
        {
            case "RAPID":
                return new ModeStmt(MotionMode.Rapid);
            case "LINEAR":
                return new ModeStmt(MotionMode.Linear);
            case "CIRCLE":
                {
                    var n = p.Next();
                    return n.Kind == TokenKind.Number && n.Value is 1 or 2
                        ? new ModeStmt(n.Value == 1 ? MotionMode.Circle1 : MotionMode.Circle2)
                        : throw new SimSyntaxException(3);
                }

            case "ABS":
            case "INC":
                return new AbsIncStmt(keyword == "INC", p.Peek.Is("(") ? AxisList(p) : string.Empty);
            case "NORMAL":
                return Normal(p);
            case "DWELL":
            case "DELAY":
                return new DwellStmt(p.ParseValue(), keyword == "DELAY");
            case "TA":
                return new ParamStmt(ParamKind.Ta, p.ParseValue());
            case "TS":
                return new ParamStmt(ParamKind.Ts, p.ParseValue());
            case "TM":
                return new ParamStmt(ParamKind.Tm, p.ParseValue());
            case "CC":
                {
                    // CC0 off, CC1 left, CC2 right (what PROG 1000 runs for G40/G41/G42).
                    var mode = p.ParseValue();
                    return mode is ConstExpr { Value: 0 or 1 or 2 } ? new ParamStmt(ParamKind.CutterComp, mode) : throw new SimSyntaxException(3);
                }

            case "CCR":
                return new ParamStmt(ParamKind.CutterRadius, p.ParseValue());
            case "TSEL" or "TSELECT":
                return new MatrixStmt(MatrixOp.Select, p.IntArgument(0, 8191));
            case "TINIT":
                return new MatrixStmt(MatrixOp.Init, 0);
            case "ADIS":
                return new MatrixStmt(MatrixOp.AbsoluteDisplacement, p.IntArgument(0, 8189));
            case "IDIS":
                return new MatrixStmt(MatrixOp.IncrementalDisplacement, p.IntArgument(0, 8189));
            case "AROT":
                return new MatrixStmt(MatrixOp.AbsoluteRotation, p.IntArgument(0, 8183));
            case "IROT":
                return new MatrixStmt(MatrixOp.IncrementalRotation, p.IntArgument(0, 8183));
            default:
                return null;
        }
    }

    /// <summary><c>NORMAL</c> with its I, J and K components (at least one, each a constant).</summary>
    private static NormalStmt Normal(ExprParser p)
    {
        double i = 0, j = 0, k = 0;
        var any = false;
        while (p.Peek.IsLetter && p.Peek.Text is "I" or "J" or "K")
        {
            var axis = p.Next().Text[0];
            var value = p.ParseValue() is ConstExpr c ? c.Value : throw new SimSyntaxException(3);
            _ = axis == 'I' ? i = value : axis == 'J' ? j = value : k = value;
            any = true;
        }

        return any ? new NormalStmt(i, j, k) : throw new SimSyntaxException(3);
    }

    /// <summary>A keyword of program flow (jumps, conditions, loops, READ, CMD/SEND), or null for another word.</summary>
    private static Stmt? FlowStatement(ExprParser p, string keyword)
    {
        switch (keyword)
        {
            case "CALL":
                return new JumpStmt(JumpKind.Call, p.ParseValue());
            case "GOSUB":
                return new JumpStmt(JumpKind.Gosub, p.ParseValue());
            case "GOTO":
                return new JumpStmt(JumpKind.Goto, p.ParseValue());
            case "RET":
            case "RETURN":
                return new ReturnStmt();
            case "STOP":
                return new StopStmt();
            case "READ":
                {
                    var list = AxisList(p);
                    return list.Length > 0 ? new ReadStmt(list) : throw new SimSyntaxException(3);
                }

            case "IF":
                return new IfStmt(Condition(p));
            case "WHILE":
                return new WhileStmt(Condition(p));
            case "ELSE":
                return new ElseStmt();
            case "ENDIF":
            case "ENDI":
                return new EndIfStmt();
            case "ENDWHILE":
            case "ENDW":
                return new EndWhileStmt();
            case "CMD":
            case "SEND":
                if (p.Peek.Kind == TokenKind.Text)
                {
                    p.Pos++;
                    return new NoOpStmt();
                }

                throw new SimSyntaxException(3);
            default:
                return null;
        }
    }

    /// <summary>The parenthesised condition of IF or WHILE.</summary>
    private static Expr Condition(ExprParser p)
    {
        p.Expect("(");
        var cond = p.ParseExpression(condition: true);
        p.Expect(")");
        // Turbo PMAC also accepts "(a) AND (b)" outside one pair of parentheses.
        while (p.Peek.Is("AND") || p.Peek.Is("OR"))
        {
            var op = p.Next().Text;
            p.Expect("(");
            var more = p.ParseExpression(condition: true);
            p.Expect(")");
            cond = new BinaryExpr(op, cond, more);
        }

        return cond;
    }

    /// <summary>Parses a run of statements; the one-line IF/WHILE forms are marked here.</summary>
    public static List<Stmt> ParseRun(ExprParser p)
    {
        var list = new List<Stmt>();
        ParseRun(p, list);
        return list;
    }

    /// <summary>Parses a run of statements into <paramref name="list"/> (cleared first), so a caller can reuse one list.</summary>
    public static void ParseRun(ExprParser p, List<Stmt> list)
    {
        list.Clear();
        while (TryParse(p) is { } s)
        {
            list.Add(s);
        }

        for (var i = 0; i < list.Count - 1; i++)
        {
            if (list[i] is IfStmt f && list[i + 1] is not EndIfStmt)
            {
                f.SingleLine = true;
            }
            else if (list[i] is WhileStmt w && list[i + 1] is not EndWhileStmt)
            {
                w.SingleLine = true;
            }
        }
    }

    private static int LabelNumber(ExprParser p)
    {
        var v = p.ParseValue();
        return v is ConstExpr c && c.Value >= 0 ? (int)c.Value : throw new SimSyntaxException(3);
    }

    private static string AxisList(ExprParser p)
    {
        p.Expect("(");
        var sb = new System.Text.StringBuilder();
        while (!p.Peek.Is(")"))
        {
            var w = p.Next();
            if (!w.IsLetter)
            {
                throw new SimSyntaxException(3);
            }

            sb.Append(w.Text);
            p.Accept(",");
        }

        p.Expect(")");
        return sb.ToString();
    }
}
