using PmacStream.GCode;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Where the interpreter's canonical moves say every moving block ends (machine coordinates, millimetres): what the
/// position proof and the rs274 comparison hold the controller and LinuxCNC to.
/// </summary>
internal sealed class CanonBlockEnds : ICanonicalMoves
{
    private readonly List<(int Line, Point3 End, MotionKind Kind)> _ends = [];

    /// <summary>The motions of the program at <paramref name="path"/>, in order.</summary>
    public static List<(int Line, Point3 End, MotionKind Kind)> Of(string path, MachineProfile profile, bool blockDelete = false)
    {
        var ends = new CanonBlockEnds();
        var interp = new Interpreter(profile) { BlockDeleteEnabled = blockDelete, Canon = ends };
        using var reader = GCodeReader.Open(path);
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
}
