namespace PmacStream.GCode;

/// <summary>
/// Where the interpreter says what each block does, as it decides it (rs274ngc's canonical machining functions:
/// STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED, DWELL, SELECT_TOOL, CHANGE_TOOL, SET_SPINDLE_SPEED, FLOOD_ON,
/// PROGRAM_STOP ...): the state the block starts from, its settings and codes in the order written, the steps of a
/// canned cycle or a reference return, the block's motion, then what it decided. Set on <see cref="Interpreter.Canon"/>; every block the
/// interpreter takes calls <see cref="StartBlock"/> first, so a consumer needs no call before
/// <see cref="Interpreter.Execute(GBlock)"/> and cannot miss a block. All positions are machine coordinates in millimetres.
/// </summary>
public interface ICanonicalMoves
{
    /// <summary>A line begins, before anything in it changes the state: where the machine is, what is in force.</summary>
    void StartBlock(in CanonStart start);

    /// <summary>One step of a canned cycle's holes or of a reference return (G28/G30), in the order it runs.</summary>
    void Step(in HostMove step);

    /// <summary>The block's motion as a whole (a cycle block's holes together), once its steps are given.</summary>
    void Motion(in CanonMotion motion);

    /// <summary>
    /// The line is taken: what the interpreter decided for it and the modal context it leaves (<see cref="CanonBlock"/>).
    /// Called for every line <see cref="StartBlock"/> began, a line that holds no block too (its record then repeats the
    /// state in force), so a consumer holds the interpreter's last word without asking the interpreter again.
    /// </summary>
    void EndBlock(in CanonBlock block)
    {
    }

    // The line's settings and codes, in the order the line wrote them, after StartBlock and before Motion and EndBlock
    // (rs274ngc's SELECT_TOOL, CHANGE_TOOL, SET_SPINDLE_SPEED, START_SPINDLE_CLOCKWISE, FLOOD_ON, PROGRAM_STOP,
    // DWELL...). Only what the interpreter took: a code it refused (unknown, a second of its group) is not called.
    // A consumer that needs none of them (the ETA, the preview) implements none.

    /// <summary>SELECT_TOOL: the line's T word, the tool the next change takes.</summary>
    void SelectTool(int tool)
    {
    }

    /// <summary>CHANGE_TOOL: M06, to tool <paramref name="tool"/> (the routine reads the tool it changes to).</summary>
    void ChangeTool(int tool, in CanonCode code)
    {
    }

    /// <summary>SET_SPINDLE_SPEED: the line's S word, in revolutions per minute.</summary>
    void SetSpindleSpeed(double speed)
    {
    }

    /// <summary>SET_FEED_RATE: the line's F word, in program units as the feed mode in force reads it.</summary>
    void SetFeedRate(double feed)
    {
    }

    /// <summary>START_SPINDLE_CLOCKWISE, START_SPINDLE_COUNTERCLOCKWISE, STOP_SPINDLE_TURNING, ORIENT_SPINDLE.</summary>
    void Spindle(SpindleCall call, in CanonCode code)
    {
    }

    /// <summary>MIST_ON, FLOOD_ON, through-tool coolant on, and their offs.</summary>
    void Coolant(CoolantCall call, in CanonCode code)
    {
    }

    /// <summary>PROGRAM_STOP (M00), OPTIONAL_PROGRAM_STOP (M01), PROGRAM_END (M02, M30).</summary>
    void ProgramStop(ProgramStopCall call, in CanonCode code)
    {
    }

    /// <summary>DWELL: G04, for <paramref name="seconds"/> (P in the profile's unit, or X in seconds).</summary>
    void Dwell(double seconds)
    {
    }

    /// <summary>
    /// USE_TOOL_LENGTH_OFFSET: G43/G44 with length offset <paramref name="number"/> (<paramref name="mode"/> 43 or 44),
    /// or G49 (0); also an H word while G43/G44 is in force.
    /// </summary>
    void UseToolLengthOffset(int mode, int number)
    {
    }

