using PmacStream.Preparation;

namespace PmacStream.Streaming;

/// <summary>
/// How fast the controller works through the job: the live feed, the measured block rate, the real-time ETA
/// (<see cref="EtaEstimator"/> over the interpreter's move times) and the lead, in seconds of motion, of the lines in
/// the buffer. Without move times the lead and the ETA come from the measured block rate.
/// </summary>
internal sealed class ExecutionPace
{
    private readonly TimeProvider _time;
    private readonly FeedMode _feedMode;
    private readonly EtaEstimator _eta = new();
    private readonly long _etaOrigin;
    private long _startTimestamp;
    private long _rateTimestamp;
    private long _rateMovesReached;

    /// <summary>Measures on <paramref name="time"/>, with <paramref name="moveTimes"/> (null: the block rate only) and the feed in <paramref name="feedMode"/>.</summary>
    public ExecutionPace(TimeProvider time, IMoveTimes? moveTimes, FeedMode feedMode)
    {
        _time = time;
        MoveTimes = moveTimes;
        _feedMode = feedMode;
        _startTimestamp = time.GetTimestamp();
        _etaOrigin = _startTimestamp;
    }

    /// <summary>The interpreter's move times, or null.</summary>
    public IMoveTimes? MoveTimes { get; }

    /// <summary>The live feed read from the controller (the feed variable in paper mode, % in override mode); null when unknown.</summary>
    public double? Feed { get; set; }

    /// <summary>Time since the job started (or was resumed by this session).</summary>
    public TimeSpan Elapsed => _time.GetElapsedTime(_startTimestamp);

    /// <summary>The ETA's measured rate: predicted over actual wall seconds (1 until measured).</summary>
    public double MeasuredRate => _eta.Rate;

    /// <summary>Moves executed per second, smoothed (0 until measured).</summary>
    public double BlocksPerSecond { get; private set; }

    /// <summary>The job starts (or resumes) now: elapsed time and the block rate count from here.</summary>
    public void Restart()
    {
        _startTimestamp = _time.GetTimestamp();
        _rateTimestamp = _startTimestamp;
    }

    /// <summary>
    /// How much faster than programmed the live feed runs the moves at <paramref name="trackedLine"/>: the % over 100
    /// in override mode, the feed variable over the programmed F in paper mode; 1 when either is unknown.
    /// </summary>
    public double FeedFactor(int trackedLine)
    {
        if (Feed is not > 0)
        {
            return 1.0;
        }

        if (_feedMode == FeedMode.Override)
        {
            return Feed.Value / 100.0;
        }

        return MoveTimes?.ProgrammedFeedAt(trackedLine) is double f && f > 0 ? Feed.Value / f : 1.0;
    }

    /// <summary>
    /// A reading of the tracking variable: feeds the ETA's rate (only while <paramref name="counting"/>, not while
    /// held) and, over intervals of at least 0.25 s, the block rate from <paramref name="movesReached"/>.
    /// </summary>
    public void Observe(int trackedLine, long movesReached, bool counting)
    {
        if (MoveTimes is not null)
        {
            var wall = _time.GetElapsedTime(_etaOrigin).TotalSeconds;
            _eta.Observe(wall, trackedLine > 0 ? MoveTimes.SecondsBetween(0, trackedLine - 1) : 0, FeedFactor(trackedLine), counting);
        }

        var now = _time.GetTimestamp();
        var dt = _time.GetElapsedTime(_rateTimestamp, now).TotalSeconds;
        if (dt >= 0.25 && movesReached > _rateMovesReached)
        {
            var rate = (movesReached - _rateMovesReached) / dt;
            BlocksPerSecond = BlocksPerSecond <= 0 ? rate : (0.7 * BlocksPerSecond) + (0.3 * rate);
            _rateTimestamp = now;
            _rateMovesReached = movesReached;
        }
    }

    /// <summary>
    /// Seconds of motion between the executing block <paramref name="trackedLine"/> and the move <paramref name="lastLine"/>
    /// (<paramref name="movesAhead"/> moves): from the move times at the live feed, or the measured block rate.
    /// </summary>
    public double LeadSeconds(int trackedLine, int lastLine, int movesAhead)
    {
        if (MoveTimes is not null)
        {
            return MoveTimes.SecondsBetween(trackedLine, lastLine) / FeedFactor(trackedLine);
        }

        return BlocksPerSecond > 0 ? movesAhead / BlocksPerSecond : 0;
    }

    /// <summary>Time to the end in wall time from the move times: program seconds after <paramref name="trackedLine"/>'s block at the live feed and the measured rate.</summary>
    public TimeSpan? EtaByMoveTimes(int trackedLine, int finalTrackedLine) =>
        MoveTimes is null ? null : _eta.Estimate(MoveTimes.SecondsBetween(trackedLine - 1, finalTrackedLine), FeedFactor(trackedLine));

    /// <summary>Time to the end from the measured block rate: the blocks left at that rate; null until measured.</summary>
    public TimeSpan? EtaByBlockRate(int executedBlocks, int totalBlocks) =>
        executedBlocks > 0 && BlocksPerSecond > 0 ? TimeSpan.FromSeconds((totalBlocks - executedBlocks) / BlocksPerSecond) : null;
}
