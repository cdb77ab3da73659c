using System.Globalization;

namespace PmacStream.GCode.Expansion;

/// <content>
/// Variables: locals of the call in force, commons and globals, named parameters, and the system variables. The host
/// interprets the whole program, so it answers what it knows (positions at block end, modal state, the machine's work
/// offsets and tool table); what only the machine knows when it runs (probe results, inputs, clocks) is refused.
/// </content>
public sealed partial class MacroExpander
{
    /// <inheritdoc/>
    double IMacroVariables.Read(int n, MacroExpr at) => _dialect == MacroDialect.Fanuc ? ReadFanuc(n, at) : ReadNgc(n, at);

    /// <inheritdoc/>
    double IMacroVariables.ReadNamed(string name, MacroExpr at)
    {
        if (name.StartsWith('_'))
        {
            if (_globalNames.TryGetValue(name, out var g))
            {
                return g;
            }

            switch (name)
            {
                case "_x": return WorkPosition(0, at);
                case "_y": return WorkPosition(1, at);
                case "_z": return WorkPosition(2, at);
                case "_metric": return Shadow(at).UnitScale == 1 ? 1 : 0;
                case "_imperial": return Shadow(at).UnitScale == 1 ? 0 : 1;
                case "_absolute": return Shadow(at).AbsoluteMode ? 1 : 0;
                case "_incremental": return Shadow(at).AbsoluteMode ? 0 : 1;
                case "_feed": return Shadow(at).FeedValue ?? 0;
                case "_current_tool": return Shadow(at).Tool;
                case "_value": return 0;
                case "_value_returned": return 0;
            }
        }
        else if (_frame.Named != null && _frame.Named.TryGetValue(name, out var v))
        {
            return v;
        }

        throw new MacroEvalException(at.Column, $"#<{name}> is not defined");
    }

    /// <summary>True when a named parameter has a value (RS274/NGC <c>EXISTS</c>).</summary>
    internal bool NamedExists(string name) =>
        name.StartsWith('_') ? _globalNames.ContainsKey(name) : _frame.Named?.ContainsKey(name) == true;

    private double ReadFanuc(int n, MacroExpr at)
    {
        switch (n)
        {
            case 0:
                return double.NaN;
            case <= 33:
                return _frame.Locals[n];
            case >= 100 and <= 999:
                return _globals[n];
            case < 100:
                throw new MacroEvalException(at.Column, $"#{n} is not a FANUC variable (locals are #1-#33, commons #100-#999)");
            case >= 1000 and <= 1035 or >= 1100 and <= 1135:
                throw MachineOnly(n, at, "an input or output signal: only the machine knows it when the program runs");
            case >= 2001 and <= 2200 or >= 2401 and <= 2600:
                return 0; // wear: the host keeps none
            case >= 2201 and <= 2400:
                return _profile.ToolLength(n - 2200) / Scale;
            case >= 2601 and <= 2800:
                return (_profile.ToolRadius(n - 2600) ?? 0) / Scale;
            case 3001 or 3002 or 3011 or 3012:
                throw MachineOnly(n, at, "the machine's clock: only the machine knows it when the program runs");
            case 3901 or 3902:
                throw MachineOnly(n, at, "the machine's part count: only the machine knows it when the program runs");
            case 4001: return Shadow(at).MotionCode;
            case 4003: return Shadow(at).AbsoluteMode ? 90 : 91;
            case 4006: return Shadow(at).UnitScale == 1 ? 21 : 20;
            case 4008: return Shadow(at).LengthMode == 0 ? 49 : Shadow(at).LengthMode;
            case 4109: return Shadow(at).FeedValue ?? 0;
            case 4111: return Shadow(at).LengthOffsetNumber;
            case 4120: return Shadow(at).Tool;
            case >= 5001 and <= 5003 or >= 5041 and <= 5043:
                return WorkPosition((n - 1) % 20, at);
            case >= 5021 and <= 5023:
                return Axis(Shadow(at).Position, n - 5021) / Scale;
            case >= 5061 and <= 5066:
                throw MachineOnly(n, at, "the skip position of G31 (a probe result): only the machine knows it when the program runs");
            case >= 5081 and <= 5083:
                return n == 5083 && Shadow(at).LengthMode != 0 ? _profile.ToolLength(Shadow(at).LengthOffsetNumber) / Scale : 0;
            case >= 5101 and <= 5106:
                throw MachineOnly(n, at, "the servo position deviation: only the machine knows it when the program runs");
            case >= 5201 and <= 5203:
                return 0;
            case >= 5221 and <= 5323 when (n - 5221) % 20 < 3:
                return Axis(_profile.WorkOffset(MachineProfile.Key(54 + ((n - 5221) / 20))), (n - 5221) % 20) / Scale;
            default:
                throw MachineOnly(n, at, "a system variable the host does not know");
        }
    }

