using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// PLC programs 0..31: which are in memory and enabled, and their background scan (subject to I5: bit 0 enables PLC
/// 0, bit 1 PLCs 1..31). Guarded by the simulator's lock.
/// </summary>
internal sealed class PlcTable
{
    /// <summary>PLC numbers 0..31.</summary>
    public const int Count = 32;

    private readonly PlcProgram?[] _plcs = new PlcProgram?[Count];

    /// <summary>PLC <paramref name="number"/>, or null when none is in memory.</summary>
    public PlcProgram? this[int number] => _plcs[number];

    /// <summary>True when any PLC is enabled (the clock must scan).</summary>
    public bool AnyEnabled
    {
        get
        {
            foreach (var p in _plcs)
            {
                if (p is { Enabled: true })
                {
                    return true;
                }
            }

            return false;
        }
    }

    /// <summary>
    /// <c>OPEN PLC n</c>: the PLC's buffer (created when new); opening a PLC buffer stops it until <c>ENABLE PLC</c>.
    /// </summary>
    public ProgramBuffer Open(int number)
    {
        var plc = _plcs[number] ??= new PlcProgram(new ProgramBuffer(BufferKind.Plc, number, 0));
        plc.Enabled = false;
        return plc.Buffer;
    }

    /// <summary><c>ENABLE PLC</c> / <c>DISABLE PLC</c>: an enabled PLC restarts from the top; one whose buffer is open stays off.</summary>
    public void Enable(IEnumerable<int> numbers, bool enable)
    {
        foreach (var n in numbers)
        {
            if (_plcs[n] is { } plc)
            {
                if (enable && !plc.Enabled)
                {
                    plc.Restart();
                }

                plc.Enabled = enable && !plc.Buffer.IsOpen;
            }
        }
    }

    /// <summary>Forgets every PLC program (factory reset).</summary>
    public void Clear() => Array.Clear(_plcs);

    /// <summary>At power-on every PLC program in memory runs (subject to I5), from the top.</summary>
    public void PowerOn()
    {
        foreach (var plc in _plcs)
        {
            if (plc is not null)
            {
                plc.Enabled = true;
                plc.Restart();
            }
        }
    }

    /// <summary>One scan of every enabled PLC that <paramref name="i5"/> allows; <paramref name="onError"/> gets each run-time error (the PLC is disabled).</summary>
    public void Scan(IVariableAccess variables, int i5, int maxStatements, Action<int, int> onError)
    {
        for (var n = 0; n < _plcs.Length; n++)
        {
            var plc = _plcs[n];
            if (plc is not { Enabled: true } || (n == 0 ? (i5 & 1) == 0 : (i5 & 2) == 0))
            {
                continue;
            }

            var error = plc.Scan(variables, maxStatements);
            if (error != 0)
            {
                onError(n, error);
            }
        }
    }
}
