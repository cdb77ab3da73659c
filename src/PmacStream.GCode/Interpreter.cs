using System.Runtime.CompilerServices;
using System.Text;

namespace PmacStream.GCode;

/// <summary>
/// Interprets blocks one after another into <see cref="DecodedBlock"/> records, keeping the modal state (one value per
/// modal group of the profile) and the absolute position. Streaming: it holds only the current state, so any
/// program size works. Semantics are FANUC milling, with the profile's dialect facts: I/J/K are incremental from the
/// arc start (absolute after G90.1), a negative R means more than 180 degrees, an arc with I/J/K and no axis words
/// is a full circle, <c>G04 P</c> is in milliseconds or seconds as the profile says and <c>G04 X</c> in seconds,
/// drilling cycles run hole by hole (<see cref="CannedCycle"/>), G28/G30 pass their point to the reference position,
/// G53 moves in machine coordinates, G10/G52/G92 set offsets (<see cref="WorkCoordinates"/>), G43/G44 H apply the tool
/// length on Z, G51.1/G51/G68 mirror, scale and rotate the programmed positions before the work offset
/// (<see cref="ProgramTransform"/>). Positions are machine coordinates in millimetres whatever the program's units (G20 values are scaled
/// by 25.4), so they are what the controller's axes reach. G41/G42 compensate lines and arcs in the XY plane
/// (<see cref="CutterCompensation"/>): positions are the tool's, beside the programmed path; rotary axes (A/B/C) are accepted and not tracked, so an offset that would move one is refused (E131).
/// </summary>
public sealed partial class Interpreter
{
    private readonly MachineProfile _profile;
    private readonly int _gCount;
    private readonly int _mCount;
    private readonly double?[] _g;
    private readonly double?[] _m;
    private readonly bool[] _gNonModal;
    private readonly bool[] _mNonModal;
    private readonly Dictionary<int, CodeInfo> _gInfo = new();
    private readonly Dictionary<int, CodeInfo> _mInfo = new();
    private readonly int _motionGroup;  // the group of G01, -1 when the profile has none
    private readonly int _cycleGroup;   // the group of G81, -1 when the profile has no cycles
    private readonly WorkCoordinates _coords;
    private readonly CannedCycle _cycle = new();
    private readonly Dictionary<string, int> _notYet = new(StringComparer.Ordinal);
    private LengthUnits _units = LengthUnits.Millimetres;
    private double _scale = 1.0;   // program length units to millimetres (25.4 in G20): positions are always millimetres
    private int _lengthMode;       // 43 or 44 while a tool length offset is in force, 0 for G49
    private int _plane = 17;
    private bool _absolute = true;
    private bool _arcAbsolute;
    private bool _returnToR;
    private int _feedMode = 94;
    private int _tool;
    private int _h;
    private int _d;
    private double _speed;
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
    private bool _laneOpenUnrecorded; // ... were neither records nor lengths wanted
    private bool _measureMoves = true;
    private bool _recordBlocks = true;
    private MotionKind _blockKind; // the motion of the line taken last (None until it moves)
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
        (_gCount, _mCount) = (profile.GGroups.Count, profile.MGroups.Count);
        (_g, _m, _gNonModal, _mNonModal) = (new double?[_gCount], new double?[_mCount], new bool[_gCount], new bool[_mCount]);
        _coords = new WorkCoordinates(profile, 54);
        (_motionGroup, _cycleGroup) = ClassifyGroups();
        foreach (var w in GCodeReader.LexLine(profile.Startup).WordList)
        {
            if (w.Letter == 'G' && profile.GGroupOf(w.Value) is var gg and >= 0)
            {
                _g[gg] = w.Value;
                ApplyG(MachineProfile.Key(w.Value), null);
            }
            else if (w.Letter == 'M' && profile.MGroupOf(w.Value) is var mg and >= 0)
            {
                _m[mg] = w.Value;
            }
        }

