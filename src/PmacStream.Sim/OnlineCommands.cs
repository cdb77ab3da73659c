using System.Globalization;
using System.Text;
using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

/// <summary>
/// The controller's command interpreter: one command line from a port, split into commands (words may run together,
/// several commands a line). While the port has a buffer open, program statements are stored in it; everything else
/// runs online: variables and M-variable definitions, <c>&amp;n</c>/<c>#n</c> addressing, motion commands
/// (<c>R S H Q A K B</c>), the feed override, status queries, buffer commands, PLC enabling, resets. Refusals throw
/// <see cref="SimSyntaxException"/> with the ERR number. Guarded by the simulator's lock.
/// </summary>
/// <param name="sim">The simulator: variables, options, resets.</param>
/// <param name="coordinateSystems">The coordinate systems (index 0 unused).</param>
/// <param name="buffers">The program buffers and the one open.</param>
/// <param name="plcs">The PLC programs.</param>
/// <param name="motors">The motor definitions.</param>
/// <param name="motorSet">The motors: jog, home, kill, reports.</param>
internal sealed class OnlineCommands(PmacSimulator sim, CoordinateSystem[] coordinateSystems, ProgramBuffers buffers, PlcTable plcs, MotorMap motors, MotorSet motorSet)
{
    // Per-line scratch, reused so that storing a line allocates only what is kept.
    private readonly List<Token> _tokens = new(32);
    private readonly List<Stmt> _stmts = new(8);
    private readonly ExprParser _parser = new([]);
    private bool _lineBusy;

    private SimMemory Memory => sim.Memory;

