using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// A PLC program: scanned from the top each cycle. As on a Turbo PMAC, a scan ends at the end of the program or
/// when an ENDWHILE jumps back (the loop continues at its WHILE in the next scan), so a waiting loop cannot hang.
/// </summary>
internal sealed class PlcProgram(ProgramBuffer buffer)
{
    private Cursor _pc = new(buffer, buffer.BaseIndex, 0);

    public ProgramBuffer Buffer { get; } = buffer;

    public bool Enabled { get; set; }

    public void Restart() => _pc = new Cursor(Buffer, Buffer.BaseIndex, 0);

    /// <summary>Runs one scan; returns an ERR number for a run-time error, else 0.</summary>
    public int Scan(IVariableAccess v, int budget)
    {
        if (_pc.AtEnd || _pc.Line < Buffer.BaseIndex)
        {
            Restart();
        }

        _pc.SkipEmptyLines();
        try
        {
            while (!_pc.AtEnd && budget-- > 0)
            {
                if (Flow.TryExecute(ref _pc, v, out var loopedBack))
                {
                    if (loopedBack)
                    {
                        return 0;
                    }

                    continue;
                }

                if (_pc.Current is AssignStmt a)
                {
                    v.Set(a.Kind, a.IndexOf(v), a.Value.Eval(v));
                }

                // Motion statements have no meaning in a PLC; the generator never writes them.
                _pc.Step();
            }
        }
        catch (SimRuntimeException e)
        {
            Enabled = false;
            Restart();
            return e.Error;
        }

        if (_pc.AtEnd)
        {
            Restart();
        }

        return 0;
    }
}