    /// <summary>G10 set work offset <paramref name="key"/> (540 G54 ... 5410+P G54.1 P) to <paramref name="offset"/>.</summary>
    void SetWorkOffset(int key, Point3 offset)
    {
    }

    /// <summary>G10 L2 P0 of a profile with FANUC's external work offset: it is now <paramref name="offset"/>.</summary>
    void SetExternalOffset(Point3 offset)
    {
    }

    /// <summary>G10 set tool <paramref name="tool"/>'s length: it is now <paramref name="length"/>.</summary>
    void SetToolLength(int tool, double length)
    {
    }

    /// <summary>G52: the local shift on the axes the line named, in millimetres (null: not named).</summary>
    void SetLocalShift(double? x, double? y, double? z)
    {
    }

    /// <summary>G92: the shift it gives on the axes the line named (null: not named).</summary>
    void SetShift(double? x, double? y, double? z)
    {
    }

    /// <summary>G92.1/G92.2: the G92 shift is cleared.</summary>
    void CancelShift()
    {
    }

    /// <summary>G54.1 P or G154 P: extended work offset <paramref name="number"/> is selected.</summary>
    void SelectExtendedWorkOffset(int number)
    {
    }

    /// <summary>
    /// A code the controller runs itself: a mode it keeps (G17, G54, G90, G64...) or a routine of the library, with
    /// the words the routine reads (<see cref="CanonCode.Words"/>).
    /// </summary>
    void Code(in CanonCode code)
    {
    }
}

/// <summary>
/// A G or M code as the controller gets it: its letter, its number, and the words its library routine reads, in the
/// order the profile lists them (a word the line did not give is left out; lengths in millimetres).
/// </summary>
public readonly ref struct CanonCode(char letter, double number, ReadOnlySpan<CanonWord> words)
{
    /// <summary>G or M.</summary>
    public char Letter { get; } = letter;

    /// <summary>The code's number (54.1 for G54.1).</summary>
    public double Number { get; } = number;

    /// <summary>The words its library routine reads, as the line gave them (lengths in millimetres).</summary>
    public ReadOnlySpan<CanonWord> Words { get; } = words;
}

/// <summary>One word a library routine reads: its letter and value.</summary>
public readonly record struct CanonWord(char Letter, double Value);

/// <summary>What a spindle code does (<see cref="ICanonicalMoves.Spindle"/>).</summary>
public enum SpindleCall
{
    /// <summary>M03.</summary>
    Clockwise,

    /// <summary>M04.</summary>
    CounterClockwise,

    /// <summary>M05.</summary>
    Stop,

    /// <summary>M19.</summary>
    Orient,
}

/// <summary>What a coolant code does (<see cref="ICanonicalMoves.Coolant"/>).</summary>
public enum CoolantCall
{
    /// <summary>M07.</summary>
    Mist,

    /// <summary>M08.</summary>
    Flood,

    /// <summary>M88 (Haas): through the spindle.</summary>
    ThroughTool,

    /// <summary>M09.</summary>
    Off,

    /// <summary>M89 (Haas).</summary>
    ThroughToolOff,
}

/// <summary>What a program stop code does (<see cref="ICanonicalMoves.ProgramStop"/>).</summary>
public enum ProgramStopCall
{
    /// <summary>M00: PROGRAM_STOP.</summary>
    Stop,

    /// <summary>M01: OPTIONAL_PROGRAM_STOP.</summary>
    OptionalStop,

    /// <summary>M02 or M30: PROGRAM_END.</summary>
    End,
}

