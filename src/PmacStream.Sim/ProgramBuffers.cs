using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// The controller's program memory as the buffer commands see it: motion programs (<c>PROG n</c>), PLC programs,
/// the coordinate systems' rotary buffers, and the one buffer open for new lines, owned by the port that opened it
/// (another port's <c>OPEN</c> is ERR007). <c>OPEN ROT</c> opens the rotary buffers of every coordinate system; a
/// line stored then goes to the one its port addresses. Guarded by the simulator's lock.
/// </summary>
internal sealed class ProgramBuffers(CoordinateSystem[] coordinateSystems, PlcTable plcs, SimOptions options, AxisMatrices matrices)
{
    private readonly Dictionary<int, ProgramBuffer> _programs = [];
    private SimPort? _owner;
    private BufferKind _kind;
    private ProgramBuffer? _open;

    /// <summary>Program lines stored into any buffer.</summary>
    public long LinesReceived { get; private set; }

    /// <summary>True when <paramref name="port"/> has a buffer open: what it sends is stored, not run.</summary>
    public bool IsOpenOn(SimPort port) => _owner == port;

    /// <summary>Motion program <paramref name="number"/>, or null.</summary>
    public ProgramBuffer? FindProgram(int number) => _programs.GetValueOrDefault(number);

    /// <summary>Forgets every motion program (factory reset).</summary>
    public void ClearPrograms() => _programs.Clear();

    /// <summary>Stores a program line sent on <paramref name="port"/>, which has a buffer open; a rotary line that does not fit is refused.</summary>
    public void Store(SimPort port, ProgramLine line)
    {
        if (_kind == BufferKind.Rotary)
        {
            var cs = coordinateSystems[port.CoordinateSystem];
            var rotary = cs.Rotary;
            if (rotary is null || !rotary.Fits(line.Words) || (options.RefuseWhileFullBitSet && cs.RotaryFullBit))
            {
                throw new SimSyntaxException(options.RotaryFullErrorCode);
            }

            rotary.Append(line);
            cs.UpdateFullBit();
        }
        else
        {
            _open!.Append(line);
        }

        LinesReceived++;
    }

    /// <summary><c>OPEN ROT</c>, <c>OPEN PROG n</c>, <c>OPEN PLC n</c>.</summary>
    public void Open(SimPort port, ExprParser p)
    {
        var what = p.Next();
        if (_owner is not null && _owner != port)
        {
            throw new SimSyntaxException(7);
        }

        if (_owner == port)
        {
            Close();
        }

        switch (what.Text)
        {
            case "ROT" or "ROTARY" when what.Kind == TokenKind.Word:
                _kind = BufferKind.Rotary;
                _open = null;
                SetRotaryOpen(true);
                break;
            case "PROG" or "PROGRAM" when what.Kind == TokenKind.Word:
                {
                    var n = p.IntArgument(1, 65535);
                    if (_programs.TryGetValue(n, out var existing) && coordinateSystems.Skip(1).Any(c => c.IsExecuting(existing)))
                    {
                        throw new SimSyntaxException(1);
                    }

                    if (existing is null)
                    {
                        existing = new ProgramBuffer(BufferKind.Prog, n, 0);
                        _programs[n] = existing;
                    }

                    _kind = BufferKind.Prog;
                    _open = existing;
                    break;
                }

            case "PLC" when what.Kind == TokenKind.Word:
                _kind = BufferKind.Plc;
                _open = plcs.Open(p.IntArgument(0, PlcTable.Count - 1));
                break;
            default:
                throw new SimSyntaxException(3);
        }

        _owner = port;
        _open?.IsOpen = true;
    }

    /// <summary>
    /// <c>CLOSE</c> on <paramref name="port"/>: closes its buffer (nothing when another port's is open); a program
    /// with an IF or WHILE left open is ERR009, closed all the same.
    /// </summary>
    public void Close(SimPort port)
    {
        if (_owner != port)
        {
            return;
        }

        var structured = _open?.IsStructured() ?? true;
        Close();
        if (!structured)
        {
            throw new SimSyntaxException(9);
        }
    }

    /// <summary>Closes whatever buffer is open (a port closed, a reset); a closed PLC restarts from the top.</summary>
    public void Close()
    {
        if (_owner is null)
        {
            return;
        }

        if (_kind == BufferKind.Rotary)
        {
            SetRotaryOpen(false);
        }
        else if (_open is not null)
        {
            _open.IsOpen = false;
            if (_kind == BufferKind.Plc)
            {
                plcs[_open.Number]?.Restart();
            }
        }

        _owner = null;
        _open = null;
    }

