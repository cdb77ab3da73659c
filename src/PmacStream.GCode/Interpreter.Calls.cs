namespace PmacStream.GCode;

/// <content>
/// The line's settings and codes as canonical calls (<see cref="ICanonicalMoves.SelectTool"/> ...
/// <see cref="ICanonicalMoves.Code"/>), so a consumer takes what the interpreter decided and never reads the line's
/// words itself.
/// </content>
public sealed partial class Interpreter
{
    private CanonAxes _given;         // the line's axis and arc words in millimetres (CanonBlock.Given)
    private int _motionInBlock = -1;  // G00..G03 written in the line (CanonBlock.MotionInBlock)
    private bool _machineBlock;       // G53 in the line
    private bool _axisDataBlock;      // a code of the line took its axis words as data

    /// <summary>Before a line, while a consumer listens: nothing of the line before it is left in the record.</summary>
    private void ClearCalls() => (_given, _motionInBlock, _machineBlock, _axisDataBlock) = (default, -1, false, false);

    /// <summary>
    /// The line's settings and codes to <paramref name="canon"/> in the order written, once the line's state is
    /// decided (a G92 shift, a G10 entry, the tool): only the words the interpreter took (the first of a letter, the
    /// first code of a group), and codes the profile does not know, which a forced split passes on as written.
    /// </summary>
    private void EmitCalls(ICanonicalMoves canon, ReadOnlySpan<GWord> words, Span<int> col, Span<double> val, Span<int> gCol, Span<int> mCol, bool anyG, bool anyM)
    {
        Span<CanonWord> read = stackalloc CanonWord[26];
        var lengthCode = false;
        foreach (ref readonly var w in words)
        {
            switch (w.Letter)
            {
                case 'G' when anyG && _gInfo.TryGetValue(w.CodeTimesTen, out var g) && gCol[g.Group] == w.Column:
                    lengthCode |= w.CodeTimesTen is 430 or 440 or 490;
                    EmitG(canon, g, w.Value, col, val, read);
                    break;
                case 'M' when anyM && _mInfo.TryGetValue(w.CodeTimesTen, out var m) && mCol[m.Group] == w.Column:
                    EmitM(canon, m, w.Value, col, val, read);
                    break;
                case 'G' when !_gInfo.ContainsKey(w.CodeTimesTen):
                case 'M' when !_mInfo.ContainsKey(w.CodeTimesTen):
                    // Not in the profile (refused, E104/E105): a split forced past the refusal passes it on as written.
                    canon.Code(new CanonCode(w.Letter, w.Value, default));
                    break;
                case 'T' when col['T' - 'A'] == w.Column:
                    canon.SelectTool(_tool);
                    break;
                case 'S' when col['S' - 'A'] == w.Column:
                    canon.SetSpindleSpeed(w.Value);
                    break;
                case 'F' when col['F' - 'A'] == w.Column:
                    canon.SetFeedRate(w.Value);
                    break;
            }
        }

        if (lengthCode || (col['H' - 'A'] != 0 && _lengthMode != 0))
        {
            canon.UseToolLengthOffset(_lengthMode, _h);
        }
    }

    private void EmitG(ICanonicalMoves canon, in CodeInfo info, double value, Span<int> col, Span<double> val, Span<CanonWord> read)
    {
        static double? Word(char c, Span<int> col, Span<double> val) => col[c - 'A'] != 0 ? val[c - 'A'] : null;
        var key = MachineProfile.Key(value);
        switch (key)
        {
            case 40:
                // P in the profile's dwell unit, else X in seconds (as written, whatever the length units).
                canon.Dwell(Word('P', col, val) is { } p ? (_profile.DwellPInMilliseconds ? p / 1000.0 : p) : Word('X', col, val) ?? 0);
                break;
            case 100:
                EmitTableEntry(canon, Word('L', col, val), Word('P', col, val));
                break;
            case 520:
                canon.SetLocalShift(Word('X', col, val) * _scale, Word('Y', col, val) * _scale, Word('Z', col, val) * _scale);
                break;
            case 920:
                var shift = _coords.Shift;
                canon.SetShift(col['X' - 'A'] != 0 ? shift.X : null, col['Y' - 'A'] != 0 ? shift.Y : null, col['Z' - 'A'] != 0 ? shift.Z : null);
                break;
            case 921 or 922:
                canon.CancelShift();
                break;
            case 541 or 1540:
                canon.SelectExtendedWorkOffset((int)(Word('P', col, val) ?? 1));
                break;
            // What the record says (the motion code, G53, the length offset), or program syntax the interpreter applied
            // (units, arc centres, cycles and their returns, reference returns, feed modes, transformations, exact
            // stop, cutter compensation: all in the positions and feeds it decided).
            case 0 or 10 or 20 or 30 or 530 or 430 or 440 or 490:
            case 200 or 210 or 901 or 911 or 800 or 980 or 990 or 270 or 280 or 290 or 300 or 930 or 940 or 950:
            case 510 or 511 or 680 or 500 or 501 or 690 or 610 or 90 or 410 or 420:
            case 730 or 740 or 760 or 810 or 820 or 830 or 840 or 850 or 860 or 870 or 880 or 890:
                break;
            default:
                canon.Code(new CanonCode('G', value, LibraryWords(info, key, 'G', col, val, read)));
                break;
        }
    }

