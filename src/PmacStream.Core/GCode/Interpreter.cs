using System.Text;

namespace PmacStream.GCode;

/// <summary>
/// Interprets blocks one after another into <see cref="DecodedBlock"/> records, keeping the modal state (groups
/// GA-GI / MA-MC) and the absolute position. Streaming: it holds only the current state, so any program size works.
/// Semantics are FANUC milling: I/J/K are incremental from the arc start, a negative R means more than 180 degrees,
/// an arc with I/J/K and no axis words is a full circle, <c>G04 P</c> is in milliseconds (profile switch) and
/// <c>G04 X</c> in seconds. Cutter radius and tool length compensation are recorded, not applied to the path.
/// </summary>
public sealed class Interpreter
{
    private const int GroupCount = 9;
    private const int MGroupCount = 3;

    private readonly MachineProfile _profile;
    private readonly double?[] _g = new double?[GroupCount];
    private readonly double?[] _m = new double?[MGroupCount];
    private readonly bool[] _gNonModal = new bool[GroupCount];
    private readonly bool[] _mNonModal = new bool[MGroupCount];
    private LengthUnits _units = LengthUnits.Millimetres;
    private int _plane = 17;
    private bool _absolute = true;
    private int _wcs = 54;
    private Point3? _wcsOffset;
    private int _tool;
    private int _h;
    private int _d;
    private int _spindle = 5;
    private double _speed;
    private int _coolant = 9;
    private double? _feed;
    private Point3 _pos;
    private ModalState? _snapshot;
    private LastBlock _last;
    private bool _dirty = true;
    private bool _nonModalSet = true;
    private readonly LetterKind[] _letterKinds = new LetterKind[26];
    private double? _motionFor = double.NaN;
    private int _motion = -1;
    private bool _axisLineLetters; // the profile takes N, G and X/Y/Z as usual, and the motion group is modal
    private bool _laneOpen;        // an AxisLine would only move now (see UpdateLane)
    private bool _measureMoves = true;
    private bool _recordBlocks = true;
    // Axis values AxisLines set that nobody read yet: where their text is, converted into _pos only when the position
    // is read (a block on the full path, Position) or the text is about to be reused (ReleaseText). The work offset
    // cannot change meanwhile: only StepCore changes it.
    private int _pendingAxes;
    private byte[]? _pendingText;
    private AxisTriple _pendingAt;
    private AxisTriple _pendingSize;

    /// <summary>Starts in the profile's power-on state (its <see cref="MachineProfile.Startup"/> codes) at the origin.</summary>
    public Interpreter(MachineProfile profile)
    {
        _profile = profile;
        ClassifyGroups();
        var startup = GCodeReader.LexLine(profile.Startup);
        foreach (var w in startup.WordList)
        {
            if (w.Letter == 'G' && profile.GGroupOf(w.Value) is var gg and >= 0)
            {
                _g[gg] = w.Value;
                ApplyG(MachineProfile.Key(w.Value));
            }
            else if (w.Letter == 'M' && profile.MGroupOf(w.Value) is var mg and >= 0)
            {
                _m[mg] = w.Value;
                ApplyM(MachineProfile.Key(w.Value));
            }
        }

        ClearNonModal();
        UpdateLane();
    }

    /// <summary>Resumes from a known state and position (start from a block: the state after the block before it).</summary>
    public Interpreter(MachineProfile profile, ModalState state, Point3 position)
    {
        _profile = profile;
        ClassifyGroups();
        for (var i = 0; i < GroupCount; i++)
        {
            _g[i] = state.GetG(i);
        }

        for (var i = 0; i < MGroupCount; i++)
        {
            _m[i] = state.GetM(i);
        }

        ClearNonModal();
        _units = state.Units;
        _plane = state.Plane;
        _absolute = state.Absolute;
        _wcs = state.WorkOffset;
        _wcsOffset = null;
        _tool = state.Tool;
        _h = state.LengthOffset;
        _d = state.CutterComp;
        _spindle = state.Spindle;
        _speed = state.SpindleSpeed;
        _coolant = state.Coolant;
        _feed = state.Feed;
        _pos = position;
        UpdateLane();
    }

