using System.Globalization;
using System.Text;
using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>Online command interpretation and reply framing.</summary>
public sealed partial class PmacSimulator
{
    private const byte Ack = 0x06;
    private const byte Bel = 0x07;
    private const byte Cr = 0x0D;
    private const byte Lf = 0x0A;

    internal byte[] ExecuteLine(SimPort port, string line)
    {
        int error = 0;
        byte[] reply;
        bool wake, events;
        lock (_sync)
        {
            var outputs = _outputs;
            outputs.Clear();
            try
            {
                ProcessLine(port, line, outputs);
            }
            catch (SimSyntaxException e)
            {
                error = e.Error;
                _errors++;
            }
            catch (Exception e) when (e is not OutOfMemoryException)
            {
                // A simulator bug must not take a server down: answer ERR003 and remember it for the tests.
                error = 3;
                _errors++;
                InternalFaults++;
                Log.Error(e, "simulator fault on {Port} for '{Line}'", port.Name, line);
            }

            // Let the controller react at this instant (calculation after R, zero-time moves).
            Pump(_now, untilIdle: false, maxIterations: 1);
            reply = Frame(outputs, error, port.I3, port.I6);
            outputs.Clear();

            // Waking the clock thread costs a futex call and lock contention per line. It only matters while a
            // coordinate system has motion to run or a PLC scans; otherwise the clock's own 1 ms tick does the same.
            wake = AnyRunningOrMoving() || AnyPlcEnabled();
            events = _pendingEvents.Count > 0;
        }

        if (wake)
        {
            Wake();
        }

        if (events)
        {
            RaiseEvents();
        }

        return reply;
    }

    internal byte[] ExecuteControl(SimPort port, char control)
    {
        var c = control < 32 ? (char)(control + 64) : char.ToUpperInvariant(control);
        string text;
        lock (_sync)
        {
            switch (c)
            {
                case 'X':
                    return [];
                case 'B':
                    text = string.Join(" ", Enumerable.Range(1, 8).Select(MotorStatus)) + "\r";
                    break;
                case 'C':
                    text = string.Join(" ", Enumerable.Range(1, 8).Select(n => CsStatus(_cs[n]))) + "\r";
                    break;
                case 'G':
                    text = "000000000000\r";
                    break;
                case 'P':
                    text = string.Join(" ", Enumerable.Range(1, 8).Select(n => Format(MotorPosition(n)))) + "\r";
                    break;
                case 'V':
                case 'F':
                    text = string.Join(" ", Enumerable.Repeat("0", 8)) + "\r";
                    break;
                default:
                    _errors++;
                    return [Bel];
            }
        }

        return Encoding.ASCII.GetBytes(text);
    }

    private static byte[] Frame(List<string> outputs, int error, int i3, int i6)
    {
        if (outputs.Count == 0 && error == 0)
        {
            // The common case (a stored program line, a setting): just the handshake.
            return i3 switch
            {
                2 or 3 => [Ack],
                1 => [Lf],
                _ => [],
            };
        }

        var bytes = new List<byte>(16);
        foreach (var o in outputs)
        {
            if (i3 == 3)
            {
                bytes.Add(Lf);
            }

            bytes.AddRange(Encoding.ASCII.GetBytes(o));
            bytes.Add(Cr);
        }

        if (error != 0)
        {
            bytes.Add(Bel);
            if (i6 != 0)
            {
                bytes.AddRange(Encoding.ASCII.GetBytes(string.Create(CultureInfo.InvariantCulture, $"ERR{error:000}")));
                bytes.Add(Cr);
            }
        }
        else if (i3 is 2 or 3)
        {
            bytes.Add(Ack);
        }
        else if (i3 == 1)
        {
            bytes.Add(Lf);
        }

        return [.. bytes];
    }