    /// <summary>Runs one command line from <paramref name="port"/>; values to send back go to <paramref name="outputs"/>.</summary>
    public void Execute(SimPort port, string line, List<string> outputs)
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
                if (buffers.IsOpenOn(port))
                {
                    var start = p.Pos;
                    ProgramParser.ParseRun(p, stmts);
                    if (stmts.Count > 0)
                    {
                        var text = StoredText(upper, tokens[start].Start, tokens[p.Pos - 1].End);
                        buffers.Store(port, new ProgramLine(text, [.. stmts]));
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

    /// <summary>The answer to a control character (Ctrl-B/C/F/G/P/V/X, or the letter), without a terminator; null for one not known.</summary>
    public string? Control(char control)
    {
        var c = control < 32 ? (char)(control + 64) : char.ToUpperInvariant(control);
        return c switch
        {
            'X' => string.Empty,
            'B' => string.Join(" ", Enumerable.Range(1, 8).Select(MotorStatusOf)) + "\r",
            'C' => string.Join(" ", Enumerable.Range(1, 8).Select(n => StatusOf(coordinateSystems[n]))) + "\r",
            'G' => "000000000000\r",
            'P' => string.Join(" ", Enumerable.Range(1, 8).Select(n => ReplyFrame.Number(PositionOf(n)))) + "\r",
            'V' => string.Join(" ", Enumerable.Range(1, 8).Select(n => ReplyFrame.Number(VelocityOf(n)))) + "\r",
            'F' => string.Join(" ", Enumerable.Range(1, 8).Select(n => ReplyFrame.Number(FollowingErrorOf(n)))) + "\r",
            _ => null,
        };
    }

    /// <summary>
    /// The coordinate system status (<c>??</c>, Ctrl-C): first word bit 0 running, bit 1 single step, bit 3 time mode,
    /// bit 4 continuous motion request; second word the move mode, bit 16 rotary buffer full, bit 17 in position (no
    /// motion and every motor in position), bits 18/19/20 warning following error, fatal following error, amplifier
    /// fault of a motor of it, bit 21 moves queued; a third word of zeros.
    /// </summary>
    private string StatusOf(CoordinateSystem cs)
    {
        var (motorBits, motorsInPosition) = MotorStatus.CoordinateSystem(motorSet, cs.Number);
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

        if (!cs.IsMoving && motorsInPosition)
        {
            w2 |= 1 << 17;
        }

        w2 |= motorBits;

        if (cs.QueuedSegments > 0)
        {
            w2 |= 1 << 21;
        }

        return string.Create(CultureInfo.InvariantCulture, $"{w1:X6}{w2:X6}{0:X6}");
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

    private void ExecuteOnline(SimPort port, ExprParser p, List<string> outputs)
    {
        var t = p.Next();
        var cs = coordinateSystems[port.CoordinateSystem];
        if (t.Kind == TokenKind.Symbol)
        {
            Symbol(port, cs, t.Text, p, outputs);
            return;
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
            case "R" or "S" when !p.AtValue:
                Check(motorSet.BeforeRun(cs));
                Motion(cs, t.Text[0]);
                if (cs.Running)
                {
                    motorSet.ProgramStarted();
                }

                return;
            case "H" or "Q" when !p.AtValue:
                Motion(cs, t.Text[0]);
                return;
            case "A" when !p.AtValue:
                Motion(cs, 'A');
                motorSet.Abort(cs.Number);
                return;
            case "K" when !p.AtValue:
                Check(motorSet.Kill(port.Motor));
                return;
            case "J":
                Jog(port, cs, p);
                return;
            case "PMATCH":
                motorSet.Match(cs);
                return;
            case "HM" or "HOME":
                Check(motorSet.Home(port.Motor));
                return;
            case "HMZ" or "HOMEZ":
                Check(motorSet.HomeHere(port.Motor));
                return;
            case "V" when ReportEnds(p):
                outputs.Add(ReplyFrame.Number(VelocityOf(port.Motor)));
                return;
            case "F" when ReportEnds(p):
                outputs.Add(ReplyFrame.Number(FollowingErrorOf(port.Motor)));
                return;
            case "B":
                Check(cs.Begin(p.IntArgument(0, 65535)));
                return;
            case "P" when !p.AtValue:
                outputs.Add(ReplyFrame.Number(PositionOf(port.Motor)));
                return;
            case "PR":
                outputs.Add(cs.RotaryLinesAhead().ToString(CultureInfo.InvariantCulture));
                return;
            case "SIZE":
                outputs.Add(buffers.UnusedWords().ToString(CultureInfo.InvariantCulture));
                return;
            case "OPEN":
                buffers.Open(port, p);
                return;
            case "CLOSE":
                buffers.Close(port);
                return;
            case "CLEAR":
                buffers.Clear(port);
                return;
            case "DEFINE" or "DEF":
                buffers.Define(port, p);
                return;
            case "DELETE" or "DEL":
                buffers.Delete(port, p);
                return;
            case "LIST":
                buffers.List(port, p, outputs);
                return;
            case "VERSION" or "VER":
                outputs.Add(sim.Options.Version);
                return;
            case "TYPE":
                outputs.Add(sim.Options.TypeText);
                return;
            case "CID":
                outputs.Add(sim.Options.CardId.ToString(CultureInfo.InvariantCulture));
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

    /// <summary><c>&amp;n</c>, <c>#n</c> (and <c>#n-&gt;</c>), <c>%</c>, <c>?</c> status queries, <c>$$$</c> resets.</summary>
    private void Symbol(SimPort port, CoordinateSystem cs, string symbol, ExprParser p, List<string> outputs)
    {
        switch (symbol)
        {
            case "&":
                port.CoordinateSystem = p.IntArgument(1, SimMemory.CoordinateSystems);
                return;
            case "#":
                port.Motor = p.IntArgument(1, MotorMap.Count);
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
                    outputs.Add(ReplyFrame.Number(Math.Round(cs.OverrideCurrent, 3)));
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
                        1 => MotorStatusOf(port.Motor),
                        2 => StatusOf(cs),
                        3 => "000000000000",
                        _ => throw new SimSyntaxException(3),
                    });
                    return;
                }

            case "$":
                motorSet.Reset(port.Motor);
                return;
            case "$$$":
                sim.Reset(factory: false);
                return;
            case "$$$***":
                sim.Reset(factory: true);
                return;
            default:
                throw new SimSyntaxException(3);
        }
    }

    /// <summary>A one-letter report (<c>V</c>, <c>F</c>) ends the command: the line ends or the next motor is addressed (<c>#1F#2F</c>).</summary>
    private static bool ReportEnds(ExprParser p) => p.Peek.Kind == TokenKind.End || p.Peek.Is("#") || p.Peek.Is("&");

    private string MotorStatusOf(int motor) => MotorStatus.Motor(motorSet, motors, coordinateSystems, motor);

    /// <summary><c>P</c>: counts, to 1/32 count as a Turbo PMAC rounds it, shown to 6 decimals at most.</summary>
    private double PositionOf(int motor) => Math.Round(motorSet.ActualPosition(motor), 6);

    /// <summary><c>V</c>: counts per servo cycle, to a tenth (the manual's Ctrl-V rounding).</summary>
    private double VelocityOf(int motor) => Math.Round(motorSet.ReportedVelocity(motor), 1);

    private double FollowingErrorOf(int motor) => Math.Round(motorSet.FollowingError(motor), 6);

    /// <summary><c>J+ J- J/ J= J={pos} J:{dist} J^{dist}</c> to the addressed motor.</summary>
    private void Jog(SimPort port, CoordinateSystem cs, ExprParser p)
    {
        var t = p.Next();
        if (t.Kind != TokenKind.Symbol || t.Text.Length != 1 || "+-/=:^".IndexOf(t.Text[0], StringComparison.Ordinal) < 0)
        {
            throw new SimSyntaxException(3);
        }

        var kind = t.Text[0];
        double? value = null;
        if (kind is '=' or ':' or '^' && p.AtValue)
        {
            value = p.ParseValue().Eval(cs);
        }
        else if (kind is ':' or '^')
        {
            throw new SimSyntaxException(3);
        }

        Check(motorSet.Jog(port.Motor, kind, value));
    }

    private static void Check(int error)
    {
        if (error != 0)
        {
            throw new SimSyntaxException(error);
        }
    }

    private static void Motion(CoordinateSystem cs, char command)
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
            var value = p.ParseExpression().Eval(coordinateSystems[csNumber]);
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
                _ => sim.GetVariable(kind, i),
            };
            outputs.Add(ReplyFrame.Number(v));
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

        sim.SetVariable(kind, index, value);
    }

