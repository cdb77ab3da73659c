using System.Runtime.CompilerServices;

namespace PmacStream.GCode;

/// <summary>The interpreter's moves beyond straight lines and arcs: dwells, reference returns, cycle holes, offsets that data codes set, move times.</summary>
public sealed partial class Interpreter
{
    /// <summary>G04: the dwell's seconds from P (in the profile's unit) or X (seconds); W005 without either, W003 for the axis words it does not read.</summary>
    private double ConvertDwell(double? p, double? x, double? y, double? z, Span<int> col, List<Diagnostic>? diags, int line, int column)
    {
        var seconds = 0.0;
        if (p is { } pd && pd >= 0)
        {
            seconds = _profile.DwellPInMilliseconds ? pd / 1000.0 : pd;
        }
        else if (x is { } xd && xd >= 0)
        {
            seconds = xd;
        }
        else if (!p.HasValue && !x.HasValue)
        {
            Add(diags, DiagnosticCodes.MissingWord, line, column, "G04", "P", "dwell of 0 s", "暂停 0 秒");
        }

        if (y.HasValue)
        {
            Add(diags, DiagnosticCodes.UnusedWord, line, col['Y' - 'A'], 'Y');
        }

        if (z.HasValue)
        {
            Add(diags, DiagnosticCodes.UnusedWord, line, col['Z' - 'A'], 'Z');
        }

        if (p.HasValue && x.HasValue)
        {
            Add(diags, DiagnosticCodes.UnusedWord, line, col['X' - 'A'], 'X');
        }

        return seconds;
    }

    /// <summary>G27-G30: through the programmed point to the reference position, on the axes named (their steps to <see cref="Canon"/>).</summary>
    private (Point3 End, MotionKind Kind, double Length, double Seconds) ConvertReference(int key, Point3 start, double? x, double? y, double? z, bool hasAxes)
    {
        var via = Target(start, x, y, z);
        var home = key is 280 or 300 ? _profile.ReferencePosition(key / 10) : via;
        var end = new Point3(x.HasValue ? home.X : start.X, y.HasValue ? home.Y : start.Y, z.HasValue ? home.Z : start.Z);
        if (Canon is { } canon && hasAxes)
        {
            // Only the axes the block names move, to the intermediate point too: the others stay wherever the
            // machine is (at a program's first G28 the host does not know where that is).
            var named = (x.HasValue ? 1 : 0) | (y.HasValue ? 2 : 0) | (z.HasValue ? 4 : 0);
            canon.Step(new HostMove(HostMoveKind.Rapid, via, 0, named));
            if (key is 280 or 300)
            {
                canon.Step(new HostMove(HostMoveKind.MachineRapid, end, 0, named));
            }
        }

        var length = MeasureMoves ? start.DistanceTo(via) + via.DistanceTo(end) : 0;
        return (end, hasAxes ? MotionKind.Rapid : MotionKind.None, length, RapidTime(length));
    }

    /// <summary>The holes of a positioning block while a cycle is in force (see <see cref="CannedCycle"/>).</summary>
    private (Point3 End, MotionKind Kind, double Length, double Seconds) Holes(Point3 start, double? x, double? y, double? z, double? r,
        Span<int> col, Span<double> val, List<Diagnostic>? diags, int line, ref BlockCodes codes)
    {
        var key = _cycle.Code;
        var info = _gInfo.TryGetValue(key, out var ci) ? ci : default;
        codes.Read |= info.WordMask;
        var column = codes.CycleColumn != 0 ? codes.CycleColumn : col['X' - 'A'] | col['Y' - 'A'] | col['Z' - 'A'];
        if (z is null && !_cycle.HasBottom)
        {
            Add(diags, DiagnosticCodes.RequiredWordMissing, line, column == 0 ? 1 : column, "G" + CodeText(key / 10.0), "Z", "where the hole ends", "孔底位置");
        }

        // A repeat count: FANUC writes K, RS274/NGC L; 0 keeps the data without drilling.
        var repeats = info.Reads('K') && col['K' - 'A'] != 0 ? val['K' - 'A'] : info.Reads('L') && col['L' - 'A'] != 0 ? val['L' - 'A'] : 1;
        double? q = col['Q' - 'A'] != 0 ? val['Q' - 'A'] * _scale : null;
        var dwell = col['P' - 'A'] != 0 ? (_profile.DwellPInMilliseconds ? val['P' - 'A'] / 1000.0 : val['P' - 'A']) : 0;
        var (end, rapid, feed, holes) = _cycle.Run(start, x, y, z, r, q, dwell, (int)Math.Max(0, repeats), _absolute, _returnToR, _coords.Active);
        if (Canon is { } canon)
        {
            var steps = _cycle.Steps;
            for (var i = 0; i < steps.Count; i++)
            {
                canon.Step(steps[i]);
            }
        }

        if (holes == 0)
        {
            return (start, MotionKind.None, 0, 0);
        }

        var dwellSeconds = 0.0;
        foreach (var step in _cycle.Steps)
        {
            dwellSeconds += step.Seconds;
        }

        var seconds = dwellSeconds + RapidTime(rapid) + FeedTime(feed, col['F' - 'A'] != 0, diags, line, column == 0 ? 1 : column, key / 10);
        return (end, MotionKind.Cycle, rapid + feed, seconds);
    }