    /// <summary>The profile the interpreter works to.</summary>
    public MachineProfile Profile => _profile;

    /// <summary>The modal state after the last block (shared instance while nothing changes).</summary>
    public ModalState State => Snapshot();

    /// <summary>The absolute position after the last block.</summary>
    public Point3 Position
    {
        get
        {
            Resolve();
            return _pos;
        }
    }

    /// <summary>When true, blocks starting with <c>/</c> are skipped (the operator's block-delete switch).</summary>
    public bool BlockDeleteEnabled { get; set; }

    /// <summary>
    /// Whether straight moves get their length (and so a duration). A caller that only wants the diagnostics (the
    /// splitter's check) turns it off: a square root per block is a tenth of the checker's time. Arcs are always
    /// measured, because their geometry is checked.
    /// </summary>
    internal bool MeasureMoves
    {
        get => _measureMoves;
        set
        {
            _measureMoves = value;
            UpdateLane();
        }
    }

    /// <summary>
    /// Whether <see cref="Last"/> gets the whole block (words, positions, motion). Off for a caller that reads only
    /// the line, N and duration (the checker when nobody takes the decoded blocks): filling the record is a tenth
    /// of a block's interpretation.
    /// </summary>
    internal bool RecordBlocks
    {
        get => _recordBlocks;
        set
        {
            _recordBlocks = value;
            UpdateLane();
        }
    }

    /// <summary>
    /// Interprets one block. Returns null for empty, comment-only, tape-mark and program-number-only lines (and for
    /// deleted blocks when <see cref="BlockDeleteEnabled"/>). Never throws on content: what cannot be executed is
    /// skipped here and reported by the checker.
    /// </summary>
    public DecodedBlock? Step(GBlock block) => Step(block, null);

    internal DecodedBlock? Step(GBlock block, List<Diagnostic>? diags) => StepCore(block, diags) ? Materialize() : null;

    /// <summary>The line given to the last <see cref="StepCore"/> carried an O program number (saves the checker a second scan of the words).</summary>
    internal bool LastHadProgramNumber { get; private set; }

    /// <summary>The last interpreted block, without allocating (the checker's hot path when nothing is stored).</summary>
    internal ref readonly LastBlock Last => ref _last;

    /// <summary>The last interpreted block as a record.</summary>
    internal DecodedBlock Materialize() => new()
    {
        Line = _last.Line,
        ByteOffset = _last.ByteOffset,
        N = _last.N,
        BlockDelete = _last.BlockDelete,
        Modal = Snapshot(),
        X = _last.X, Y = _last.Y, Z = _last.Z, I = _last.I, J = _last.J, K = _last.K, R = _last.R, F = _last.F, S = _last.S,
        T = _last.T, H = _last.H, D = _last.D, P = _last.P,
        Motion = _last.Motion,
        Start = _last.Start,
        End = _last.End,
        Center = _last.Center,
        Length = _last.Length,
        DurationSeconds = _last.DurationSeconds,
    };

