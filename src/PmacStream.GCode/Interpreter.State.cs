namespace PmacStream.GCode;

/// <summary>
/// What the interpreter tells its callers after a block: the modal state and position, the modes, offsets and units
/// the host conversion reads, the switches a caller sets (block delete, measuring, recording), and the last block
/// as a record.
/// </summary>
public sealed partial class Interpreter
{
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

    /// <summary>When true, blocks starting with <c>/</c> are skipped (the operator's block-delete switch), and with it the part of a block after a <c>/</c> inside it where the profile allows that.</summary>
    public bool BlockDeleteEnabled { get; set; }

    /// <summary>
    /// When set, every block's canonical moves go here as the interpreter decides them: the state it starts from, the
    /// steps of its cycle holes or reference return, its motion (the host sends them, the ETA times them).
    /// </summary>
    public ICanonicalMoves? Canon { get; set; }

    /// <summary>
    /// The last block is one the host rewrites before the controller sees it: program units other than millimetres,
    /// a code the host converts or whose words a library routine reads (G04, G10, G43/G44, G52, G92, G53, M06, M19,
    /// G64 ...), a cycle or reference return, T/H/D words, or an arc with absolute centres.
    /// </summary>
    internal bool HostBlock { get; private set; }

    /// <summary>The offset from program to machine coordinates in force (work offset, G52, G92, tool length).</summary>
    public Point3 ActiveOffset => _coords.Active;

    /// <summary>The work coordinates (offsets, shifts, tool table) as the program left them.</summary>
    public WorkCoordinates Coordinates => _coords;

    /// <summary>Program length units to millimetres: 25.4 in G20, else 1.</summary>
    internal double UnitScale => _scale;

    /// <summary>Whether I/J/K are absolute (G90.1).</summary>
    internal bool ArcCentresAbsolute => _arcAbsolute;

    /// <summary>Whether G90 is in force.</summary>
    internal bool AbsoluteMode => _absolute;

    /// <summary>The motion code in force (0..3 for G00..G03, 4 other moves, -1 none).</summary>
    internal int MotionCode => MotionMode();

    /// <summary>The tool length code in force: 43, 44 or 0.</summary>
    internal int LengthMode => _lengthMode;

    /// <summary>The feed in force in program units (per minute, per revolution or inverse time as the feed mode says).</summary>
    internal double? FeedValue => _feed;

    /// <summary>The feed mode code in force (93, 94, 95).</summary>
    internal int FeedMode => _feedMode;

    /// <summary>The tool T selected last.</summary>
    internal int Tool => _tool;

    /// <summary>The tool length offset number H in force.</summary>
    internal int LengthOffsetNumber => _h;

    /// <summary>The codes used so far that the controller cannot run yet (<see cref="ControllerSupport.NotYet"/>), with the line of their first use.</summary>
    public IReadOnlyDictionary<string, int> NotYetCodes => _notYet;

    /// <summary>
    /// Whether straight moves get their length (and so a duration). A caller that only wants the diagnostics (the
    /// splitter's check) turns it off: a square root per block is a tenth of the checker's time. Arcs are always
    /// measured, because their geometry is checked.
    /// </summary>
    public bool MeasureMoves
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
    public bool RecordBlocks
    {
        get => _recordBlocks;
        set
        {
            _recordBlocks = value;
            UpdateLane();
        }
    }

    /// <summary>The line given to the last <see cref="StepCore"/> carried an O program number (saves the checker a second scan of the words).</summary>
    internal bool LastHadProgramNumber { get; private set; }

    /// <summary>The last interpreted block, without allocating (the checker's hot path when nothing is stored).</summary>
    public ref readonly LastBlock Last => ref _last;

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

    private ModalState Snapshot()
    {
        if (_dirty || _snapshot is null)
        {
            _snapshot = new ModalState
            {
                G = CodeValues.CopyOf(_g),
                M = CodeValues.CopyOf(_m),
                Tool = _tool, LengthOffset = _h, CutterComp = _d, SpindleSpeed = _speed, Feed = _feed,
            };
            _dirty = false;
        }

        return _snapshot;
    }

    /// <summary>The fields of a decoded block without the allocation (<see cref="DecodedBlock"/> names them alike).</summary>
    public struct LastBlock
    {
        /// <summary>The source line.</summary>
        public int Line;

        /// <summary>The line's first byte in the source.</summary>
        public long ByteOffset;

        /// <summary>The N word.</summary>
        public double? N;

        /// <summary>The line starts with a block delete slash.</summary>
        public bool BlockDelete;

        /// <summary>Axis words as written (program units).</summary>
        public double? X, Y, Z;

        /// <summary>Arc centre words and the radius as written.</summary>
        public double? I, J, K, R;

        /// <summary>Feed, spindle speed, tool, length offset, cutter compensation and P words as written.</summary>
        public double? F, S, T, H, D, P;

        /// <summary>What the block moved.</summary>
        public MotionKind Motion;

        /// <summary>Where the block started and ended (machine coordinates, millimetres).</summary>
        public Point3 Start, End;

        /// <summary>An arc's centre.</summary>
        public Point3? Center;

        /// <summary>The path's length in millimetres and its time.</summary>
        public double Length, DurationSeconds;
    }
}