    /// <summary>Cycles begin with their code and end with G80 or a motion code later in the block (FANUC cancels a cycle with a group 01 code).</summary>
    private void UpdateCycle(ref BlockCodes codes)
    {
        if (codes.Cycle != 0 && !(codes.MotionInBlock >= 0 && codes.MotionColumn > codes.CycleColumn))
        {
            _cycle.Enter(codes.Cycle, _pos.Z);
        }
        else if (_cycle.Active && (codes.CycleCancel || codes.MotionInBlock >= 0))
        {
            _cycle.Cancel();
            if (!codes.CycleCancel && _cycleGroup >= 0 && _cycleGroup != _motionGroup && _profile.GGroupOf(80) == _cycleGroup)
            {
                SetG(_cycleGroup, 80);
            }
        }
    }

    /// <summary>
    /// E131 for a data code that would give a rotary axis (A, B, C) an offset: the library's offsets are on X, Y and Z
    /// and rotary positions are not tracked, so the axis would run at its program value. Zero offsets are what the
    /// controller does anyway; G92 and "from the current position" settings depend on a position nobody knows here.
    /// </summary>
    private void CheckRotaryOffset(int key, double? l, Span<int> col, Span<double> val, List<Diagnostic> diags, int line)
    {
        foreach (var c in "ABC")
        {
            var at = col[c - 'A'];
            if (at == 0)
            {
                continue;
            }

            var zero = val[c - 'A'] == 0;
            var what = key switch
            {
                920 => "G92",
                520 when !zero => "G52",
                100 when l is 2 && !zero => "G10 L2",
                100 when l is 20 && (!zero || !_profile.ExtendedWorkOffsets) => "G10 L20",
                _ => null,
            };
            if (what != null)
            {
                Add(diags, DiagnosticCodes.RotaryOffset, line, at, what, c);
            }
        }
    }

    /// <summary>The offsets a data code sets from its words.</summary>
    private void SetData(int key, double? x, double? y, double? z, double? l, double? p, double? r)
    {
        if (key == 100)
        {
            SetRadius(l, p, r);
        }

        switch (key)
        {
            case 920:
                _coords.SetShift(x, y, z, _pos);
                break;
            case 921 or 922:
                _coords.ClearShift();
                break;
            case 520:
                _coords.SetLocal(x, y, z);
                break;
            case 100 when l is 2 or 20 && p is { } n && n >= 0:
                // L2 sets an offset to the values; L20 sets FANUC's extended offsets, or (RS274/NGC, grbl) the offset
                // that makes the current position read as the values.
                var extended = l == 20 && _profile.ExtendedWorkOffsets;
                _coords.SetOffset((int)n, extended, fromPosition: l == 20 && !extended, x, y, z, _pos);
                break;
            case 100 when l is 10 or 11 && _profile.ExtendedWorkOffsets && p is { } h && r is { } length:
                // FANUC: L10 tool length geometry of offset P, L11 its wear, the value in R.
                _coords.SetToolLength((int)h, length, wear: l == 11);
                UpdateToolLength();
                break;
            case 100 when l is 1 or 10 && !_profile.ExtendedWorkOffsets && p is { } t && z is { } zl:
                // RS274/NGC: L1 sets tool P's length to Z; L10 so that the current position reads as Z with it applied.
                var c = _coords;
                _coords.SetToolLength((int)t, l == 1 ? zl : _pos.Z - zl - (c.OffsetOf(c.Selected) + c.External + c.Local + c.Shift).Z, wear: false);
                UpdateToolLength();
                break;
            default:
                return;
        }

        _dirty = true;
    }

