namespace PmacStream.GCode;

/// <summary>
/// Two consumers of one interpreter's canonical calls, in order: each call goes to <see cref="First"/>, then to
/// <see cref="Second"/>. One pass over a program can then feed both the host's conversion of the blocks it sends and
/// the store's decoded records, from the same decisions.
/// </summary>
public sealed class CanonFanOut : ICanonicalMoves
{
    /// <summary>Calls <paramref name="first"/> (the host conversion, whose lines the split takes after the block), then <paramref name="second"/>.</summary>
    public CanonFanOut(ICanonicalMoves first, ICanonicalMoves second)
    {
        ArgumentNullException.ThrowIfNull(first);
        ArgumentNullException.ThrowIfNull(second);
        (First, Second) = (first, second);
    }

    /// <summary>The consumer called first.</summary>
    public ICanonicalMoves First { get; }

    /// <summary>The consumer called second.</summary>
    public ICanonicalMoves Second { get; }

    /// <inheritdoc />
    public void StartBlock(in CanonStart start)
    {
        First.StartBlock(start);
        Second.StartBlock(start);
    }

    /// <inheritdoc />
    public void Step(in HostMove step)
    {
        First.Step(step);
        Second.Step(step);
    }

    /// <inheritdoc />
    public void Motion(in CanonMotion motion)
    {
        First.Motion(motion);
        Second.Motion(motion);
    }

    /// <inheritdoc />
    public void EndBlock(in CanonBlock block)
    {
        First.EndBlock(block);
        Second.EndBlock(block);
    }

    /// <inheritdoc />
    public void SelectTool(int tool)
    {
        First.SelectTool(tool);
        Second.SelectTool(tool);
    }

    /// <inheritdoc />
    public void ChangeTool(int tool, in CanonCode code)
    {
        First.ChangeTool(tool, code);
        Second.ChangeTool(tool, code);
    }

    /// <inheritdoc />
    public void SetSpindleSpeed(double speed)
    {
        First.SetSpindleSpeed(speed);
        Second.SetSpindleSpeed(speed);
    }

    /// <inheritdoc />
    public void SetFeedRate(double feed)
    {
        First.SetFeedRate(feed);
        Second.SetFeedRate(feed);
    }

    /// <inheritdoc />
    public void Spindle(SpindleCall call, in CanonCode code)
    {
        First.Spindle(call, code);
        Second.Spindle(call, code);
    }

    /// <inheritdoc />
    public void Coolant(CoolantCall call, in CanonCode code)
    {
        First.Coolant(call, code);
        Second.Coolant(call, code);
    }

    /// <inheritdoc />
    public void ProgramStop(ProgramStopCall call, in CanonCode code)
    {
        First.ProgramStop(call, code);
        Second.ProgramStop(call, code);
    }

    /// <inheritdoc />
    public void Dwell(double seconds)
    {
        First.Dwell(seconds);
        Second.Dwell(seconds);
    }

    /// <inheritdoc />
    public void UseToolLengthOffset(int mode, int number)
    {
        First.UseToolLengthOffset(mode, number);
        Second.UseToolLengthOffset(mode, number);
    }

    /// <inheritdoc />
    public void SetWorkOffset(int key, Point3 offset)
    {
        First.SetWorkOffset(key, offset);
        Second.SetWorkOffset(key, offset);
    }

    /// <inheritdoc />
    public void SetExternalOffset(Point3 offset)
    {
        First.SetExternalOffset(offset);
        Second.SetExternalOffset(offset);
    }

    /// <inheritdoc />
    public void SetToolLength(int tool, double length)
    {
        First.SetToolLength(tool, length);
        Second.SetToolLength(tool, length);
    }

    /// <inheritdoc />
    public void SetLocalShift(double? x, double? y, double? z)
    {
        First.SetLocalShift(x, y, z);
        Second.SetLocalShift(x, y, z);
    }

    /// <inheritdoc />
    public void SetShift(double? x, double? y, double? z)
    {
        First.SetShift(x, y, z);
        Second.SetShift(x, y, z);
    }

    /// <inheritdoc />
    public void CancelShift()
    {
        First.CancelShift();
        Second.CancelShift();
    }

    /// <inheritdoc />
    public void SelectExtendedWorkOffset(int number)
    {
        First.SelectExtendedWorkOffset(number);
        Second.SelectExtendedWorkOffset(number);
    }

    /// <inheritdoc />
    public void Code(in CanonCode code)
    {
        First.Code(code);
        Second.Code(code);
    }
}