    private void ProcessLine(SimPort port, string line, List<string> outputs)
    {
        var upper = line.ToUpperInvariant(); // returns the same string when it is upper case already
        var reuse = !_lineBusy;
        var tokens = reuse ? _tokens : new List<Token>(16);
        var stmts = reuse ? _stmts : new List<Stmt>();
        _lineBusy = true;
        try
        {
            Lexer.Tokenize(upper, tokens);
            var p = reuse ? _parser : new ExprParser(tokens);
            p.Reset(tokens);
            while (p.Peek.Kind != TokenKind.End)
            {
                if (_openOwner == port)
                {
                    var start = p.Pos;
                    ProgramParser.ParseRun(p, stmts);
                    if (stmts.Count > 0)
                    {
                        var text = StoredText(upper, tokens[start].Start, tokens[p.Pos - 1].End);
                        StoreLine(port, text, [.. stmts]);
                        continue;
                    }
                }

                ExecuteOnline(port, p, outputs);
            }
        }
        finally
        {
            if (reuse)
            {
                _lineBusy = false;
                tokens.Clear();
                stmts.Clear();
            }
        }
    }

    /// <summary>
    /// The text LIST shows for <c>upper[start..end]</c>: trimmed, with blank runs collapsed to one space. Without
    /// anything to collapse it is a plain slice, or the line itself when the statements span all of it.
    /// </summary>
    private static string StoredText(string upper, int start, int end)
    {
        var span = upper.AsSpan(start, end - start);
        if (span.IsEmpty || char.IsWhiteSpace(span[0]) || char.IsWhiteSpace(span[^1]) || span.Contains('\t') || span.Contains("  ", StringComparison.Ordinal))
        {
            return CollapseSpaces(upper[start..end]);
        }

        return start == 0 && end == upper.Length ? upper : upper[start..end];
    }

    private static string CollapseSpaces(string text)
    {
        var sb = new StringBuilder(text.Length);
        var space = false;
        foreach (var ch in text.Trim())
        {
            if (ch is ' ' or '\t')
            {
                space = true;
                continue;
            }

            if (space)
            {
                sb.Append(' ');
                space = false;
            }

            sb.Append(ch);
        }

        return sb.ToString();
    }

    private void StoreLine(SimPort port, string text, Stmt[] stmts)
    {
        var line = new ProgramLine(text, stmts);
        if (_openKind == BufferKind.Rotary)
        {
            var cs = _cs[port.CoordinateSystem];
            var rotary = cs.Rotary;
            if (rotary is null || !rotary.Fits(line.Words) || (Options.RefuseWhileFullBitSet && cs.RotaryFullBit))
            {
                throw new SimSyntaxException(Options.RotaryFullErrorCode);
            }

            rotary.Append(line);
            cs.UpdateFullBit();
        }
        else
        {
            _openBuffer!.Append(line);
        }

        _linesReceived++;
    }

