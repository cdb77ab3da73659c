namespace PmacStream.Streaming;

/// <summary>What a tick's look at the buffer found.</summary>
internal enum BufferVerdict
{
    /// <summary>Nothing to report: lines are ahead, or the dry spell was already counted.</summary>
    None,

    /// <summary>The buffer ran dry before everything was sent (counted once per dry spell).</summary>
    Underrun,

    /// <summary>Everything was sent and has run: the job is complete.</summary>
    Completed,
}

/// <summary>
/// Decides from the tracking variable and <c>PR</c> whether the rotary buffer ran dry before the end (an underrun) or
/// the job is complete. The controller is asked for <c>PR</c> only once execution has reached the last move sent.
/// </summary>
internal sealed class CompletionDetector
{
    private bool _dry;
    private int _stableReads;
    private int _lastTracked = -1;

    /// <summary>Underruns counted so far.</summary>
    public int Underruns { get; private set; }

    /// <summary>
    /// True when the buffer must be read (<c>PR</c>) this tick: everything was sent, or execution has reached the last
    /// move sent. Otherwise lines are still ahead, and a dry spell (if any) has ended.
    /// </summary>
    public bool NeedsLinesAhead(bool allSent, int lastSentLine, int trackedLine)
    {
        if (!allSent && lastSentLine > trackedLine)
        {
            _dry = false;
            return false;
        }

        return true;
    }

    /// <summary>
    /// Judges a <c>PR</c> reading. Before everything was sent, an empty buffer while running is an underrun (once per
    /// dry spell). Once everything was sent, an empty buffer is the end when the tracking variable reached the final
    /// move, or stood still over three readings (a final move the variable never names, e.g. with paper placement).
    /// </summary>
    public BufferVerdict Observe(bool allSent, int linesAhead, int trackedLine, int finalTrackedLine, bool running)
    {
        if (!allSent)
        {
            if (linesAhead == 0 && !_dry && running)
            {
                _dry = true;
                Underruns++;
                return BufferVerdict.Underrun;
            }

            if (linesAhead > 0)
            {
                _dry = false;
            }

            return BufferVerdict.None;
        }

        _stableReads = linesAhead == 0 && trackedLine == _lastTracked ? _stableReads + 1 : 0;
        _lastTracked = trackedLine;
        return linesAhead == 0 && (trackedLine >= finalTrackedLine || _stableReads >= 2) ? BufferVerdict.Completed : BufferVerdict.None;
    }
}