    /// <summary>An M-variable definition: <c>*</c>, <c>X:$addr[,bit[,width[,U|S]]]</c>, <c>Y:...</c>, <c>D:/L:/F:/DP:$addr</c>.</summary>
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
            bit = p.IntArgument(0, 23);
            if (p.Accept(","))
            {
                width = p.IntArgument(1, 24);
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

    /// <summary><c>#n-&gt;</c> (query) or <c>#n-&gt;[scale]axis</c>.</summary>
    private void MotorDefinition(int motor, ExprParser p, List<string> outputs)
    {
        if (p.Peek.Kind == TokenKind.End)
        {
            outputs.Add(motors.Describe(motor));
            return;
        }

        var scale = 1.0;
        if (p.Peek.Kind == TokenKind.Number || p.Peek.Is("-"))
        {
            scale = p.ParseValue().Eval(coordinateSystems[1]);
        }

        var letter = p.Next();
        if (!letter.IsLetter || !motors.Define(motor, letter.Text[0], scale))
        {
            throw new SimSyntaxException(3);
        }
    }

    /// <summary><c>ENABLE PLC n[,m][..k]</c> / <c>DISABLE PLC ...</c>.</summary>
    private void EnablePlc(ExprParser p, bool enable)
    {
        if (p.Next().Text != "PLC")
        {
            throw new SimSyntaxException(3);
        }

        var numbers = new List<int> { p.IntArgument(0, PlcTable.Count - 1) };
        while (true)
        {
            if (p.Accept(","))
            {
                numbers.Add(p.IntArgument(0, PlcTable.Count - 1));
            }
            else if (p.Accept(".."))
            {
                var last = p.IntArgument(0, PlcTable.Count - 1);
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

        plcs.Enable(numbers, enable);
    }
}
