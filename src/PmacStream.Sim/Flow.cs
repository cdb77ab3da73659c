using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>A position in a program buffer. <see cref="LoopBack"/> is the one-line WHILE to return to at line end.</summary>
internal struct Cursor(ProgramBuffer buffer, long line, int stmt)
{
    public ProgramBuffer Buffer = buffer;
    public long Line = line;
    public int Stmt = stmt;
    public int LoopBack = -1;

    public readonly bool AtEnd => Line >= Buffer.EndIndex;

    public readonly Stmt Current => Buffer[Line].Statements[Stmt];

    /// <summary>Moves past the current statement; at line end returns to a one-line WHILE or goes to the next line.</summary>
    public void Step()
    {
        Stmt++;
        if (Stmt >= Buffer[Line].Statements.Length)
        {
            EndLine();
        }
    }

    public void EndLine()
    {
        if (LoopBack >= 0)
        {
            Stmt = LoopBack;
            LoopBack = -1;
            return;
        }

        Line++;
        Stmt = 0;
        SkipEmptyLines();
    }

    public void JumpTo((long Line, int Stmt) target)
    {
        Line = target.Line;
        Stmt = target.Stmt;
        LoopBack = -1;
        if (Stmt >= Buffer[Line].Statements.Length)
        {
            EndLine();
        }
    }

    public void SkipEmptyLines()
    {
        while (Line < Buffer.EndIndex && Buffer[Line].Statements.Length == 0)
        {
            Line++;
        }
    }
}

/// <summary>Structured control flow shared by motion programs and PLC programs.</summary>
internal static class Flow
{
    /// <summary>
    /// Executes an IF/ELSE/ENDIF/WHILE/ENDWHILE at the cursor and moves it. Returns false when the statement is not
    /// control flow. <paramref name="loopedBack"/> is set when an ENDWHILE jumped back (a PLC scan ends there).
    /// </summary>
    public static bool TryExecute(ref Cursor c, IVariableAccess v, out bool loopedBack)
    {
        loopedBack = false;
        switch (c.Current)
        {
            case IfStmt f:
                If(ref c, f, v);
                return true;
            case ElseStmt:
                // Reached from the taken IF branch: skip the ELSE branch.
                if (c.Buffer.TryFindMatch(c.Line, c.Stmt, out var endIf))
                {
                    c.JumpTo(endIf);
                    c.Step();
                    return true;
                }

                throw new SimRuntimeException(16);
            case EndIfStmt:
                c.Step();
                return true;
            case WhileStmt w:
                While(ref c, w, v);
                return true;
            case EndWhileStmt:
                if (c.Buffer.TryFindMatch(c.Line, c.Stmt, out var start))
                {
                    c.JumpTo(start);
                    loopedBack = true;
                    return true;
                }

                throw new SimRuntimeException(16);
            default:
                return false;
        }
    }

    /// <summary>IF: into its branch when true; else past the line (one-line form) or to its ELSE/ENDIF.</summary>
    private static void If(ref Cursor c, IfStmt f, IVariableAccess v)
    {
        if (f.Condition.Eval(v) != 0)
        {
            c.Step();
        }
        else if (f.SingleLine)
        {
            c.LoopBack = -1;
            c.EndLine();
        }
        else if (c.Buffer.TryFindMatch(c.Line, c.Stmt, out var m))
        {
            c.JumpTo(m);
            if (!c.AtEnd && c.Current is ElseStmt or EndIfStmt)
            {
                c.Step();
            }
        }
        else
        {
            throw new SimRuntimeException(16);
        }
    }

    /// <summary>WHILE: into the loop when true (a one-line loop comes back to itself); else past the line or its ENDWHILE.</summary>
    private static void While(ref Cursor c, WhileStmt w, IVariableAccess v)
    {
        if (w.Condition.Eval(v) != 0)
        {
            if (w.SingleLine)
            {
                var self = c.Stmt;
                c.Step();
                c.LoopBack = self;
            }
            else
            {
                c.Step();
            }
        }
        else if (w.SingleLine)
        {
            c.LoopBack = -1;
            c.EndLine();
        }
        else if (c.Buffer.TryFindMatch(c.Line, c.Stmt, out var endWhile))
        {
            c.JumpTo(endWhile);
            c.Step();
        }
        else
        {
            throw new SimRuntimeException(16);
        }
    }
}

/// <summary>A run-time program error (ERR016 improperly structured program and the like): the program stops.</summary>
internal sealed class SimRuntimeException(int error) : Exception($"ERR{error:000}")
{
    public int Error { get; } = error;
}
