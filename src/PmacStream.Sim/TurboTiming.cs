namespace PmacStream.Sim;

/// <summary>
/// How long a Turbo PMAC takes for a blended LINEAR or CIRCLE move (issue 28; facts and pages in
/// docs/turbo-pmac-timing.md). The acceleration time is TA, or twice TS when TS is more than half of TA (Turbo SRM
/// p. 188); it is also the shortest a blended move can take: a move whose distance over the feed (or whose TM) is
/// shorter is done in the acceleration time instead, and with TA and TS both 0 the shortest is 0.5 ms (p. 188).
/// Blended moves run back to back at their own speeds, the velocity changing over the acceleration time around each
/// boundary, so a sequence costs the sum of its move times plus one acceleration time: half to start from rest, half
/// to stop. Here the whole acceleration time is charged to the first move of a sequence (one that starts from rest:
/// after a rapid, a dwell, an underrun or a stop), so the sequence's total is right and a starved buffer costs time,
/// as on the machine. Not modelled: the motors' Ixx16/Ixx17 speed and acceleration limits and the rapid moves'
/// jog acceleration (rapids keep <see cref="SimOptions.RapidFeed"/>).
/// </summary>
internal static class TurboTiming
{
    /// <summary>True for the moves a Turbo PMAC blends (LINEAR and CIRCLE).</summary>
    public static bool IsBlended(Segment seg) => seg.Kind is MoveKind.Linear or MoveKind.Circle1 or MoveKind.Circle2;

    /// <summary>The acceleration time in seconds of <paramref name="taMs"/> and <paramref name="tsMs"/>: TA, or 2 TS when TS is more than TA/2.</summary>
    public static double AccelerationSeconds(double taMs, double tsMs) => Math.Max(0, tsMs > taMs / 2 ? 2 * tsMs : taMs) / 1000.0;

    /// <summary>Applies the minimum move time to a calculated blended move and notes its acceleration time.</summary>
    public static void Blend(Segment seg, double taMs, double tsMs, SimOptions options)
    {
        var accel = AccelerationSeconds(taMs, tsMs);
        seg.Acceleration = accel;
        var least = accel > 0 ? accel : Math.Max(0, options.MinimumMoveTimeMs) / 1000.0;
        if (seg.Duration < least)
        {
            seg.Duration = least;
        }
    }

    /// <summary>A blended move that starts from rest (not <paramref name="continuing"/> a sequence) takes its acceleration time more.</summary>
    public static void StartFromRest(Segment seg, bool continuing)
    {
        if (continuing || !IsBlended(seg) || seg.Acceleration <= 0)
        {
            return;
        }

        seg.Duration += seg.Acceleration;
        seg.Remaining += seg.Acceleration;
    }
}
