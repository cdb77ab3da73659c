using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// The return addresses of a coordinate system's subroutine calls (<c>CALL</c>, <c>GOSUB</c>, the G/M/T/D code
/// routines of PROG 1000-1003), at most 255 deep, and <c>READ</c>, which takes the caller's arguments.
/// </summary>
internal sealed class CallStack
{
    private const int MaxDepth = 255;

    private readonly List<Cursor> _frames = [];

    /// <summary>Calls under way (0 at the top level).</summary>
    public int Depth => _frames.Count;

    /// <summary>Where the top-level program stands (the first return address), when <see cref="Depth"/> is above 0.</summary>
    public Cursor Bottom => _frames[0];

    /// <summary>True when a return address lies in <paramref name="buffer"/>.</summary>
    public bool Contains(ProgramBuffer buffer) => _frames.Exists(f => f.Buffer == buffer);

    /// <summary>Forgets every call (a new start, a cleared buffer).</summary>
    public void Clear() => _frames.Clear();

    /// <summary>Enters <paramref name="buffer"/> at <paramref name="target"/> from <paramref name="pc"/>, which is kept as the return address and moves there. ERR016 when nested too deep.</summary>
    public void Call(ref Cursor pc, ProgramBuffer buffer, (long Line, int Stmt) target)
    {
        if (_frames.Count >= MaxDepth)
        {
            throw new SimRuntimeException(16);
        }

        _frames.Add(pc);
        pc = new Cursor(buffer, target.Line, target.Stmt);
        AtStatement(ref pc);
    }

    /// <summary>Returns from the innermost call: <paramref name="pc"/> moves to where calculation goes on in the caller.</summary>
    public void Return(ref Cursor pc)
    {
        pc = _frames[^1];
        _frames.RemoveAt(_frames.Count - 1);
        AtStatement(ref pc);
    }

    /// <summary>
    /// <c>READ(letters)</c>: the caller's arguments after the call, while their letter is one of
    /// <paramref name="letters"/>, into Q101..Q126 (A..Z), with Q100's bits saying which came; the caller goes on after them.
    /// </summary>
    public void Read(string letters, IVariableAccess variables)
    {
        if (_frames.Count == 0)
        {
            return;
        }

        var caller = _frames[^1];
        var q100 = 0L; // READ reports only the letters this call received
        var line = caller.Buffer[caller.Line].Statements;
        while (caller.Stmt < line.Length && ArgumentOf(line[caller.Stmt]) is { } arg && letters.Contains(arg.Letter))
        {
            var n = arg.Letter - 'A';
            variables.Set('Q', 101 + n, arg.Value.Eval(variables));
            q100 |= 1L << n;
            caller.Stmt++;
        }

        variables.Set('Q', 100, q100);
        _frames[^1] = caller;
    }

    /// <summary>A cursor past the end of its line's statements moves on to the next line.</summary>
    private static void AtStatement(ref Cursor pc)
    {
        if (!pc.AtEnd && pc.Stmt >= pc.Buffer[pc.Line].Statements.Length)
        {
            pc.EndLine();
        }
    }

    /// <summary>Any letter-value pair after a call is an argument READ can take (F and M/G/T/D included).</summary>
    private static (char Letter, Expr Value)? ArgumentOf(Stmt s) => s switch
    {
        WordStmt w => (w.Letter, w.Value),
        ParamStmt { Kind: ParamKind.Feed } f => ('F', f.Value),
        CodeCallStmt c => (c.Letter, c.Code),
        _ => null,
    };
}
