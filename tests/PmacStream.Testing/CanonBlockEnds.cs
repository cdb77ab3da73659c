using PmacStream.GCode;

namespace PmacStream.Testing;

/// <summary>
/// Where the interpreter's canonical moves say every moving block ends (machine coordinates, millimetres): what the
/// position proof and the rs274 comparison hold the controller and LinuxCNC to.
/// </summary>
public sealed class CanonBlockEnds : ICanonicalMoves
{
    private readonly List<(int Line, Point3 End, MotionKind Kind)> _ends = [];
    private bool _amend = true;

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
        var ends = new CanonBlockEnds { _amend = amend };
        var interp = new Interpreter(profile) { BlockDeleteEnabled = blockDelete, Canon = ends };
        while (reader.Read())
        {
            interp.Execute(reader.Current);
        }

        return ends._ends;
    }

    public void StartBlock(in CanonStart start)
    {
    }

    public void Step(in HostMove step)
    {
    }

    public void Motion(in CanonMotion motion) => _ends.Add((motion.Line, motion.End, motion.Kind));

    /// <summary>An inside corner under compensation moves the end of the move before this block's back (the one move held).</summary>
    public void EndBlock(in CanonBlock block)
    {
        if (_amend && block.AmendedEnd is { } end && _ends.Count >= 2)
        {
            var held = _ends[^2];
            _ends[^2] = (held.Line, end, held.Kind);
        }
    }
}