    private void ExecuteOnline(SimPort port, ExprParser p, List<string> outputs)
    {
        var t = p.Next();
        var cs = _cs[port.CoordinateSystem];
        if (t.Kind == TokenKind.Symbol)
        {
            switch (t.Text)
            {
                case "&":
                    port.CoordinateSystem = IntArgument(p, 1, SimMemory.CoordinateSystems);
                    return;
                case "#":
                    port.Motor = IntArgument(p, 1, 32);
                    if (p.Accept("->"))
                    {
                        MotorDefinition(port.Motor, p, outputs);
                    }

                    return;
                case "%":
                    if (p.AtValue)
                    {
                        cs.OverrideTarget = Math.Clamp(p.ParseValue().Eval(cs), 0, 32767);
                    }
                    else
                    {
                        outputs.Add(Format(Math.Round(cs.OverrideCurrent, 3)));
                    }

                    return;
                case "?":
                    {
                        var n = 1;
                        while (p.Peek.Is("?"))
                        {
                            p.Pos++;
                            n++;
                        }

                        outputs.Add(n switch
                        {
                            1 => MotorStatus(port.Motor),
                            2 => CsStatus(cs),
                            3 => "000000000000",
                            _ => throw new SimSyntaxException(3),
                        });
                        return;
                    }

                case "$$$":
                    Reset(factory: false);
                    return;
                case "$$$***":
                    Reset(factory: true);
                    return;
                default:
                    throw new SimSyntaxException(3);
            }
        }

        if (t.Kind != TokenKind.Word)
        {
            throw new SimSyntaxException(3);
        }

        if (t.IsLetter && t.Text[0] is 'I' or 'P' or 'Q' or 'M' && p.Peek.Kind == TokenKind.Number)
        {
            Variable(port, t.Text[0], p, outputs);
            return;
        }

        switch (t.Text)
        {
            case "R" or "S" or "H" or "Q" or "A" or "K" when !p.AtValue:
                Motion(cs, t.Text[0]);
                return;
            case "B":
                {
                    var n = IntArgument(p, 0, 65535);
                    Check(cs.Begin(n));
                    return;
                }

            case "P" when !p.AtValue:
                outputs.Add(Format(MotorPosition(port.Motor)));
                return;
            case "PR":
                outputs.Add(cs.RotaryLinesAhead().ToString(CultureInfo.InvariantCulture));
                return;
            case "OPEN":
                Open(port, p);
                return;
            case "CLOSE":
                if (_openOwner == port)
                {
                    var structured = _openBuffer?.IsStructured() ?? true;
                    CloseBuffer();
                    if (!structured)
                    {
                        throw new SimSyntaxException(9);
                    }
                }

                return;
            case "CLEAR":
                Clear(port);
                return;
            case "DEFINE" or "DEF":
                Define(port, p);
                return;
            case "DELETE" or "DEL":
                Delete(port, p);
                return;
            case "LIST":
                List(port, p, outputs);
                return;
            case "VERSION" or "VER":
                outputs.Add(Options.Version);
                return;
            case "TYPE":
                outputs.Add(Options.TypeText);
                return;
            case "CID":
                outputs.Add(Options.CardId.ToString(CultureInfo.InvariantCulture));
                return;
            case "DATE":
                outputs.Add("05/18/2010");
                return;
            case "SAVE":
                return;
            case "ENABLE" or "ENA" or "DISABLE" or "DIS":
                EnablePlc(p, t.Text.StartsWith("EN", StringComparison.Ordinal));
                return;
        }

        // A program statement sent with no buffer open on this port.
        p.Pos--;
        if (ProgramParser.TryParse(p) is not null)
        {
            throw new SimSyntaxException(5);
        }

        throw new SimSyntaxException(3);
    }

    private static void Check(int error)
    {
        if (error != 0)
        {
            throw new SimSyntaxException(error);
        }
    }

    private static int IntArgument(ExprParser p, int min, int max)
    {
        var t = p.Next();
        if (t.Kind != TokenKind.Number || t.Value < min || t.Value > max)
        {
            throw new SimSyntaxException(3);
        }

        return (int)t.Value;
    }

    private void Motion(CoordinateSystem cs, char command)
    {
        switch (command)
        {
            case 'R':
                Check(cs.Run(step: false));
                break;
            case 'S':
                Check(cs.Run(step: true));
                break;
            case 'H':
                cs.Hold();
                break;
            case 'Q':
                cs.Quit();
                break;
            default:
                cs.Abort();
                break;
        }
    }

