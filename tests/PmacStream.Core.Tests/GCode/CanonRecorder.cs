using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>Keeps every canonical call the interpreter makes, in order, for tests to read.</summary>
internal sealed class CanonRecorder : ICanonicalMoves
{
    /// <summary>The states blocks started from.</summary>
    public List<CanonStart> Starts { get; } = [];

    /// <summary>The steps of cycles and reference returns.</summary>
    public List<HostMove> Steps { get; } = [];

    /// <summary>The blocks' motions.</summary>
    public List<CanonMotion> Motions { get; } = [];

    public void StartBlock(in CanonStart start) => Starts.Add(start);

    public void Step(in HostMove step) => Steps.Add(step);

    public void Motion(in CanonMotion motion) => Motions.Add(motion);
}
