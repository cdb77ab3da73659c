namespace PmacStream.Streaming;

/// <summary>
/// Tells a program stop from an underrun and from the end, beside <see cref="CompletionDetector"/>: at a stop the
/// controller clears its program-running bit while the rotary buffer still holds the rest of the program, and the
/// tracking variable stands on the stop block. So the running bit is asked only when the tracking variable stood
/// still over a tick (a program that moves on needs no extra query): on every such tick while the rotary buffer
/// holds nothing past the tracked block (where a stop must be told from a dry buffer or the end), otherwise every
/// <see cref="AskEvery"/>-th tick it stands (a block longer than a tick needs no query each tick: a stop there is
/// seen at most that many ticks late); and every tick while stopped (to see the run command, from this host or the controller's panel). Which code stopped does not
/// matter here: any routine that says <c>STOP</c>, or a stop from elsewhere, reads the same.
/// </summary>
internal sealed class ProgramStopWatch
{
    private int _lastTracked = -1;
    private int _stillTicks;

    /// <summary>Watches, asking every <paramref name="askEvery"/>-th tick the tracking variable stands still (1: every one).</summary>
    public ProgramStopWatch(int askEvery = 10) => AskEvery = Math.Max(1, askEvery);

    /// <summary>While the tracking variable stands on one block, the running bit is asked every this many ticks.</summary>
    public int AskEvery { get; }

    /// <summary>Where the program stands stopped, or null while it runs.</summary>
    public ProgramStop? Stop { get; private set; }

    /// <summary>Takes the tracking variable at a start or resume, so the first tick judges it against that.</summary>
    public void Reset(int trackedLine)
    {
        _lastTracked = trackedLine;
        _stillTicks = 0;
        Stop = null;
    }

    /// <summary>
    /// True when this tick must ask whether the program runs: while stopped; while running with the tracking variable
    /// where it stood on the last tick, every tick when <paramref name="nothingAhead"/> (the buffer holds nothing past
    /// the tracked block), else every <see cref="AskEvery"/>-th tick it stands.
    /// </summary>
    public bool MustAsk(int trackedLine, bool running, bool nothingAhead = true)
    {
        var still = trackedLine == _lastTracked;
        _lastTracked = trackedLine;
        _stillTicks = still ? _stillTicks + 1 : 0;
        return Stop is not null || (running && still && (nothingAhead || _stillTicks % AskEvery == 0));
    }

    /// <summary>
    /// Judges the running bit: a program that stopped gives its stop (<paramref name="locate"/> names it), one that
    /// runs again after a stop gives the stop it left (as <paramref name="left"/>). Null results mean no change.
    /// </summary>
    public ProgramStop? Observe(bool programRunning, Func<ProgramStop> locate, out ProgramStop? left)
    {
        left = null;
        if (Stop is null && !programRunning)
        {
            Stop = locate();
            return Stop;
        }

        if (Stop is not null && programRunning)
        {
            left = Stop;
            Stop = null;
        }

        return null;
    }

    /// <summary>The operator gave the run command: the stop is left (the next ticks see the program move on).</summary>
    public void Continued() => Stop = null;
}