    private double ReadNgc(int n, MacroExpr at)
    {
        switch (n)
        {
            case 0:
                return 0;
            case <= 30:
                return _frame.Locals[n];
            case >= 5061 and <= 5070:
                throw MachineOnly(n, at, "a probe result of G38: only the machine knows it when the program runs");
            case 5399:
                throw MachineOnly(n, at, "the input M66 waited for: only the machine knows it when the program runs");
            case >= 5161 and <= 5163:
                return Axis(_profile.ReferencePosition(MachineProfile.Key(28)), n - 5161) / Scale;
            case >= 5181 and <= 5183:
                return Axis(_profile.ReferencePosition(MachineProfile.Key(30)), n - 5181) / Scale;
            case >= 5221 and <= 5388 when (n - 5221) % 20 < 3:
            {
                var k = (n - 5221) / 20;
                var code = k < 6 ? MachineProfile.Key(54 + k) : MachineProfile.Key(59 + (0.1 * (k - 5)));
                return Axis(_profile.WorkOffset(code), (n - 5221) % 20) / Scale;
            }

            case 5400:
                return Shadow(at).Tool;
            case >= 5420 and <= 5422:
                return WorkPosition(n - 5420, at);
            case < 10000:
                return _globals[n];
            default:
                throw MachineOnly(n, at, "a parameter the host does not know");
        }
    }

    private double Scale => _shadow?.UnitScale ?? 1;

    private static double Axis(Point3 p, int i) => i switch { 0 => p.X, 1 => p.Y, 2 => p.Z, _ => 0 };

    /// <summary>The position at the end of the last block emitted, in the program's work coordinates and units.</summary>
    private double WorkPosition(int axis, MacroExpr at)
    {
        var s = Shadow(at);
        return (Axis(s.Position, axis) - Axis(s.ActiveOffset, axis)) / s.UnitScale;
    }

    private Interpreter Shadow(MacroExpr at) =>
        _shadow ?? throw new MacroEvalException(at.Column, "a position or modal variable read in a subprogram file: the host follows the machine state only for programs whose own file reads it");

    private ExpansionException MachineOnly(int n, MacroExpr at, string why)
    {
        return Make(ExpansionCodes.MachineOnly, at.Column, $"#{n.ToString(CultureInfo.InvariantCulture)} is {why}; the host expands the program before it runs and cannot read it", _curFrame, _curLine);
    }

    private void Write(MacroExpr target, double value, MacroLine line)
    {
        if (target is NamedExpr named)
        {
            if (named.Name.StartsWith('_'))
            {
                _globalNames[named.Name] = value;
            }
            else
            {
                (_frame.Named ??= [])[named.Name] = value;
            }

            return;
        }

        var n = target is VarExpr v ? v.Number : MacroExpr.ToVariableNumber(((IndirectExpr)target).Index.Num(this), target);
        if (_dialect == MacroDialect.Fanuc)
        {
            switch (n)
            {
                case >= 1 and <= 33:
                    _frame.Locals[n] = value;
                    return;
                case >= 100 and <= 999:
                    _globals[n] = value;
                    return;
                case 3000:
                {
                    var text = line.Comment.Length > 0 ? line.Comment : "(no message)";
                    throw Make(ExpansionCodes.Alarm, target.Column,
                        $"the program raises alarm #3000={value.ToString(CultureInfo.InvariantCulture)}: {text}", _curFrame, _curLine);
                }

                case 3006:
                    // FANUC's stop with a message: a program stop (M00) here, the message with it.
                    _text.Clear();
                    _text.Append("M00");
                    if (line.Comment.Length > 0)
                    {
                        _text.Append(" (").Append(line.Comment.Replace('(', '[').Replace(')', ']')).Append(')');
                    }

                    EmitText(_curFrame, _curLine);
                    return;
            }
        }
        else
        {
            switch (n)
            {
                case >= 1 and <= 30:
                    _frame.Locals[n] = value;
                    return;
                case >= 31 and < 5000:
                    _globals[n] = value;
                    return;
            }
        }

        throw MachineOnly(n, target, "a system variable the host does not set");
    }
}

/// <summary>
/// The persistent common variables of one machine (FANUC <c>#500</c>-<c>#999</c>) kept on the host between programs:
/// a text file of <c>number value</c> lines, replaced whole when saved.
/// </summary>
public static class PersistentVariables
{
    /// <summary>The values kept (none when the file does not exist).</summary>
    public static IEnumerable<(int Number, double Value)> Load(string file)
    {
        if (!File.Exists(file))
        {
            yield break;
        }

        foreach (var line in File.ReadLines(file))
        {
            var parts = line.Split(' ', StringSplitOptions.RemoveEmptyEntries);
            if (parts.Length == 2 && int.TryParse(parts[0], CultureInfo.InvariantCulture, out var n) && n is >= 500 and <= 999 &&
                double.TryParse(parts[1], CultureInfo.InvariantCulture, out var v))
            {
                yield return (n, v);
            }
        }
    }

    /// <summary>Writes #500-#999 of <paramref name="globals"/> that hold a value.</summary>
    public static void Save(string file, IReadOnlyList<double> globals)
    {
        var temp = file + ".tmp";
        using (var w = new StreamWriter(temp))
        {
            for (var n = 500; n <= 999; n++)
            {
                if (!double.IsNaN(globals[n]))
                {
                    w.Write(FormattableString.Invariant($"{n} {globals[n]:R}\n"));
                }
            }
        }

        File.Move(temp, file, overwrite: true);
    }
}
