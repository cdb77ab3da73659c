namespace PmacStream.GCode;

/// <summary>
/// Dialect hazards (issue 27 item 5): codes that mean different things in FANUC/Haas, LinuxCNC and grbl, used the way
/// another dialect means them. The block runs with the profile's meaning; the check warns and names both, so a program
/// posted for another controller is not run with a meaning its author did not intend.
/// </summary>
public sealed partial class Interpreter
{
    // The first G10 L20 P under an extended-offset profile while the program has selected no extended offset (line 0:
    // none yet; -1: the program selects extended offsets, so it means them).
    private int _extendedSetLine;
    private int _extendedSetP;
    private Point3 _extendedSetValues;

    // A T word since the last M06 (or since the start): M06 then changes to it.
    private bool _toolSelected;

    /// <summary>
    /// The hazards of one block, after it ran: only called while checking, and only for blocks with a G, M or T word
    /// or while a G10 L20 waits for its selection, so a plain move costs one test.
    /// </summary>
    private void CheckDialect(in BlockCodes codes, bool toolChange, MotionKind kind, Point3 start, double? x, double? y, double? z,
        Span<int> col, Span<double> val, ReadOnlySpan<GWord> words, List<Diagnostic> diags, int line)
    {
        var first = words[0].Column;
        if (_coords.Selected >= 5410)
        {
            // The program selects extended offsets: its G10 L20 means them.
            _extendedSetLine = -1;
        }

        if (codes.Data == 100 && col['L' - 'A'] != 0 && col['P' - 'A'] != 0)
        {
            var l = val['L' - 'A'];
            var p = val['P' - 'A'];
            if (l == 20 && _profile.ExtendedWorkOffsets && p is >= 1 and <= 9 && p == Math.Floor(p) && _extendedSetLine == 0)
            {
                // FANUC: extended offset G54.1 Pn. grbl/LinuxCNC: G54..G59 (G59.x) so that here reads as the values.
                (_extendedSetLine, _extendedSetP, _extendedSetValues) = (line, (int)p, InProgramUnits(new Point3(x ?? 0, y ?? 0, z ?? 0)));
            }
            else if (l == 2 && p == 0)
            {
                Add(diags, DiagnosticCodes.DialectG10L2P0, line, col['P' - 'A'], _profile.Name, _profile.ExternalWorkOffset ? "FANUC" : "LinuxCNC/grbl",
                    OffsetName(_coords.Selected));
            }
        }

        if (_extendedSetLine > 0)
        {
            if (kind is not (MotionKind.None or MotionKind.Dwell))
            {
                var v = _extendedSetValues;
                Add(diags, DiagnosticCodes.DialectG10L20, line, first, _extendedSetP, _extendedSetLine, _profile.Name,
                    $"X{ModalState.Num(Math.Round(v.X, 4))} Y{ModalState.Num(Math.Round(v.Y, 4))} Z{ModalState.Num(Math.Round(v.Z, 4))}");
                _extendedSetLine = 0;
            }
        }

        if (codes.Dwell && col['P' - 'A'] != 0)
        {
            var p = val['P' - 'A'];
            var ms = _profile.DwellPInMilliseconds;
            // FANUC's P takes no decimal point (whole milliseconds); a dwell of 100 s or more is a millisecond count.
            if (ms ? p != Math.Floor(p) : p >= 100 && p == Math.Floor(p))
            {
                Add(diags, DiagnosticCodes.DialectDwellUnits, line, col['P' - 'A'], ModalState.Num(p), ModalState.Num(p / 1000), _profile.Name, ms ? "FANUC" : "LinuxCNC/grbl");
            }
        }

        if (codes.Reference is 280 or 300)
        {
            var name = codes.Reference == 280 ? "G28" : "G30";
            if (x is null && y is null && z is null)
            {
                Add(diags, DiagnosticCodes.DialectReturn, line, first, name, _profile.Name);
            }
            else if (_absolute && start.DistanceTo(Target(start, x, y, z)) > 1e-6)
            {
                var via = InProgramUnits(Target(start, x, y, z) - _coords.Active);
                diags.Add(new Diagnostic(Severity.Warning, DiagnosticCodes.DialectReturn, line, first, DiagnosticText.Format(DiagnosticText.ReturnThroughWorkKey, name,
                    (x.HasValue ? $"X{ModalState.Num(Math.Round(via.X, 4))} " : string.Empty) + (y.HasValue ? $"Y{ModalState.Num(Math.Round(via.Y, 4))} " : string.Empty) + (z.HasValue ? $"Z{ModalState.Num(Math.Round(via.Z, 4))}" : string.Empty))));
            }
        }

        if (col['T' - 'A'] != 0)
        {
            _toolSelected = true;
        }
        else if (toolChange && !_toolSelected)
        {
            Add(diags, DiagnosticCodes.DialectToolChange, line, first, _tool);
        }

        if (toolChange)
        {
            _toolSelected = false;
        }

        for (var i = 0; i < words.Length && _coords.Shift != default; i++)
        {
            ref readonly var w = ref words[i];
            if (w.Letter == 'M' && w.Value is 2 or 30)
            {
                var s = InProgramUnits(_coords.Shift);
                Add(diags, DiagnosticCodes.DialectG92AtEnd, line, w.Column,
                    $"X{ModalState.Num(Math.Round(s.X, 4))} Y{ModalState.Num(Math.Round(s.Y, 4))} Z{ModalState.Num(Math.Round(s.Z, 4))}");
                break;
            }
        }
    }

    private Point3 InProgramUnits(Point3 p) => new(p.X / _scale, p.Y / _scale, p.Z / _scale);

    private static string OffsetName(int key) => key switch
    {
        >= 540 and <= 590 when key % 10 == 0 => "G" + (key / 10).ToString(System.Globalization.CultureInfo.InvariantCulture),
        >= 5410 => "G54.1 P" + (key - 5410).ToString(System.Globalization.CultureInfo.InvariantCulture),
        _ => "G" + ModalState.Num(key / 10.0),
    };
}
