using PmacStream.GCode;

namespace PmacStream.Testing;

/// <summary>
/// Where the interpreter's canonical moves say every moving block ends (machine coordinates, millimetres): what the
/// position proof and the rs274 comparison hold the controller and LinuxCNC to.
/// </summary>
public sealed class CanonBlockEnds : ICanonicalMoves
{
    private readonly List<(int Line, Point3 End, MotionKind Kind)> _ends = [];
    private readonly List<(int Line, Point3 End, MotionKind Kind)> _block = [];
    private readonly HeldMoves<(int Line, Point3 End, MotionKind Kind)> _held;
    private readonly bool _amend;

    private CanonBlockEnds(bool amend)
    {
        _amend = amend;
        // The move held and the moves queued behind it end at the crossing on X and Y (each its own Z).
        _held = new((m, crossing, _) => _amend ? (m.Line, AmendedMove.MovedTo(m.End, crossing), m.Kind) : m);
    }

    /// <summary>
    /// The motions of the program at <paramref name="path"/>, in order; <paramref name="amend"/> false leaves a move
    /// before an inside corner where it was reported before the next move was known (to show a comparison can fail).
    /// </summary>
    public static List<(int Line, Point3 End, MotionKind Kind)> Of(string path, MachineProfile profile, bool blockDelete = false, bool amend = true)
    {
        using var reader = GCodeReader.Open(path);
        return Of(reader, profile, blockDelete, amend);
    }

    /// <summary>The motions of the lines <paramref name="reader"/> gives (an expansion's, say), in order.</summary>
    public static List<(int Line, Point3 End, MotionKind Kind)> Of(GCodeReader reader, MachineProfile profile, bool blockDelete = false, bool amend = true)
    {
        var ends = new CanonBlockEnds(amend);
        var interp = new Interpreter(profile) { BlockDeleteEnabled = blockDelete, Canon = ends };
        while (reader.Read())
        {
            interp.Execute(reader.Current);
        }

        ends._held.Flush(ends._ends);
        return ends._ends;
    }

    public void StartBlock(in CanonStart start) => _block.Clear();

    public void Step(in HostMove step)
    {
    }

    public void Motion(in CanonMotion motion) => _block.Add((motion.Line, motion.End, motion.Kind));

    /// <summary>An inside corner under compensation moves the end of the move held, and of the moves queued behind it, to the crossing.</summary>
    public void EndBlock(in CanonBlock block)
    {
        _held.Take(block, _block, _ends);
        _block.Clear();
    }
}
