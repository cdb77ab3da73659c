namespace PmacStream.Streaming;

/// <summary>
/// When a recovering or resuming session may give the run command (<c>&amp;n R</c>) of a start whose run command is
/// not known to have arrived. A second <c>R</c> is not harmless: it continues a held program, restarts one stopped at
/// a program stop, and starts the rotary program of a completed job again on whatever the buffer holds. So it is given
/// only to a coordinate system that is not running a program and has not executed a tracked block of it (the tracking
/// variable, reset to 0 before the start, still 0); a status that is not understood counts as running.
/// </summary>
internal static class RunCommandRule
{
    /// <summary>True when the run command may be sent to a controller that reported <paramref name="seen"/>.</summary>
    public static bool MaySend(ControllerReading seen) => seen.Running == false && seen.TrackedLine == 0;

    /// <summary>Why the run command is not sent (for the log), or null when it may be.</summary>
    public static string? WhyNot(ControllerReading seen, string trackingVariable) => MaySend(seen)
        ? null
        : seen.Running switch
        {
            true => $"the coordinate system is running the program ({trackingVariable}={seen.TrackedLine}): the run command arrived; not sent again",
            null => $"the coordinate system's status was not understood ({trackingVariable}={seen.TrackedLine}): not knowing whether it runs, the run command is not sent",
            false => $"the program already ran to {trackingVariable}={seen.TrackedLine} and stopped: the run command arrived; not sent again",
        };
}