    [MethodImpl(MethodImplOptions.AggressiveInlining)]
    private double RapidTime(double length) => length / _profile.RapidRate * 60.0;

    [MethodImpl(MethodImplOptions.AggressiveInlining)]
    private double FeedTime(double length, bool fInBlock, List<Diagnostic>? diags, int line, int column, int mode) =>
        _feedMode == 94 && _feed is { } feed && feed > 0 ? length / (feed * _scale) * 60.0 : OtherFeedTime(length, fInBlock, diags, line, column, mode);

    /// <summary><see cref="FeedTime"/> without a feed, or in inverse time or per revolution.</summary>
    private double OtherFeedTime(double length, bool fInBlock, List<Diagnostic>? diags, int line, int column, int mode)
    {
        if (_feed is not { } feed || feed <= 0 || (_feedMode == 93 && !fInBlock))
        {
            // Inverse time (G93) wants the F of every feed move in its own block.
            Add(diags, DiagnosticCodes.FeedMoveWithoutFeed, line, column, mode < 10 ? "0" + mode : mode.ToString(System.Globalization.CultureInfo.InvariantCulture));
            return 0;
        }

        return _feedMode switch
        {
            93 => 60.0 / feed,                                   // F is moves per minute
            95 => _speed > 0 ? length / (feed * _scale * _speed) * 60.0 : 0, // F per spindle revolution
            _ => length / (feed * _scale) * 60.0,
        };
    }

    /// <summary>F, S, T, H, D and P: their ranges (E106, E107), and the modal values they set.</summary>
    private void TakeValues(Span<int> col, Span<double> val, List<Diagnostic>? diags, int line)
    {
        [MethodImpl(MethodImplOptions.AggressiveInlining)]
        static double? ValueOf(char c, Span<int> col, Span<double> val) => col[c - 'A'] != 0 ? val[c - 'A'] : null;

        var f = ValueOf('F', col, val);
        if (f is { } fv)
        {
            if (fv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, col['F' - 'A'], 'F', ModalState.Num(fv));
            }
            else if (_feed != fv)
            {
                _feed = fv;
                _dirty = true;
            }
        }

        var s = ValueOf('S', col, val);
        if (s is { } sv)
        {
            if (sv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, col['S' - 'A'], 'S', ModalState.Num(sv));
            }
            else if (_speed != sv)
            {
                _speed = sv;
                _dirty = true;
            }
        }

        var t = ValueOf('T', col, val);
        if (t is { } tv)
        {
            if (tv < 0 || tv > _profile.ToolCount || tv != Math.Floor(tv))
            {
                Add(diags, DiagnosticCodes.ToolOutOfRange, line, col['T' - 'A'], ModalState.Num(tv), _profile.ToolCount);
            }
            else if (_tool != (int)tv)
            {
                _tool = (int)tv;
                _dirty = true;
            }
        }

        var h = ValueOf('H', col, val);
        if (h is { } hv)
        {
            if (hv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, col['H' - 'A'], 'H', ModalState.Num(hv));
            }
            else if (_h != (int)hv)
            {
                _h = (int)hv;
                _dirty = true;
            }
        }

        var d = ValueOf('D', col, val);
        if (d is { } dv)
        {
            if (dv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, col['D' - 'A'], 'D', ModalState.Num(dv));
            }
            else if (_d != (int)dv)
            {
                _d = (int)dv;
                _dirty = true;
            }
        }

        var p = ValueOf('P', col, val);
        if (p is { } pv && pv < 0)
        {
            Add(diags, DiagnosticCodes.NegativeValue, line, col['P' - 'A'], 'P', ModalState.Num(pv));
        }
    }
}