    private void EmitM(ICanonicalMoves canon, in CodeInfo info, double value, Span<int> col, Span<double> val, Span<CanonWord> read)
    {
        var key = MachineProfile.Key(value);
        var code = new CanonCode('M', value, LibraryWords(info, key, 'M', col, val, read));
        switch (key)
        {
            case 0: canon.ProgramStop(ProgramStopCall.Stop, code); break;
            case 10: canon.ProgramStop(ProgramStopCall.OptionalStop, code); break;
            case 20 or 300: canon.ProgramStop(ProgramStopCall.End, code); break;
            case 30: canon.Spindle(SpindleCall.Clockwise, code); break;
            case 40: canon.Spindle(SpindleCall.CounterClockwise, code); break;
            case 50: canon.Spindle(SpindleCall.Stop, code); break;
            case 190: canon.Spindle(SpindleCall.Orient, code); break;
            case 60: canon.ChangeTool(_tool, code); break;
            case 70: canon.Coolant(CoolantCall.Mist, code); break;
            case 80: canon.Coolant(CoolantCall.Flood, code); break;
            case 880: canon.Coolant(CoolantCall.ThroughTool, code); break;
            case 90: canon.Coolant(CoolantCall.Off, code); break;
            case 890: canon.Coolant(CoolantCall.ThroughToolOff, code); break;
            default: canon.Code(code); break;
        }
    }

    /// <summary>
    /// The words a library routine reads (the profile's <c>words</c> of the code) that the line gave, in the profile's
    /// order: <c>READ</c> takes the letters right after the call. Lengths among them in millimetres.
    /// </summary>
    private ReadOnlySpan<CanonWord> LibraryWords(in CodeInfo info, int key, char letter, Span<int> col, Span<double> val, Span<CanonWord> read)
    {
        if (info.Def is not { Controller: ControllerSupport.Library, Words.Length: > 0 } def)
        {
            return default;
        }

        var n = 0;
        foreach (var c in def.Words)
        {
            if (col[c - 'A'] != 0)
            {
                var v = val[c - 'A'];
                read[n++] = new CanonWord(c, letter == 'G' && CodeRoles.WordIsLength(key, c) ? v * _scale : v);
            }
        }

        return read[..n];
    }

    /// <summary>G10: the table entry its L and P name, as the line left it.</summary>
    private void EmitTableEntry(ICanonicalMoves canon, double? l, double? p)
    {
        switch (l)
        {
            case 2 when p is 0 && _profile.ExternalWorkOffset:
                // FANUC's external work offset: added to every offset.
                canon.SetExternalOffset(_coords.External);
                break;
            case 2 or 20:
                var extended = l == 20 && _profile.ExtendedWorkOffsets;
                var n = (int)(p ?? 0);
                var key = extended ? 5410 + n : n == 0 ? _coords.Selected : n <= 6 ? 530 + (n * 10) : 590 + (n - 6);
                canon.SetWorkOffset(key, _coords.OffsetOf(key));
                break;
            case 1 or 10 or 11 when p is { } t:
                canon.SetToolLength((int)t, _coords.LengthOf((int)t));
                break;
        }
    }
}
