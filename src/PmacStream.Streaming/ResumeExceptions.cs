namespace PmacStream.Streaming;

/// <summary>
/// A resume refused because the job record and the controller disagree in a way that could repeat or skip a block:
/// nothing was sent but <c>CLOSE</c> and queries, and the controller runs on with what it holds. The message gives both
/// positions and the operator's choices; the faces show it and exit non-zero (never restart on their own).
/// </summary>
public sealed class ResumeRefusedException : Exception
{
    /// <summary>Creates the refusal.</summary>
    public ResumeRefusedException(string message, ControllerReading controller, Checkpoint record, int? restartLine)
        : base(message)
    {
        Controller = controller;
        Record = record;
        RestartLine = restartLine;
    }

    /// <summary>What the controller said (M0, running, lines ahead, line probe).</summary>
    public ControllerReading Controller { get; }

    /// <summary>The job record's checkpoint.</summary>
    public Checkpoint Record { get; }

    /// <summary>The line a restart with a preamble would start at once the controller stopped (its M0), or null when it names none.</summary>
    public int? RestartLine { get; }
}

/// <summary>
/// The controller no longer runs the job (aborted, stopped or reset) and agrees with the record about where it got:
/// the job can only start again at <see cref="RestartLine"/> behind a preamble, which the operator confirms.
/// </summary>
public sealed class ControllerLostJobException : InvalidOperationException
{
    /// <summary>Creates the exception.</summary>
    public ControllerLostJobException(string message, int? restartLine)
        : base(message) => RestartLine = restartLine;

    /// <summary>Where a restart starts: the block the controller stopped in; null when it names none (M0 is 0) and the record's line is all there is.</summary>
    public int? RestartLine { get; }
}