    private void Variable(SimPort port, char kind, ExprParser p, List<string> outputs)
    {
        var first = ExprParser.VariableIndex(p.Next());
        var last = first;
        if (p.Accept(".."))
        {
            last = ExprParser.VariableIndex(p.Next());
            if (last < first)
            {
                throw new SimSyntaxException(3);
            }
        }

        var csNumber = port.CoordinateSystem;
        if (p.Accept("="))
        {
            var value = p.ParseExpression().Eval(_cs[csNumber]);
            for (var i = first; i <= last; i++)
            {
                Write(port, kind, i, value);
            }

            return;
        }

        if (kind == 'M' && p.Accept("->"))
        {
            if (first != last)
            {
                throw new SimSyntaxException(3);
            }

            if (p.Peek.Kind == TokenKind.End || p.Peek.IsLetter && p.Peek.Text[0] is 'I' or 'P' or 'Q' or 'M' && p.PeekAt(1).Kind == TokenKind.Number && !p.PeekAt(2).Is(":"))
            {
                outputs.Add(Memory.GetDefinition(first).ToString());
                return;
            }

            Memory.Define(first, ParseDefinition(p));
            return;
        }

        if (p.Peek.Is("==") || p.Peek.Is("->"))
        {
            throw new SimSyntaxException(3);
        }

        for (var i = first; i <= last; i++)
        {
            var v = kind switch
            {
                'Q' => Memory.GetQ(csNumber, i),
                'I' when i is 3 => port.I3,
                'I' when i is 6 => port.I6,
                _ => GetVariable(kind, i),
            };
            outputs.Add(Format(v));
        }
    }

    private void Write(SimPort port, char kind, int index, double value)
    {
        switch (kind)
        {
            case 'Q':
                Memory.SetQ(port.CoordinateSystem, index, value);
                return;
            case 'I' when index == 3:
                port.I3 = Math.Clamp((int)value, 0, 3);
                break;
            case 'I' when index == 6:
                port.I6 = Math.Clamp((int)value, 0, 3);
                break;
        }

        SetVariable(kind, index, value);
    }

    private static MDefinition ParseDefinition(ExprParser p)
    {
        if (p.Accept("*"))
        {
            return MDefinition.Self;
        }

        var spaceToken = p.Next();
        if (spaceToken.Kind != TokenKind.Word || spaceToken.Text is not ("X" or "Y" or "D" or "L" or "F" or "DP"))
        {
            throw new SimSyntaxException(3);
        }

        var space = spaceToken.Text[0];
        p.Expect(":");
        var address = p.Next();
        if (address.Kind != TokenKind.Number || address.Value < 0 || address.Value > 0xFFFFFF)
        {
            throw new SimSyntaxException(3);
        }

        if (space is not ('X' or 'Y'))
        {
            return new MDefinition(space, (int)address.Value, 0, 48, true);
        }

        var bit = 0;
        var width = 1;
        var signed = false;
        if (p.Accept(","))
        {
            bit = IntArgument(p, 0, 23);
            if (p.Accept(","))
            {
                width = IntArgument(p, 1, 24);
                if (p.Accept(","))
                {
                    var f = p.Next();
                    signed = f.Kind == TokenKind.Word && f.Text == "S" ? true
                        : f.Kind == TokenKind.Word && f.Text == "U" ? false
                        : throw new SimSyntaxException(3);
                }
            }
        }
        else
        {
            width = 24; // "M1->X:$1234" alone is the whole word
            signed = true;
        }

        if (bit + width > 24)
        {
            throw new SimSyntaxException(3);
        }

        return new MDefinition(space, (int)address.Value, bit, width, signed);
    }

    private void MotorDefinition(int motor, ExprParser p, List<string> outputs)
    {
        if (p.Peek.Kind == TokenKind.End)
        {
            var (_, axis, scale) = _motors[motor];
            outputs.Add(axis < 0 ? "0" : Format(scale) + "XYZABCUVW"[axis]);
            return;
        }

        var scaleValue = 1.0;
        if (p.Peek.Kind == TokenKind.Number || p.Peek.Is("-"))
        {
            scaleValue = p.ParseValue().Eval(_cs[1]);
        }

        var letter = p.Next();
        var index = letter.IsLetter ? "XYZABCUVW".IndexOf(letter.Text[0]) : -1;
        if (index < 0)
        {
            throw new SimSyntaxException(3);
        }

        _motors[motor] = (1, index, scaleValue);
    }