        ClearNonModal();
        UpdateLane();
    }

    /// <summary>Resumes from a known state and position (start from a block: the state after the block before it).</summary>
    public Interpreter(MachineProfile profile, ModalState state, Point3 position)
    {
        _profile = profile;
        (_gCount, _mCount) = (profile.GGroups.Count, profile.MGroups.Count);
        (_g, _m, _gNonModal, _mNonModal) = (new double?[_gCount], new double?[_mCount], new bool[_gCount], new bool[_mCount]);
        _coords = new WorkCoordinates(profile, state.WorkOffset);
        (_motionGroup, _cycleGroup) = ClassifyGroups();
        for (var i = 0; i < _gCount; i++)
        {
            _g[i] = state.GetG(i);
            if (_g[i] is { } v)
            {
                ApplyG(MachineProfile.Key(v), null);
            }
        }

        for (var i = 0; i < _mCount; i++)
        {
            _m[i] = state.GetM(i);
        }

        ClearNonModal();
        (_tool, _h, _d, _speed, _feed, _pos) = (state.Tool, state.LengthOffset, state.CutterComp, state.SpindleSpeed, state.Feed, position);
        if (state.Cycle is { } cycle)
        {
            _cycle.Enter(MachineProfile.Key(cycle), position.Z);
        }

        UpdateLane();
    }

    /// <summary>
    /// Interprets one block. Returns null for empty, comment-only, tape-mark, label (N and a comment) and
    /// program-number-only lines (and for deleted blocks when <see cref="BlockDeleteEnabled"/>). Never throws on
    /// content: what cannot be executed is skipped here and reported by the checker.
    /// </summary>
    public DecodedBlock? Step(GBlock block) => Step(block, null);

    /// <summary><see cref="Step(GBlock)"/>, reporting the block's findings into <paramref name="diagnostics"/>.</summary>
    public DecodedBlock? Step(GBlock block, List<Diagnostic>? diagnostics) => StepCore(block, diagnostics) ? Materialize() : null;

    /// <summary>
    /// Interprets one block for its canonical moves (<see cref="Canon"/>) and state only, without a record: the
    /// allocation-free step of a caller that times or sends the moves. False when the line holds no block.
    /// </summary>
    public bool Execute(GBlock block) => StepCore(block, null);

    /// <summary><see cref="Execute(GBlock)"/>, reporting the block's findings into <paramref name="diagnostics"/> (the preview lists them).</summary>
    public bool Execute(GBlock block, List<Diagnostic>? diagnostics) => StepCore(block, diagnostics);

    /// <summary>
    /// Interprets a block into <see cref="Last"/>, reporting its findings into <paramref name="diagnostics"/> (when
    /// given) and its canonical moves to <see cref="Canon"/> (when set); false when the line holds no block.
    /// </summary>
    internal bool StepCore(GBlock block, List<Diagnostic>? diagnostics)
    {
        if (Canon is not { } canon)
        {
            return StepBlock(block, diagnostics);
        }

        ClearCalls();
        var taken = StepBlock(block, diagnostics);
        canon.EndBlock(Decided());
        return taken;
    }

    /// <summary>What the interpreter decided for the line it took last, and the context it leaves (<see cref="ICanonicalMoves.EndBlock"/>).</summary>
    private CanonBlock Decided() => new()
    {
        Host = HostBlock,
        Position = _pos,
        Offset = _coords.Active,
        UnitScale = _scale,
        Absolute = _absolute,
        ArcCentresAbsolute = _arcAbsolute,
        MotionCode = MotionMode(),
        Plane = _plane,
        FeedMode = _feedMode,
        Feed = _feed,
        InverseTimeLength = _inverseTimeLength,
        SpindleSpeed = _speed,
        LengthMode = _lengthMode,
        LengthOffsetNumber = _h,
        Tool = _tool,
        ExactStop = _exactStopBlock,
        Transforming = _transform != null,
        Compensated = _compensated,
        Corner = _corner,
        AmendedEnd = _amended,
        Hold = _taken || HoldOfBlock == CompensationHold.None ? HoldOfBlock : CompensationHold.Queued, // a comment line keeps the hold
        ArcCentre = _arcCentre,
        ArcClockwise = _arcClockwise,
        Holes = _blockKind == MotionKind.Cycle ? _cycle.LastHoles : null,
        Tables = _coords,
        MotionInBlock = _motionInBlock,
        MachineCoordinates = _machineBlock,
        AxisData = _axisDataBlock,
        Given = _given,
    };

    // Hot loop of a million-line program: compile optimized at once instead of spending the first
    // hundreds of milliseconds in unoptimized tier-0 code waiting for tiering.
    [MethodImpl(MethodImplOptions.AggressiveOptimization)]
    [SkipLocalsInit]
    private bool StepBlock(GBlock block, List<Diagnostic>? diags)
    {
        // Before anything here changes the mode or the work offset the lane's values were written under.
        Resolve();
        _blockKind = MotionKind.None;
        (_corner, _compensated, _amended, _taken) = (null, false, null, false); // a line taken as no block decides nothing
        Canon?.StartBlock(new CanonStart(_pos, _coords.Active, _tool, _coords));
        var words = block.WordList;
        if (words.Count == 0 || block.IsTapeMark || (BlockDeleteEnabled && block.BlockDelete))
        {
            LastHadProgramNumber = block.ProgramNumber.HasValue;
            return false;
        }

        var line = block.LineNumber;
        var wordSpan = System.Runtime.InteropServices.CollectionsMarshal.AsSpan(words);
        if (block.SkipFrom >= 0)
        {
            if (!_profile.SlashInBlock)
            {
                Add(diags, DiagnosticCodes.IllegalCharacter, line, block.SkipColumn, "/");
            }
            else if (BlockDeleteEnabled)
            {
                wordSpan = wordSpan[..block.SkipFrom];
            }
        }

        var sawO = false;
        var anyG = false;                              // most CAM blocks carry no G or M word: skip the group loops
        var anyM = false;
        Span<int> col = stackalloc int[26];          // column of the first word of each letter, 0 = absent
        Span<double> val = stackalloc double[26];
        // Fixed sizes: a constant stackalloc is part of the frame, a variable one costs a stack probe per block.
        Span<double> gIn = stackalloc double[MachineProfile.MaxGroups];
        Span<int> gCol = stackalloc int[MachineProfile.MaxGroups];
        Span<double> mIn = stackalloc double[MachineProfile.MaxGroups];
        Span<int> mCol = stackalloc int[MachineProfile.MaxGroups];
        col.Clear();                                   // SkipLocalsInit: only the "seen" markers need zeroing
        var onlyO = true;
        var effective = false;
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
                if (!(isG ? _gInfo : _mInfo).TryGetValue(w.CodeTimesTen, out var info))
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

                var group = info.Group;
                if (isG ? !anyG : !anyM)
                {
                    // Cleared at the block's first G (or M) word: most blocks have none, and profiles have many groups.
                    (isG ? gCol : mCol).Clear();
                }

                var slotCol = isG ? gCol : mCol;
                if (slotCol[group] != 0)
                {
                    if (diags != null)
                    {
                        var name = (isG ? _profile.GGroups : _profile.MGroups)[group].Name;
                        Add(diags, DiagnosticCodes.ModalGroupConflict, line, w.Column, w.Letter, CodeText(isG ? gIn[group] : mIn[group]), CodeText(w.Value), name);
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
        if (onlyO || (!effective && block.CommentList.Count > 0 && OnlySequenceNumbers(wordSpan)))
        {
            // A program number, or a label: a sequence number naming the comment after it (N10 (FACE1)), not a block.
            return false;
        }

        [MethodImpl(MethodImplOptions.AggressiveInlining)]
        static double? Word(char c, Span<int> col, Span<double> val) => col[c - 'A'] != 0 ? val[c - 'A'] : null;

        // Modal groups first (units, plane, distance, offsets), so that motion in the same block uses them.
        ClearNonModal();
        var codes = new BlockCodes();
        var exactStopOnce = false;
        var compColumn = 0;
        _taken = true;
        if (_comp.Active)
        {
            _comp.NextBlock();
        }

        for (var gi = 0; anyG && gi < _gCount; gi++)
        {
            if (gCol[gi] != 0)
            {
                var key = MachineProfile.Key(gIn[gi]);
                exactStopOnce |= key == 90;
                compColumn = key is 400 or 410 or 420 ? gCol[gi] : compColumn;
                var info = _gInfo[key];
                SetG(gi, gIn[gi]);
                ApplyG(key, Word('P', col, val));
                codes.Add(info, key, gCol[gi]);
                CheckCode(info, col, val, diags, line, gCol[gi]);
            }
        }

        var toolChange = false;
        for (var mi = 0; anyM && mi < _mCount; mi++)
        {
            if (mCol[mi] != 0)
            {
                var key = MachineProfile.Key(mIn[mi]);
                toolChange |= key == 60;
                var info = _mInfo[key];
                SetM(mi, mIn[mi]);
                codes.Read |= info.WordMask;
                CheckCode(info, col, val, diags, line, mCol[mi]);
            }
        }

        if (anyG)
        {
            UpdateCycle(ref codes);
        }

        // Values and their ranges.
        if ((col['F' - 'A'] | col['S' - 'A'] | col['T' - 'A'] | col['H' - 'A'] | col['D' - 'A'] | col['P' - 'A']) != 0)
        {
            TakeValues(col, val, diags, line);
        }

        if (anyG || col['H' - 'A'] != 0)
        {
            UpdateToolLength();
        }

        if (_compRequest >= 0 || (col['D' - 'A'] != 0 && _comp.Active))
        {
            UpdateCompensation(col['D' - 'A'] != 0, diags, line, compColumn != 0 ? compColumn : col['D' - 'A'] != 0 ? col['D' - 'A'] : words[0].Column);
        }
        else if (anyG && _comp.Active && _plane != 17)
        {
            Add(diags, DiagnosticCodes.CompensationNotRunnable, line, words[0].Column, "G" + _plane.ToString(System.Globalization.CultureInfo.InvariantCulture),
                "compensation runs in the XY plane (G17) only", "补偿只在 XY 平面（G17）执行");
        }

        var hasF = col['F' - 'A'] != 0;
        var p = Word('P', col, val);

        var xw = Word('X', col, val);
        var yw = Word('Y', col, val);
        var zw = Word('Z', col, val);
        var iw = Word('I', col, val);
        var jw = Word('J', col, val);
        var kw = Word('K', col, val);
        var rw = Word('R', col, val);
        var (x, y, z, i0, j0, k0, r) = (xw, yw, zw, iw, jw, kw, rw);
        if (_scale != 1.0)
        {
            // Inch program: every length becomes millimetres here, so positions, offsets and times are millimetres.
            (x, y, z, i0, j0, k0, r) = (xw * _scale, yw * _scale, zw * _scale, iw * _scale, jw * _scale, kw * _scale, rw * _scale);
        }
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

        if (codes.Dwell)
        {
            kind = MotionKind.Dwell;
            usedP = p.HasValue;
            // X of G04 is seconds, not a length: the word as written, never scaled by G20.
            seconds = ConvertDwell(p, xw, y, z, col, diags, line, codes.DwellColumn);
        }
        else if (codes.Data is 510 or 511 or 680)
        {
            SetTransform(codes.Data, x, y, z, i0, j0, k0, p, r, wordSpan, diags, line, words[0].Column);
        }
        else if (codes.Data != 0)
        {
            // The axis words are data: offsets change, nothing moves.
            if (diags != null && (col['A' - 'A'] | col['B' - 'A'] | col['C' - 'A']) != 0)
            {
                CheckRotaryOffset(codes.Data, Word('L', col, val), col, val, diags, line);
            }

            SetData(codes.Data, x, y, z, Word('L', col, val), p, r);
        }
        else if (codes.Reference != 0)
        {
            RefuseUnderCompensation("G" + ModalState.Num(codes.Reference / 10.0), diags, line, words[0].Column);
            (end, kind, length, seconds) = ConvertReference(codes.Reference, start, x, y, z, hasAxes);
        }
        else if (hasAxes && _cycle.Active && !codes.MachineCoordinates)
        {
            if (_feedMode == 93)
            {
                Add(diags, DiagnosticCodes.CycleInInverseTime, line, codes.CycleColumn != 0 ? codes.CycleColumn : words[0].Column, CodeText(_cycle.Code / 10.0));
            }

            RefuseUnderCompensation("canned cycle", diags, line, words[0].Column);
            if (_transform != null)
            {
                (x, y, z, r) = TransformCycleWords(x, y, z, r, diags, line, codes.CycleColumn != 0 ? codes.CycleColumn : words[0].Column);
            }

            (end, kind, length, seconds) = Holes(start, x, y, z, r, col, val, diags, line, ref codes);
        }
        else if (hasAxes || ((codes.MotionInBlock is 2 or 3) && (i0.HasValue || j0.HasValue || k0.HasValue)))
        {
            var mode = codes.OtherMotion ? 4 : MotionMode();
            var modeCol = codes.MotionInBlock >= 0 ? codes.MotionColumn : words[0].Column;
            double cornerLength = 0;
            if (codes.MachineCoordinates)
            {
                RefuseUnderCompensation("G53", diags, line, words[0].Column);
                end = MachineTarget(start, x, y, z);
            }
            else if (_comp.Active)
            {
                // Incremental words count from the programmed point, not from the tool beside it.
                end = Target(_comp.Programmed(start), x, y, z);
                if (mode is not (2 or 3))
                {
                    (end, cornerLength) = Compensate(start, end, mode, (col['A' - 'A'] | col['B' - 'A'] | col['C' - 'A']) != 0, diags, line, modeCol);
                    start = _amended ?? start; // an inside corner: the move starts where the offset paths cross
                }
            }
            else
            {
                end = Target(start, x, y, z);
            }

            switch (mode)
            {
                case 0:
                    kind = MotionKind.Rapid;
                    length = MeasureMoves ? start.DistanceTo(end) + cornerLength : 0;
                    seconds = RapidTime(length);
                    break;
                case 1:
                case 4:
                    kind = MotionKind.Linear;
                    length = MeasureMoves ? start.DistanceTo(end) + cornerLength : 0;
                    seconds = FeedTime(length, hasF, diags, line, modeCol, 1);
                    break;
                case 2:
                case 3:
                    usedArcWords = true;
                    codes.Read |= MotionWords();
                    var cw = mode == 2;
                    if (_transform != null && !codes.MachineCoordinates)
                    {
                        (i0, j0, k0, r, cw) = TransformArc(cw, i0, j0, k0, r, diags, line, modeCol);
                    }

                    kind = cw ? MotionKind.ArcCw : MotionKind.ArcCcw;
                    // Under compensation the arc is the programmed one (from the programmed point), then offset.
                    (center, length) = ArcGeometry.Solve(cw, _plane, _comp.Active ? _comp.Programmed(start) : start, end, i0, j0, k0, r, _arcAbsolute && _transform == null, _coords.Active,
                        _profile.ArcTolerance, _scale, diags, line, modeCol, col, out var radii);
                    if (diags != null && Math.Abs(radii.Start - radii.End) > 0.001 / _scale)
                    {
                        WarnOffCircle(radii, block, wordSpan, diags, line, modeCol);
                    }
                    if (_comp.Active)
                    {
                        (end, length) = CompensateArc(start, end, center, cw, length, (col['A' - 'A'] | col['B' - 'A'] | col['C' - 'A']) != 0, diags, line, modeCol);
                        start = _amended ?? start;
                    }

                    (_arcCentre, _arcClockwise) = (center, cw);
                    seconds = FeedTime(length, hasF, diags, line, modeCol, mode);
                    break;
                default:
                    // Axis words with no motion mode in force (G80 where it ends the motion mode, or none at power-on).
                    Add(diags, DiagnosticCodes.NoMotionMode, line, words[0].Column);
                    end = start;
                    break;
            }
        }
        else if (codes.MotionInBlock is 2 or 3)
        {
            Add(diags, DiagnosticCodes.MotionWithoutAxes, line, codes.MotionColumn, codes.MotionInBlock == 2 ? "02" : "03");
            usedArcWords = true;
        }

        if (toolChange && _profile.ToolChangePosition is { } tc)
        {
            // M06's default hook, after the block's own move: to the tool change position in machine coordinates, Z
            // first, then X and Y.
            var from = end;
            end = new Point3(tc[0], tc[1], tc[2]);
            kind = kind == MotionKind.None ? MotionKind.Rapid : kind;
            var hook = MeasureMoves ? Math.Abs(end.Z - from.Z) + Math.Sqrt(((end.X - from.X) * (end.X - from.X)) + ((end.Y - from.Y) * (end.Y - from.Y))) : 0;
            length += hook;
            seconds += RapidTime(hook);
        }

        if (diags != null && (anyG || anyM || col['T' - 'A'] != 0 || _extendedSetLine > 0))
        {
            CheckDialect(codes, toolChange, kind, start, x, y, z, col, val, wordSpan, diags, line);
        }

        // Most blocks carry no parameter word: eight loads instead of the report's loop.
        if (diags != null && (col['I' - 'A'] | col['J' - 'A'] | col['K' - 'A'] | col['R' - 'A'] | col['P' - 'A'] | col['Q' - 'A'] | col['L' - 'A'] | col['E' - 'A']) != 0)
        {
            ReportUnusedWords(col, codes.Read, usedArcWords, usedP || (codes.Read & (1 << ('P' - 'A'))) != 0, effective, diags, line);
        }

        _exactStopBlock = (_exactStop || exactStopOnce) && kind is not (MotionKind.None or MotionKind.Dwell);
        if (_transform != null && (kind != MotionKind.None || codes.Data != 0) && codes.Data is not (510 or 511 or 680))
        {
            // Blocks that moved (or changed offsets) leave the untransformed position where their end is.
            _programPos = _transform.Inverse(end - _coords.Active);
        }

        var inverseTime = _feedMode == 93 && kind is MotionKind.Linear or MotionKind.ArcCw or MotionKind.ArcCcw;
        if (inverseTime)
        {
            // G93: the host sends each move's feed per minute, its length times F (the move takes 1/F minute).
            _inverseTimeLength = kind == MotionKind.Linear ? start.DistanceTo(end) : length;
        }

        // G95: every move (and a lone F) goes with its feed per minute at the spindle speed now in force.
        var perRevolution = _feedMode == 95 && (kind is MotionKind.Linear or MotionKind.ArcCw or MotionKind.ArcCcw || col['F' - 'A'] != 0);
        HostBlock = _scale != 1.0 || codes.Host || _exactStopBlock || inverseTime || perRevolution || (_transform != null && kind is not (MotionKind.None or MotionKind.Dwell)) || col['T' - 'A'] != 0 || col['H' - 'A'] != 0 || col['D' - 'A'] != 0 ||
            kind == MotionKind.Cycle || (usedArcWords && _arcAbsolute) || (anyM && MHost(mIn, mCol)) || _compensated;
        _pos = end;
        UpdateLane();
        _blockKind = kind;
        if (Canon is { } sink)
        {
            (_given, _motionInBlock, _machineBlock, _axisDataBlock) = (new CanonAxes(xw * _scale, yw * _scale, zw * _scale, Word('A', col, val), Word('B', col, val), Word('C', col, val),
                iw * _scale, jw * _scale, kw * _scale, rw * _scale), codes.MotionInBlock, codes.MachineCoordinates, codes.Data != 0);
            if (HostBlock || anyG || anyM || (col['T' - 'A'] | col['S' - 'A'] | col['F' - 'A'] | col['H' - 'A']) != 0)
            {
                EmitCalls(sink, wordSpan, col, val, gCol, mCol, anyG, anyM);
            }

            if (kind != MotionKind.None)
            {
                sink.Motion(new CanonMotion(line, kind, start, end, center, length, seconds, _feed));
            }
        }

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
        last.X = xw;
        last.Y = yw;
        last.Z = zw;
        last.I = iw;
        last.J = jw;
        last.K = kw;
        last.R = rw;
        last.F = Word('F', col, val);
        last.S = Word('S', col, val);
        last.T = Word('T', col, val);
        last.H = Word('H', col, val);
        last.D = Word('D', col, val);
        last.P = p;
        last.Motion = kind;
        last.Start = start;
        last.End = end;
        last.Center = center;
        last.Length = length;
        last.DurationSeconds = seconds;
        return true;
    }

    /// <summary>True when every word is an N (a label, with its comment): looked at only for blocks without an effective word.</summary>
    private static bool OnlySequenceNumbers(ReadOnlySpan<GWord> words)
    {
        foreach (ref readonly var w in words)
        {
            if (w.Letter != 'N')
            {
                return false;
            }
        }

        return true;
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
        Parameter,   // N, O, I, J, K, R, P, Q, L, E: not an effective function on their own
        Effective,   // axes, F, S, T, H, D...: the block does something
    }
}
