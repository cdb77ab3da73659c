using PmacStream.Pmac;

namespace PmacStream.Streaming;

/// <summary>How a resume from a job record goes on.</summary>
internal enum ResumeRoute
{
    /// <summary>The start had loaded the buffer (or run): continue from the checkpoint.</summary>
    FromCheckpoint,

    /// <summary>The start broke off while loading (nothing ran): clear the buffer and load the recorded start again.</summary>
    LoadStartAgain,
}

/// <summary>
/// The decisions of recovery, apart from carrying them out: how a job record is resumed, whether the controller
/// still holds the job a checkpoint describes, and what a fault tells the operator to do.
/// </summary>
internal static class JobRecovery
{
    /// <summary>
    /// The route of a resume from <paramref name="job"/>. Throws <see cref="InvalidOperationException"/> when the start
    /// from a line must be loaded again but the record holds no preamble (a record of an older version).
    /// </summary>
    public static ResumeRoute RouteOf(JobRecord job)
    {
        ArgumentNullException.ThrowIfNull(job);
        if (job.Checkpoint is { } cp && (cp.Loaded || cp.Started))
        {
            return ResumeRoute.FromCheckpoint;
        }

        if (job.FromLine is { } line && job.Preamble is null)
        {
            throw new InvalidOperationException(
                $"job {job.Id} broke off while loading its start at line {line} and the record holds no preamble: restart from line {line} with a preamble");
        }

        return ResumeRoute.LoadStartAgain;
    }

    /// <summary>Throws when <paramref name="checkpoint"/> was taken while the start loaded the buffer: only the start itself can be loaded again.</summary>
    public static void EnsureLoaded(Checkpoint checkpoint)
    {
        if (!checkpoint.Loaded && !checkpoint.Started)
        {
            // Nothing ran and the buffer holds an unknown part of the start.
            throw new InvalidOperationException(
                "the job's start broke off while loading the buffer (nothing has run): start it again (resume from the job record loads the recorded start)");
        }
    }

    /// <summary>What a resume tells the operator: where the controller is and where sending goes on.</summary>
    public static string ResumedMessage(int trackedLine, bool draining, string? controllerAhead, StreamPosition next) => (draining, controllerAhead) switch
    {
        (true, { } why) => $"resumed at line {trackedLine}; the controller is ahead of the job record ({why}): waiting for the buffer to drain, then sending goes on after the last line it holds",
        (true, null) => $"resumed at line {trackedLine}; waiting for the buffer to drain to find where sending broke off",
        _ => $"resumed at line {trackedLine}; sending continues at {next}",
    };

    /// <summary>
    /// True when the job was at a program stop when the checkpoint was taken and the tracking variable still names
    /// that block: the controller waits there for the run command, the job is not lost.
    /// </summary>
    public static bool StillAtStop(Checkpoint checkpoint, int trackedLine) =>
        checkpoint.State == SessionState.Stopped && trackedLine == checkpoint.LastExecutedLine;

    /// <summary>What a fault means for the job and what the operator does next: nothing is lost or repeated on resume.</summary>
    public static string FaultMessage(Exception e, int trackedLine, StreamPosition next)
    {
        ArgumentNullException.ThrowIfNull(e);
        var at = $"last executed line {trackedLine}, sending stopped at {next}";
        return e switch
        {
            PmacLinkException => $"link to the controller lost ({e.Message}); {at}. The controller keeps running the lines it holds. When the link is back, resume (pmacstream resume, or Resume in the HMI): nothing is lost or repeated.",
            PmacErrorException pe => $"controller refused '{pe.Command}' with ERR{pe.Number:000} ({PmacErrors.Describe(pe.Number)}); {at}. Fix the cause, then resume.",
            IOException or InvalidDataException or UnauthorizedAccessException => $"{e.Message}; {at}. The controller runs the lines it holds, then stops. Put the chunk right (or split again), then resume: nothing is lost or repeated.",
            _ => $"{e.Message}; {at}",
        };
    }
}