/// <summary>
/// The axis and arc words of a line as the program gave them, in millimetres (rotary A/B/C as written): what the host
/// sends for a plain move, which the controller runs in its own modes and offsets. Null: the line did not give it.
/// </summary>
public readonly record struct CanonAxes(double? X, double? Y, double? Z, double? A, double? B, double? C, double? I, double? J, double? K, double? R)
{
    /// <summary>The line named an axis.</summary>
    public bool Any => X.HasValue || Y.HasValue || Z.HasValue || A.HasValue || B.HasValue || C.HasValue;

    /// <summary>The line gave an arc's centre.</summary>
    public bool AnyCentre => I.HasValue || J.HasValue || K.HasValue;
}

/// <summary>The state a block starts from (<see cref="ICanonicalMoves.StartBlock"/>).</summary>
/// <param name="Position">Where the machine is, machine coordinates.</param>
/// <param name="Offset">The offset from program to machine coordinates in force (work offset, G52, G92, tool length).</param>
/// <param name="Tool">The tool T selected last.</param>
/// <param name="Tables">The work offset and tool tables and the G52/G92 shifts before the line (live: read them at once).</param>
public readonly record struct CanonStart(Point3 Position, Point3 Offset, int Tool, WorkCoordinates Tables);

/// <summary>A block's motion (<see cref="ICanonicalMoves.Motion"/>): a traverse, a feed, an arc, a dwell, a cycle's holes.</summary>
/// <param name="Line">The block's source line.</param>
/// <param name="Kind">What moves: never <see cref="MotionKind.None"/>.</param>
/// <param name="Start">Where the block starts.</param>
/// <param name="End">Where it ends.</param>
/// <param name="Centre">An arc's centre (under compensation the programmed one).</param>
/// <param name="Length">The path's length in millimetres (0 when the interpreter does not measure straight moves).</param>
/// <param name="Seconds">Its time at the programmed feed, or the dwell's.</param>
/// <param name="Feed">The feed in force after the block, in program units.</param>
public readonly record struct CanonMotion(int Line, MotionKind Kind, Point3 Start, Point3 End, Point3? Centre, double Length, double Seconds, double? Feed);