    /// <summary>Interprets a block into <see cref="Last"/>; false when the line holds no block.</summary>
    // Hot loop of a million-line program: compile optimized at once instead of spending the first
    // hundreds of milliseconds in unoptimized tier-0 code waiting for tiering.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveOptimization)]
    [System.Runtime.CompilerServices.SkipLocalsInit]
    internal bool StepCore(GBlock block, List<Diagnostic>? diags)
    {
        // Before anything here changes the mode or the work offset the lane's values were written under.
        Resolve();
        var words = block.WordList;
        if (words.Count == 0 || block.IsTapeMark || (BlockDeleteEnabled && block.BlockDelete))
        {
            LastHadProgramNumber = block.ProgramNumber.HasValue;
            return false;
        }

        var sawO = false;
        var anyG = false;                              // most CAM blocks carry no G or M word: skip the group loops
        var anyM = false;

        var line = block.LineNumber;
        Span<int> col = stackalloc int[26];          // column of the first word of each letter, 0 = absent
        Span<double> val = stackalloc double[26];
        Span<double> gIn = stackalloc double[GroupCount];
        Span<int> gCol = stackalloc int[GroupCount];
        Span<double> mIn = stackalloc double[MGroupCount];
        Span<int> mCol = stackalloc int[MGroupCount];
        col.Clear();                                   // SkipLocalsInit: only the "seen" markers need zeroing
        gCol.Clear();
        mCol.Clear();
        var onlyO = true;
        var effective = false;
        var wordSpan = System.Runtime.InteropServices.CollectionsMarshal.AsSpan(words);
        var letterKinds = _letterKinds;
        for (var i = 0; i < wordSpan.Length; i++)
        {
            ref readonly var w = ref wordSpan[i];
            var li = w.Letter - 'A';
            if (w.Letter != 'O')
            {
                onlyO = false;
            }
            else
            {
                sawO = true;
            }

            var letterKind = (uint)li < 26 ? letterKinds[li] : LetterKind.Unsupported;
            if (letterKind == LetterKind.Unsupported)
            {
                Add(diags, DiagnosticCodes.UnsupportedLetter, line, w.Column, w.Letter, _profile.Name, _profile.Letters);
                continue;
            }

            if (letterKind is LetterKind.G or LetterKind.M)
            {
                effective = true;
                var isG = letterKind == LetterKind.G;
                var group = isG ? _profile.GGroupOf(w.Value) : _profile.MGroupOf(w.Value);
                if (group < 0)
                {
                    if (diags != null)
                    {
                        var text = Ascii(block.NumberText(w));
                        if (!w.IsInteger)
                        {
                            Add(diags, DiagnosticCodes.DecimalCode, line, w.Column, w.Letter, text);
                        }
                        else
                        {
                            Add(diags, isG ? DiagnosticCodes.UnknownGCode : DiagnosticCodes.UnknownMCode, line, w.Column, text, _profile.Name);
                        }
                    }

                    continue;
                }

                var slotCol = isG ? gCol : mCol;
                if (slotCol[group] != 0)
                {
                    if (diags != null)
                    {
                        var names = isG ? MachineProfile.GGroupNames : MachineProfile.MGroupNames;
                        Add(diags, DiagnosticCodes.ModalGroupConflict, line, w.Column, w.Letter, CodeText(isG ? gIn[group] : mIn[group]), CodeText(w.Value), names[group]);
                    }

                    continue;
                }

                slotCol[group] = w.Column;
                (isG ? gIn : mIn)[group] = w.Value;
                anyG |= isG;
                anyM |= !isG;
                continue;
            }

            if (col[li] != 0)
            {
                Add(diags, DiagnosticCodes.DuplicateWord, line, w.Column, w.Letter, col[li]);
                continue;
            }

            col[li] = w.Column;
            val[li] = w.Value;
            effective |= letterKind == LetterKind.Effective;
        }

        LastHadProgramNumber = sawO;
        if (onlyO)
        {
            return false;
        }

        // Modal groups first (units, plane, distance, offsets), so that motion in the same block uses them.
        ClearNonModal();
        var dwell = false;
        var motionInBlock = -1;
        for (var gi = 0; anyG && gi < GroupCount; gi++)
        {
            if (gCol[gi] == 0)
            {
                continue;
            }

            var key = MachineProfile.Key(gIn[gi]);
            SetG(gi, gIn[gi]);
            ApplyG(key);
            if (key == 40)
            {
                dwell = true;
            }
            else if (key is 0 or 10 or 20 or 30)
            {
                motionInBlock = key / 10;
            }
        }

        for (var mi = 0; anyM && mi < MGroupCount; mi++)
        {
            if (mCol[mi] != 0)
            {
                SetM(mi, mIn[mi]);
                ApplyM(MachineProfile.Key(mIn[mi]));
            }
        }

        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        static double? Word(char c, Span<int> col, Span<double> val) => col[c - 'A'] != 0 ? val[c - 'A'] : null;
        static int ColOf(char c, Span<int> col) => col[c - 'A'];

        // Values and their ranges.
        var f = Word('F', col, val);
        if (f is { } fv)
        {
            if (fv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, ColOf('F', col), 'F', ModalState.Num(fv));
            }
            else if (_feed != fv)
            {
                _feed = fv;
                _dirty = true;
            }
        }

