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