    private double MotorPosition(int motor)
    {
        var (csNumber, axis, scale) = _motors[motor];
        if (axis < 0)
        {
            return 0;
        }

        _cs[csNumber].ActualPosition(_scratch);
        return Math.Round(_scratch[axis] * scale, 6);
    }

    private string MotorStatus(int motor)
    {
        var (csNumber, axis, _) = _motors[motor];
        var moving = axis >= 0 && _cs[csNumber].IsMoving;
        var w1 = 0x800000 | (moving ? 0 : 0x002000);
        var w2 = ((csNumber - 1) << 20) | (axis >= 0 ? 0x008000 | ((Math.Min(axis, 8) + 1) << 16) : 0) | 0x004000 | 0x000400 | (moving ? 0 : 1);
        return string.Create(CultureInfo.InvariantCulture, $"{w1:X6}{w2:X6}");
    }

    private static string CsStatus(CoordinateSystem cs)
    {
        var w1 = 0xA80000; // X, Y, Z used in feedrate calculations
        if (cs.Running)
        {
            w1 |= 0x000001;
        }

        if (cs.Stepping)
        {
            w1 |= 0x000002;
        }

        if (cs.Running && !cs.Stepping && !cs.Quitting)
        {
            w1 |= 0x000010;
        }

        if (cs.TimeMode)
        {
            w1 |= 0x000008;
        }

        var w2 = cs.Mode switch
        {
            MotionMode.Rapid => 0x000002,
            MotionMode.Circle1 => 0x000001,
            MotionMode.Circle2 => 0x000003,
            _ => 0,
        };
        if (cs.RotaryFullBit)
        {
            w2 |= 1 << 16;
        }

        if (!cs.IsMoving)
        {
            w2 |= 1 << 17;
        }

        if (cs.QueuedSegments > 0)
        {
            w2 |= 1 << 21;
        }

        return string.Create(CultureInfo.InvariantCulture, $"{w1:X6}{w2:X6}{0:X6}");
    }

    private void Open(SimPort port, ExprParser p)
    {
        var what = p.Next();
        if (_openOwner is not null && _openOwner != port)
        {
            throw new SimSyntaxException(7);
        }

        if (_openOwner == port)
        {
            CloseBuffer();
        }

        switch (what.Text)
        {
            case "ROT" or "ROTARY" when what.Kind == TokenKind.Word:
                _openKind = BufferKind.Rotary;
                _openBuffer = null;
                foreach (var c in _cs.Skip(1))
                {
                    if (c.Rotary is not null)
                    {
                        c.Rotary.IsOpen = true;
                    }
                }

                break;
            case "PROG" or "PROGRAM" when what.Kind == TokenKind.Word:
                {
                    var n = IntArgument(p, 1, 65535);
                    if (_programs.TryGetValue(n, out var existing) && _cs.Skip(1).Any(c => c.IsExecuting(existing)))
                    {
                        throw new SimSyntaxException(1);
                    }

                    if (existing is null)
                    {
                        existing = new ProgramBuffer(BufferKind.Prog, n, 0);
                        _programs[n] = existing;
                    }

                    _openKind = BufferKind.Prog;
                    _openBuffer = existing;
                    break;
                }

            case "PLC" when what.Kind == TokenKind.Word:
                {
                    var n = IntArgument(p, 0, 31);
                    var plc = _plcs[n];
                    if (plc is null)
                    {
                        plc = new PlcProgram(new ProgramBuffer(BufferKind.Plc, n, 0));
                        _plcs[n] = plc;
                    }

                    plc.Enabled = false; // opening a PLC buffer stops it until ENABLE PLC
                    _openKind = BufferKind.Plc;
                    _openBuffer = plc.Buffer;
                    break;
                }

            default:
                throw new SimSyntaxException(3);
        }

        _openOwner = port;
        _openBuffer?.IsOpen = true;
    }