        var s = Word('S', col, val);
        if (s is { } sv)
        {
            if (sv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, ColOf('S', col), 'S', ModalState.Num(sv));
            }
            else if (_speed != sv)
            {
                _speed = sv;
                _dirty = true;
            }
        }

        var t = Word('T', col, val);
        if (t is { } tv)
        {
            if (tv < 0 || tv > _profile.ToolCount || tv != Math.Floor(tv))
            {
                Add(diags, DiagnosticCodes.ToolOutOfRange, line, ColOf('T', col), ModalState.Num(tv), _profile.ToolCount);
            }
            else if (_tool != (int)tv)
            {
                _tool = (int)tv;
                _dirty = true;
            }
        }

        var h = Word('H', col, val);
        if (h is { } hv)
        {
            if (hv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, ColOf('H', col), 'H', ModalState.Num(hv));
            }
            else if (_h != (int)hv)
            {
                _h = (int)hv;
                _dirty = true;
            }
        }

        var d = Word('D', col, val);
        if (d is { } dv)
        {
            if (dv < 0)
            {
                Add(diags, DiagnosticCodes.NegativeValue, line, ColOf('D', col), 'D', ModalState.Num(dv));
            }
            else if (_d != (int)dv)
            {
                _d = (int)dv;
                _dirty = true;
            }
        }

        var p = Word('P', col, val);
        if (p is { } pv && pv < 0)
        {
            Add(diags, DiagnosticCodes.NegativeValue, line, ColOf('P', col), 'P', ModalState.Num(pv));
        }

        var x = Word('X', col, val);
        var y = Word('Y', col, val);
        var z = Word('Z', col, val);
        var i0 = Word('I', col, val);
        var j0 = Word('J', col, val);
        var k0 = Word('K', col, val);
        var r = Word('R', col, val);
        var hasAxes = x.HasValue || y.HasValue || z.HasValue || col['A' - 'A'] != 0 || col['B' - 'A'] != 0 || col['C' - 'A'] != 0;

        if (!effective)
        {
            var first = words[0].Column;
            Add(diags, DiagnosticCodes.NoFunction, line, first);
        }

        var start = _pos;
        var end = start;
        Point3? center = null;
        var kind = MotionKind.None;
        double length = 0;
        double seconds = 0;
        var usedArcWords = false;
        var usedP = false;

        if (dwell)
        {
            kind = MotionKind.Dwell;
            usedP = p.HasValue;
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
                Add(diags, DiagnosticCodes.MissingWord, line, gCol[IndexOfGroupWithKey(40)], "G04", "P", "dwell of 0 s", "暂停 0 秒");
            }

            if (y.HasValue)
            {
                Add(diags, DiagnosticCodes.UnusedWord, line, ColOf('Y', col), 'Y');
            }

            if (z.HasValue)
            {
                Add(diags, DiagnosticCodes.UnusedWord, line, ColOf('Z', col), 'Z');
            }

            if (p.HasValue && x.HasValue)
            {
                Add(diags, DiagnosticCodes.UnusedWord, line, ColOf('X', col), 'X');
            }
        }
        else if (hasAxes || ((motionInBlock is 2 or 3) && (i0.HasValue || j0.HasValue || k0.HasValue)))
        {
            end = Target(start, x, y, z);
            var mode = MotionMode();
            var modeCol = motionInBlock >= 0 ? gCol[0] : words[0].Column;
            switch (mode)
            {
                case 0:
                    kind = MotionKind.Rapid;
                    length = MeasureMoves ? start.DistanceTo(end) : 0;
                    seconds = length / (_units == LengthUnits.Inches ? _profile.RapidRate / 25.4 : _profile.RapidRate) * 60.0;
                    break;
                case 1:
                    kind = MotionKind.Linear;
                    length = MeasureMoves ? start.DistanceTo(end) : 0;
                    seconds = FeedTime(length, diags, line, modeCol, 1);
                    break;
                case 2:
                case 3:
                    kind = mode == 2 ? MotionKind.ArcCw : MotionKind.ArcCcw;
                    usedArcWords = true;
                    (center, length) = Arc(mode == 2, start, end, i0, j0, k0, r, diags, line, modeCol, col);
                    seconds = FeedTime(length, diags, line, modeCol, mode);
                    break;
                default:
                    // Axis words with no motion mode in force: the startup codes of the profile set none.
                    Add(diags, DiagnosticCodes.MotionWithoutAxes, line, words[0].Column, "00/G01");
                    end = start;
                    break;
            }
        }
        else if (motionInBlock is 2 or 3)
        {
            Add(diags, DiagnosticCodes.MotionWithoutAxes, line, gCol[0], motionInBlock == 2 ? "02" : "03");
            usedArcWords = true;
        }

        if (diags != null)
        {
            if (!usedArcWords && (col['I' - 'A'] | col['J' - 'A'] | col['K' - 'A'] | col['R' - 'A']) != 0)
            {
                foreach (var c in "IJKR")
                {
                    if (col[c - 'A'] != 0)
                    {
                        Add(diags, DiagnosticCodes.UnusedWord, line, col[c - 'A'], c);
                    }
                }
            }

            if (p.HasValue && !usedP && effective)
            {
                Add(diags, DiagnosticCodes.UnusedWord, line, ColOf('P', col), 'P');
            }
        }

        _pos = end;
        UpdateLane();
        // Filled in place: the record is large and this runs once per block.
        ref var last = ref _last;
        if (!RecordBlocks)
        {
            // Only what the checker's own summary reads.
            last.Line = line;
            last.N = Word('N', col, val);
            last.DurationSeconds = seconds;
            return true;
        }

        last.Line = line;
        last.ByteOffset = block.ByteOffset;
        last.N = Word('N', col, val);
        last.BlockDelete = block.BlockDelete;
        last.X = x;
        last.Y = y;
        last.Z = z;
        last.I = i0;
        last.J = j0;
        last.K = k0;
        last.R = r;
        last.F = f;
        last.S = s;
        last.T = t;
        last.H = h;
        last.D = d;
        last.P = p;
        last.Motion = kind;
        last.Start = start;
        last.End = end;
        last.Center = center;
        last.Length = length;
        last.DurationSeconds = seconds;
        return true;
    }

    /// <summary>
    /// Interprets an <see cref="AxisLine"/> (N, the motion code in force, X/Y/Z), whose text is at
    /// <paramref name="textStart"/> of <paramref name="text"/>, when that is sure to raise no diagnostic and to do
    /// nothing but move: absolute G00 (with a rapid rate) or G01 with a feed, no non-modal code pending, neither
    /// lengths nor records wanted. The state then ends as <see cref="StepCore"/> leaves it (<see cref="Last"/> is
    /// not filled: nobody reads it without records); otherwise nothing changes and the answer is false.
    /// </summary>
    internal bool TryStepAxisLine(in AxisLine a, byte[] text, int textStart)
    {
        if (!_laneOpen || (a.HasG && a.G != _g[0]))
        {
            return false;
        }

        if (!ReferenceEquals(text, _pendingText))
        {
            // Values left in another array (a grown or earlier batch) are read while it is still intact.
            Resolve();
            _pendingText = text;
        }

        var axes = a.Axes;
        for (var axis = 0; axis < 3; axis++)
        {
            if ((axes & (AxisLine.XBit << axis)) != 0)
            {
                _pendingAt[axis] = textStart + a.At[axis];
                _pendingSize[axis] = a.Size[axis];
            }
        }

        _pendingAxes |= axes;
        LastHadProgramNumber = false;
        return true;
    }

    /// <summary>Whether <see cref="TryStepAxisLine"/> can take a line at all now (false in G91, G02/G03, without a feed, ...).</summary>
    internal bool AxisLaneOpen => _laneOpen;

    /// <summary>
    /// The caller is about to reuse <paramref name="text"/> (an <see cref="AxisLine"/>'s text array given to
    /// <see cref="TryStepAxisLine"/>): values still held there are read now.
    /// </summary>
    internal void ReleaseText(byte[] text)
    {
        if (ReferenceEquals(text, _pendingText))
        {
            Resolve();
            _pendingText = null;
        }
    }

    /// <summary>Converts the axis values lane lines left as text into the position.</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private void Resolve()
    {
        if (_pendingAxes != 0)
        {
            ResolvePending();
        }
    }

    private void ResolvePending()
    {
        // The lane only takes lines in absolute mode, and nothing changed the mode or the work offset since: the
        // block's own target computation gives the same position the full path would have.
        var axes = _pendingAxes;
        _pendingAxes = 0;
        _pos = Target(_pos, PendingValue(axes, 0), PendingValue(axes, 1), PendingValue(axes, 2));
    }

    private double? PendingValue(int axes, int axis) =>
        (axes & (AxisLine.XBit << axis)) != 0 ? AxisLine.Value(_pendingText.AsSpan(_pendingAt[axis], _pendingSize[axis])) : null;

    /// <summary>Whether an <see cref="AxisLine"/> would only move in the state reached (recomputed whenever it may change).</summary>
    private void UpdateLane()
    {
        var mode = MotionMode();
        _laneOpen = !_nonModalSet && _absolute && !_recordBlocks && !_measureMoves && _axisLineLetters &&
            (mode == 1 ? _feed > 0 : mode == 0 && _profile.RapidRate > 0);
    }

    // The motion mode (0..3 for G00..G03, -1 when none) of group GA, recomputed only when GA changes.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private int MotionMode()
    {
        var ga = _g[0];
        if (ga != _motionFor)
        {
            _motionFor = ga;
            _motion = ga is { } v ? MachineProfile.Key(v) / 10 : -1;
        }

        return _motion;
    }

    private int IndexOfGroupWithKey(int key)
    {
        for (var i = 0; i < GroupCount; i++)
        {
            if (_g[i] is { } v && MachineProfile.Key(v) == key)
            {
                return i;
            }
        }

        return 0;
    }

    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private double FeedTime(double length, List<Diagnostic>? diags, int line, int column, int mode) =>
        _feed is { } feed && feed > 0 ? length / feed * 60.0 : NoFeed(diags, line, column, mode);

    private double NoFeed(List<Diagnostic>? diags, int line, int column, int mode)
    {
        Add(diags, DiagnosticCodes.FeedMoveWithoutFeed, line, column, "0" + mode);
        return 0;
    }

    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    private Point3 Target(Point3 start, double? x, double? y, double? z)
    {
        if (_absolute)
        {
            // The offset of the active work coordinate system, looked up once per G54..G59 change, not per block.
            var o = _wcsOffset ??= _profile.WorkOffset(_wcs);
            return new Point3(x is { } ax ? ax + o.X : start.X, y is { } ay ? ay + o.Y : start.Y, z is { } az ? az + o.Z : start.Z);
        }

        return new Point3(start.X + (x ?? 0), start.Y + (y ?? 0), start.Z + (z ?? 0));
    }

    private (Point3? Center, double Length) Arc(bool cw, Point3 start, Point3 end, double? i, double? j, double? k, double? r,
        List<Diagnostic>? diags, int line, int column, Span<int> col)
    {
        // Map the plane to (first, second, linear) axes; G18 is ZX so that G02/G03 keep the right-hand rule.
        (double s1, double s2, double sl, double e1, double e2, double el, double? o1, double? o2, string names) = _plane switch
        {
            18 => (start.Z, start.X, start.Y, end.Z, end.X, end.Y, k, i, "I/K"),
            19 => (start.Y, start.Z, start.X, end.Y, end.Z, end.X, j, k, "J/K"),
            _ => (start.X, start.Y, start.Z, end.X, end.Y, end.Z, i, j, "I/J"),
        };

        double c1, c2;
        var tol = _profile.ArcTolerance;
        if (r is { } radius)
        {
            var dx = e1 - s1;
            var dy = e2 - s2;
            var chord = Math.Sqrt((dx * dx) + (dy * dy));
            var half = chord / 2;
            var rr = Math.Abs(radius);
            if (chord < 1e-12 || half - rr > tol)
            {
                Add(diags, DiagnosticCodes.ArcRadiusMismatch, line, col['R' - 'A'], ModalState.Num(Math.Round(rr, 4)),
                    ModalState.Num(Math.Round(half, 4)), ModalState.Num(tol));
                return (null, start.DistanceTo(end));
            }

            var hgt = Math.Sqrt(Math.Max(0, (rr * rr) - (half * half)));
            var sign = (cw ? -1 : 1) * (radius < 0 ? -1 : 1);
            c1 = s1 + (dx / 2) + (-dy / chord * hgt * sign);
            c2 = s2 + (dy / 2) + (dx / chord * hgt * sign);
        }
        else if (o1.HasValue || o2.HasValue)
        {
            c1 = s1 + (o1 ?? 0);
            c2 = s2 + (o2 ?? 0);
            var r0 = Math.Sqrt(((s1 - c1) * (s1 - c1)) + ((s2 - c2) * (s2 - c2)));
            var r1 = Math.Sqrt(((e1 - c1) * (e1 - c1)) + ((e2 - c2) * (e2 - c2)));
            if (Math.Abs(r0 - r1) > tol && Math.Abs(r0 - r1) > 0.001 * Math.Max(r0, r1))
            {
                var firstOffset = _plane switch { 18 => Min(col['K' - 'A'], col['I' - 'A']), 19 => Min(col['J' - 'A'], col['K' - 'A']), _ => Min(col['I' - 'A'], col['J' - 'A']) };
                Add(diags, DiagnosticCodes.ArcRadiusMismatch, line, firstOffset, ModalState.Num(Math.Round(r0, 4)),
                    ModalState.Num(Math.Round(r1, 4)), ModalState.Num(tol));
            }
        }
        else
        {
            Add(diags, DiagnosticCodes.ArcWithoutCenter, line, column, cw ? "02" : "03", names, _plane);
            return (null, start.DistanceTo(end));
        }

        var a0 = Math.Atan2(s2 - c2, s1 - c1);
        var a1 = Math.Atan2(e2 - c2, e1 - c1);
        var sweep = cw ? a0 - a1 : a1 - a0;
        while (sweep <= 1e-12)
        {
            sweep += 2 * Math.PI;
        }

        var rad = Math.Sqrt(((s1 - c1) * (s1 - c1)) + ((s2 - c2) * (s2 - c2)));
        var planar = rad * sweep;
        var helix = el - sl;
        var len = Math.Sqrt((planar * planar) + (helix * helix));
        var centre = _plane switch
        {
            18 => new Point3(c2, start.Y, c1),
            19 => new Point3(start.X, c1, c2),
            _ => new Point3(c1, c2, start.Z),
        };
        return (centre, len);
    }

    private static int Min(int a, int b) => a == 0 ? b : b == 0 ? a : Math.Min(a, b);

    private void ClassifyGroups()
    {
        // One table lookup per word instead of the profile's letter set plus the letter tests in the hot loop.
        for (var c = 'A'; c <= 'Z'; c++)
        {
            _letterKinds[c - 'A'] = !_profile.AcceptsLetter(c) ? LetterKind.Unsupported
                : c == 'G' ? LetterKind.G
                : c == 'M' ? LetterKind.M
                : c is 'N' or 'O' or 'I' or 'J' or 'K' or 'R' or 'P' or 'Q' or 'L' ? LetterKind.Parameter
                : LetterKind.Effective;
        }

        // A group is non-modal when every code in it is one that acts only in its own block.
        int[] nonModalG = [40, 90, 100, 280, 300, 530, 650, 920];
        int[] nonModalM = [0, 10, 20, 300, 60, 980, 990];
        Classify(_profile.GCodes, MachineProfile.GGroupNames, nonModalG, _gNonModal);
        Classify(_profile.MCodes, MachineProfile.MGroupNames, nonModalM, _mNonModal);
        _axisLineLetters = _letterKinds['N' - 'A'] == LetterKind.Parameter && _letterKinds['G' - 'A'] == LetterKind.G &&
            _letterKinds['X' - 'A'] == LetterKind.Effective && _letterKinds['Y' - 'A'] == LetterKind.Effective &&
            _letterKinds['Z' - 'A'] == LetterKind.Effective && !_gNonModal[0];
    }

    private static void Classify(IReadOnlyList<CodeDefinition> codes, IReadOnlyList<string> names, int[] nonModal, bool[] result)
    {
        for (var gi = 0; gi < names.Count; gi++)
        {
            var any = false;
            var all = true;
            foreach (var c in codes)
            {
                if (!string.Equals(c.Group, names[gi], StringComparison.OrdinalIgnoreCase))
                {
                    continue;
                }

                any = true;
                var key = MachineProfile.Key(double.Parse(c.Code.AsSpan(1), System.Globalization.CultureInfo.InvariantCulture));
                all &= Array.IndexOf(nonModal, key) >= 0;
            }

            result[gi] = any && all;
        }
    }

    private void ClearNonModal()
    {
        // Most blocks follow a block that set no non-modal code (G04, G53, M00...): nothing to clear then.
        if (!_nonModalSet)
        {
            return;
        }

        _nonModalSet = false;
        for (var i = 0; i < GroupCount; i++)
        {
            if (_gNonModal[i] && _g[i] != null)
            {
                _g[i] = null;
                _dirty = true;
            }
        }

        for (var i = 0; i < MGroupCount; i++)
        {
            if (_mNonModal[i] && _m[i] != null)
            {
                _m[i] = null;
                _dirty = true;
            }
        }
    }

    private void SetG(int group, double value)
    {
        _nonModalSet |= _gNonModal[group];
        if (_g[group] != value)
        {
            _g[group] = value;
            _dirty = true;
        }
    }

    private void SetM(int group, double value)
    {
        _nonModalSet |= _mNonModal[group];
        if (_m[group] != value)
        {
            _m[group] = value;
            _dirty = true;
        }
    }

    private void ApplyG(int key)
    {
        switch (key)
        {
            case 170 or 180 or 190: _plane = key / 10; break;
            case 200: _units = LengthUnits.Inches; break;
            case 210: _units = LengthUnits.Millimetres; break;
            case 900: _absolute = true; break;
            case 910: _absolute = false; break;
            case >= 540 and <= 590 when key % 10 == 0: _wcs = key / 10; _wcsOffset = null; break;
            default: return;
        }

        _dirty = true;
    }

    private void ApplyM(int key)
    {
        switch (key)
        {
            case 30 or 40 or 50: _spindle = key / 10; break;
            case 70 or 80 or 90: _coolant = key / 10; break;
            default: return;
        }

        _dirty = true;
    }

    private ModalState Snapshot()
    {
        if (_dirty || _snapshot is null)
        {
            _snapshot = new ModalState
            {
                GA = _g[0], GB = _g[1], GC = _g[2], GD = _g[3], GE = _g[4], GF = _g[5], GG = _g[6], GH = _g[7], GI = _g[8],
                MA = _m[0], MB = _m[1], MC = _m[2],
                Units = _units, Plane = _plane, Absolute = _absolute, WorkOffset = _wcs, Tool = _tool, LengthOffset = _h,
                CutterComp = _d, Spindle = _spindle, SpindleSpeed = _speed, Coolant = _coolant, Feed = _feed,
            };
            _dirty = false;
        }

        return _snapshot;
    }

    private static string CodeText(double code) => (code < 10 ? "0" : string.Empty) + ModalState.Num(code);

    private static string Ascii(ReadOnlySpan<byte> text) => Encoding.ASCII.GetString(text);

    private static void Add(List<Diagnostic>? diags, string code, int line, int column, params object[] args)
    {
        diags?.Add(new Diagnostic(DiagnosticCodes.SeverityOf(code), code, line, column, DiagnosticText.Format(code, args)));
    }

    /// <summary>What a word's letter does in a block.</summary>
    private enum LetterKind : byte
    {
        Unsupported,
        G,
        M,
        Parameter,   // N, O, I, J, K, R, P, Q, L: not an effective function on their own
        Effective,   // axes, F, S, T, H, D...: the block does something
    }

    /// <summary>The fields of a decoded block without the allocation.</summary>
    internal struct LastBlock
    {
        public int Line;
        public long ByteOffset;
        public double? N;
        public bool BlockDelete;
        public double? X, Y, Z, I, J, K, R, F, S, T, H, D, P;
        public MotionKind Motion;
        public Point3 Start, End;
        public Point3? Center;
        public double Length, DurationSeconds;
    }
}