/// <summary>
/// What the interpreter decided for one line and the modal context it leaves (<see cref="ICanonicalMoves.EndBlock"/>):
/// the record host conversion, the preview and the start planner work from, instead of the interpreter's fields. All
/// positions are machine coordinates in millimetres; values in program units say so.
/// </summary>
public readonly record struct CanonBlock
{
    /// <summary>
    /// The host rewrites the block before the controller sees it: program units other than millimetres, a code the
    /// host converts or whose words a library routine reads, a cycle or reference return, T/H/D words, an arc with
    /// absolute centres, a compensated or transformed move, inverse time or feed per revolution.
    /// </summary>
    public bool Host { get; init; }

    /// <summary>Where the block left the machine.</summary>
    public Point3 Position { get; init; }

    /// <summary>The offset from program to machine coordinates in force after it (work offset, G52, G92, tool length).</summary>
    public Point3 Offset { get; init; }

    /// <summary>Program length units to millimetres: 25.4 in G20, else 1.</summary>
    public double UnitScale { get; init; }

    /// <summary>G90 in force (else G91).</summary>
    public bool Absolute { get; init; }

    /// <summary>I/J/K are absolute (G90.1).</summary>
    public bool ArcCentresAbsolute { get; init; }

    /// <summary>The motion code in force: 0..3 for G00..G03, 4 another move, -1 none.</summary>
    public int MotionCode { get; init; }

    /// <summary>The plane in force: 17, 18 or 19.</summary>
    public int Plane { get; init; }

    /// <summary>The feed mode in force: 93 inverse time, 94 per minute, 95 per revolution.</summary>
    public int FeedMode { get; init; }

    /// <summary>The feed in force, in program units as <see cref="FeedMode"/> reads it.</summary>
    public double? Feed { get; init; }

    /// <summary>Under G93: the last feed move's path length in millimetres (arcs along the arc).</summary>
    public double InverseTimeLength { get; init; }

    /// <summary>The spindle speed in force.</summary>
    public double SpindleSpeed { get; init; }

    /// <summary>The tool length code in force: 43, 44 or 0 (G49).</summary>
    public int LengthMode { get; init; }

    /// <summary>The tool length offset number H in force.</summary>
    public int LengthOffsetNumber { get; init; }

    /// <summary>The tool T selected last.</summary>
    public int Tool { get; init; }

    /// <summary>The block moved and must end at rest before the next starts (G61 in force, or G09 in it).</summary>
    public bool ExactStop { get; init; }

    /// <summary>A programmable transformation (G51.1, G51, G68) is in force: the positions are the transformed ones.</summary>
    public bool Transforming { get; init; }

    /// <summary>The block's move was compensated (G41/G42): its positions are the tool's, not the words'.</summary>
    public bool Compensated { get; init; }

    /// <summary>The corner a compensated move went around first; null when it went straight.</summary>
    public CompensationCorner? Corner { get; init; }

    /// <summary>
    /// An inside corner under compensation: the compensated XY move held (<see cref="CompensationHold.Held"/>) ends at
    /// this X and Y, not where it was reported to end, and so does every move queued behind it
    /// (<see cref="CompensationHold.Queued"/>: a plunge or retract runs at this X and Y, its own Z); this move starts
    /// here. Z is the tool's when this move starts (the last queued move's), not the held move's: rewrite X and Y only
    /// (<see cref="AmendedMove.MovedTo"/>). Null for any other block.
    /// </summary>
    public Point3? AmendedEnd { get; init; }

    /// <summary>
    /// The block's part in the hold under G41/G42, the one decision every consumer applies (rs274ngc's queue): the
    /// compensated XY move whose end the next XY move may still move (<see cref="CompensationHold.Held"/>: what was held
    /// before is final, after this block's <see cref="AmendedEnd"/>), a block queued behind it
    /// (<see cref="CompensationHold.Queued"/>: its moves, all out of the XY plane, stay held with it), or none (what
    /// was held is final). The hold is bounded: at most <see cref="Interpreter.MaxHeldCompensationBlocks"/> blocks after
    /// the move (an inside corner after that is refused, E135).
    /// </summary>
    public CompensationHold Hold { get; init; }

    /// <summary>The last arc's centre (a mirror may have reversed its direction: <see cref="ArcClockwise"/>).</summary>
    public Point3? ArcCentre { get; init; }

    /// <summary>Whether the last arc ran clockwise, as the machine runs it.</summary>
    public bool ArcClockwise { get; init; }

    /// <summary>A cycle block's holes; null for any other block.</summary>
    public CycleHoles? Holes { get; init; }

    /// <summary>The work offset and tool tables and the G52/G92 shifts as the block left them (live: read them at once).</summary>
    public WorkCoordinates Tables { get; init; }

    /// <summary>The motion code the line wrote: 0..3 for G00..G03, -1 none.</summary>
    public int MotionInBlock { get; init; }

    /// <summary>G53: the line's move is in machine coordinates.</summary>
    public bool MachineCoordinates { get; init; }

    /// <summary>A code of the line took its axis words as data (G10, G52, G92, G51, G68...): nothing moves.</summary>
    public bool AxisData { get; init; }

    /// <summary>The line's axis and arc words as given, in millimetres (<see cref="CanonAxes"/>).</summary>
    public CanonAxes Given { get; init; }
}

/// <summary>A block's part in the moves held under G41/G42 until the next XY move decides where they end (<see cref="CanonBlock.Hold"/>).</summary>
public enum CompensationHold : byte
{
    /// <summary>Not held: the moves held before it (if any) are final, and so are its own.</summary>
    None,

    /// <summary>Its move (its last, after an outside corner's arc) is the compensated XY move held now; the moves held before are final.</summary>
    Held,

    /// <summary>Queued behind the move held: its moves (Z only, no XY motion) end at the held move's X and Y, wherever that ends.</summary>
    Queued,
}