    /// <summary><c>CLEAR</c>: empties the buffer <paramref name="port"/> has open (a rotary buffer: its coordinate system's).</summary>
    public void Clear(SimPort port)
    {
        if (_owner != port)
        {
            throw new SimSyntaxException(5);
        }

        if (_kind == BufferKind.Rotary)
        {
            var cs = coordinateSystems[port.CoordinateSystem];
            if (cs.Rotary is { } r)
            {
                r.Clear();
                cs.RotaryCleared();
                cs.UpdateFullBit();
            }

            return;
        }

        _open!.Clear();
    }

    /// <summary>
    /// <c>SIZE</c>: the user memory's words not taken by stored motion programs, PLCs and defined rotary buffers;
    /// negative while a buffer is open (PMAC Software Reference p. 286, "If a buffer is currently open, the value is
    /// reported as a negative number").
    /// </summary>
    public int UnusedWords()
    {
        long used = 0;
        foreach (var p in _programs.Values)
        {
            used += p.UsedWords;
        }

        for (var i = 0; i < PlcTable.Count; i++)
        {
            used += plcs[i]?.Buffer.UsedWords ?? 0;
        }

        foreach (var c in coordinateSystems.Skip(1))
        {
            used += c.Rotary?.CapacityWords ?? 0;
        }

        var unused = (int)Math.Max(0, options.UserMemoryWords - used);
        return _owner is null ? unused : -unused;
    }

    /// <summary><c>DEFINE ROT n</c> (a new rotary buffer of n words for the port's coordinate system), <c>DEFINE GATHER</c> (accepted).</summary>
    public void Define(SimPort port, ExprParser p)
    {
        var what = p.Next();
        switch (what.Text)
        {
            case "ROT" or "ROTARY":
                {
                    var size = p.IntArgument(1, 8_388_607);
                    var cs = RotaryChangeable(port);
                    cs.DropRotary();
                    cs.Rotary = new ProgramBuffer(BufferKind.Rotary, 0, size);
                    return;
                }

            case "GAT" or "GATHER":
                if (p.Peek.Kind == TokenKind.Number)
                {
                    p.Pos++;
                }

                return;
            case "TBUF":
                // Axis transformation matrices for TSEL (global on a Turbo PMAC).
                matrices.Define(p.IntArgument(1, 8191));
                return;
            default:
                throw new SimSyntaxException(3);
        }
    }

    /// <summary><c>DELETE ROT</c> (the port's coordinate system's rotary buffer), <c>DELETE GATHER</c> (accepted).</summary>
    public void Delete(SimPort port, ExprParser p)
    {
        var what = p.Next();
        switch (what.Text)
        {
            case "ROT" or "ROTARY":
                RotaryChangeable(port).DropRotary();
                return;
            case "GAT" or "GATHER":
                return;
            default:
                throw new SimSyntaxException(3);
        }
    }

    /// <summary><c>LIST PROG n</c>, <c>LIST PLC n</c>, <c>LIST ROT</c>: the stored lines, one value each.</summary>
    public void List(SimPort port, ExprParser p, List<string> outputs)
    {
        var what = p.Next();
        ProgramBuffer? buffer = what.Text switch
        {
            "PROG" or "PROGRAM" => _programs.GetValueOrDefault(p.IntArgument(1, 65535)),
            "PLC" => plcs[p.IntArgument(0, PlcTable.Count - 1)]?.Buffer,
            "ROT" or "ROTARY" => coordinateSystems[port.CoordinateSystem].Rotary,
            _ => throw new SimSyntaxException(3),
        };
        if (buffer is null)
        {
            throw new SimSyntaxException(what.Text.StartsWith("ROT", StringComparison.Ordinal) ? 15 : 3);
        }

        for (var i = buffer.BaseIndex; i < buffer.EndIndex; i++)
        {
            outputs.Add(buffer[i].Text);
        }
    }

    /// <summary>
    /// The port's coordinate system, when its rotary buffer may be redefined or deleted: not while it runs from it
    /// (ERR001), not while rotary buffers are open (ERR007).
    /// </summary>
    private CoordinateSystem RotaryChangeable(SimPort port)
    {
        var cs = coordinateSystems[port.CoordinateSystem];
        if (cs.Running && cs.ProgramNumber == 0)
        {
            throw new SimSyntaxException(1);
        }

        if (_owner is not null && _kind == BufferKind.Rotary)
        {
            throw new SimSyntaxException(7);
        }

        return cs;
    }

    private void SetRotaryOpen(bool open)
    {
        foreach (var c in coordinateSystems.Skip(1))
        {
            if (c.Rotary is not null)
            {
                c.Rotary.IsOpen = open;
            }
        }
    }
}
