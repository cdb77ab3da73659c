namespace PmacStream.GCode;

/// <summary>
/// Where the interpreter says what each block does, as it decides it (rs274ngc's canonical machining functions:
/// STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED, DWELL): the state the block starts from, the steps of a canned cycle
/// or a reference return, then the block's motion. Set on <see cref="Interpreter.Canon"/>; every block the
/// interpreter takes calls <see cref="StartBlock"/> first, so a consumer needs no call before
/// <see cref="Interpreter.Execute"/> and cannot miss a block. All positions are machine coordinates in millimetres.
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
}

/// <summary>The state a block starts from (<see cref="ICanonicalMoves.StartBlock"/>).</summary>
/// <param name="Position">Where the machine is, machine coordinates.</param>
/// <param name="Offset">The offset from program to machine coordinates in force (work offset, G52, G92, tool length).</param>
/// <param name="Tool">The tool T selected last.</param>
public readonly record struct CanonStart(Point3 Position, Point3 Offset, int Tool);

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
    /// An inside corner under compensation: the compensated move before this one ends here, not where it was reported
    /// to end (rs274ngc's one queued move); this move starts here. Whoever sends or draws moves holds the last
    /// compensated one until the next move is known. Null for any other block.
    /// </summary>
    public Point3? AmendedEnd { get; init; }

    /// <summary>The last arc's centre (a mirror may have reversed its direction: <see cref="ArcClockwise"/>).</summary>
    public Point3? ArcCentre { get; init; }

    /// <summary>Whether the last arc ran clockwise, as the machine runs it.</summary>
    public bool ArcClockwise { get; init; }

    /// <summary>A cycle block's holes; null for any other block.</summary>
    public CycleHoles? Holes { get; init; }

    /// <summary>The work offset and tool tables and the G52/G92 shifts as the block left them (live: read them at once).</summary>
    public WorkCoordinates Tables { get; init; }
}