    private void CloseBuffer()
    {
        if (_openOwner is null)
        {
            return;
        }

        if (_openKind == BufferKind.Rotary)
        {
            foreach (var c in _cs.Skip(1))
            {
                if (c.Rotary is not null)
                {
                    c.Rotary.IsOpen = false;
                }
            }
        }
        else if (_openBuffer is not null)
        {
            _openBuffer.IsOpen = false;
            if (_openKind == BufferKind.Plc)
            {
                _plcs[_openBuffer.Number]?.Restart();
            }
        }

        _openOwner = null;
        _openBuffer = null;
    }

    private void Clear(SimPort port)
    {
        if (_openOwner != port)
        {
            throw new SimSyntaxException(5);
        }

        if (_openKind == BufferKind.Rotary)
        {
            var cs = _cs[port.CoordinateSystem];
            if (cs.Rotary is { } r)
            {
                r.Clear();
                cs.RotaryCleared();
                cs.UpdateFullBit();
            }

            return;
        }

        _openBuffer!.Clear();
    }

    private void Define(SimPort port, ExprParser p)
    {
        var what = p.Next();
        switch (what.Text)
        {
            case "ROT" or "ROTARY":
                {
                    var size = IntArgument(p, 1, 8_388_607);
                    var cs = _cs[port.CoordinateSystem];
                    if (cs.Running && cs.ProgramNumber == 0)
                    {
                        throw new SimSyntaxException(1);
                    }

                    if (_openOwner is not null && _openKind == BufferKind.Rotary)
                    {
                        throw new SimSyntaxException(7);
                    }

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
            default:
                throw new SimSyntaxException(3);
        }
    }

    private void Delete(SimPort port, ExprParser p)
    {
        var what = p.Next();
        switch (what.Text)
        {
            case "ROT" or "ROTARY":
                {
                    var cs = _cs[port.CoordinateSystem];
                    if (cs.Running && cs.ProgramNumber == 0)
                    {
                        throw new SimSyntaxException(1);
                    }

                    if (_openOwner is not null && _openKind == BufferKind.Rotary)
                    {
                        throw new SimSyntaxException(7);
                    }

                    cs.DropRotary();
                    return;
                }

            case "GAT" or "GATHER":
                return;
            default:
                throw new SimSyntaxException(3);
        }
    }

    private void List(SimPort port, ExprParser p, List<string> outputs)
    {
        var what = p.Next();
        ProgramBuffer? buffer = what.Text switch
        {
            "PROG" or "PROGRAM" => _programs.GetValueOrDefault(IntArgument(p, 1, 65535)),
            "PLC" => _plcs[IntArgument(p, 0, 31)]?.Buffer,
            "ROT" or "ROTARY" => _cs[port.CoordinateSystem].Rotary,
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

    private void EnablePlc(ExprParser p, bool enable)
    {
        var what = p.Next();
        if (what.Text != "PLC")
        {
            throw new SimSyntaxException(3);
        }

        var first = IntArgument(p, 0, 31);
        var numbers = new List<int> { first };
        while (true)
        {
            if (p.Accept(","))
            {
                numbers.Add(IntArgument(p, 0, 31));
            }
            else if (p.Accept(".."))
            {
                var last = IntArgument(p, 0, 31);
                for (var n = numbers[^1] + 1; n <= last; n++)
                {
                    numbers.Add(n);
                }
            }
            else
            {
                break;
            }
        }

        foreach (var n in numbers)
        {
            if (_plcs[n] is { } plc)
            {
                if (enable && !plc.Enabled)
                {
                    plc.Restart();
                }

                plc.Enabled = enable && !(plc.Buffer.IsOpen);
            }
        }
    }

    private void Reset(bool factory)
    {
        PowerOn(factory);
        Serilog.Log.ForContext<PmacSimulator>().Information("simulated PMAC reset ({Kind})", factory ? "factory" : "$$$");
    }

    internal static string Format(double v)
    {
        if (v == 0)
        {
            return "0";
        }

        return v.ToString("0.##########", CultureInfo.InvariantCulture);
    }
}
