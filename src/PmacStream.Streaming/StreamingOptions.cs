using PmacStream.Preparation;

namespace PmacStream.Streaming;

/// <summary>The ways of feeding the rotary buffer.</summary>
public enum StrategyKind
{
    /// <summary>Whole chunk files, the next one downloaded once when M0 enters the current chunk's download window.</summary>
    Chunk,

    /// <summary>The traditional method: poll <c>PR</c> and top the rotary buffer up line by line.</summary>
    Pr,

    /// <summary>Keep a time-based lead (seconds of motion ahead) from move times and the measured round trip, bounded by buffer words.</summary>
    Adaptive,

    /// <summary>
    /// Keep the rotary buffer full: a buffer defined as large as the controller's memory allows, topped up as soon as
    /// a slice of it is free, so the lead rides out the link's retransmission stalls. The default of `stream`; a choice in the HMI.
    /// </summary>
    Full,
}

/// <summary>Settings of a streaming session.</summary>
public sealed record StreamingOptions
{
    /// <summary>The PComm device number used for <c>Download</c>.</summary>
    public int PmacNumber { get; init; }

    /// <summary>Coordinate system that runs the rotary buffer.</summary>
    public int CoordinateSystem { get; init; } = 1;

    /// <summary>Which strategy feeds the buffer.</summary>
    public StrategyKind Strategy { get; init; } = StrategyKind.Chunk;

    /// <summary>Timer period the host calls <see cref="StreamingSession.TickAsync"/> with (the HMI's timer1 interval).</summary>
    public TimeSpan TickPeriod { get; init; } = StreamingDefaults.TickPeriod;

    /// <summary>Start of the download window as a fraction of the current chunk (0.6: line 600 of a 1000-line chunk).</summary>
    public double WindowStart { get; init; } = StreamingDefaults.WindowStart;

    /// <summary>End of the download window as a fraction of the current chunk (0.7: line 700 of a 1000-line chunk).</summary>
    public double WindowEnd { get; init; } = StreamingDefaults.WindowEnd;

    /// <summary>Rotary buffer size in words (what <c>&amp;n DEFINE ROT</c> gave it).</summary>
    public int BufferWords { get; init; } = StreamingDefaults.BufferWords;

    /// <summary>When set, the session defines the rotary buffer with this many words before starting (<c>DEL GAT</c>, <c>DEF ROT</c>).</summary>
    public bool DefineBuffer { get; init; }

    /// <summary>
    /// With <see cref="DefineBuffer"/>: define the rotary buffer from what the controller's <c>SIZE</c> reports free
    /// (less <see cref="MemoryReserveWords"/>, at most <see cref="BufferWordsCap"/>) instead of <see cref="BufferWords"/>,
    /// which stays the size for a controller that does not answer it. The <c>full</c> strategy's.
    /// </summary>
    public bool SizeBufferFromController { get; init; }

    /// <summary>Words of free user memory left out of a buffer sized from <c>SIZE</c> (PLCs and programs loaded later).</summary>
    public int MemoryReserveWords { get; init; } = StreamingDefaults.MemoryReserveWords;

    /// <summary>Most words a buffer sized from <c>SIZE</c> gets; 0: no cap (as large as the controller allows).</summary>
    public int BufferWordsCap { get; init; }

    /// <summary>Words kept free as a margin against the splitter's estimate.</summary>
    public int SafetyWords { get; init; } = StreamingDefaults.BufferMarginWords;

    /// <summary>
    /// While the tracking variable stands on one block (a move longer than a tick), the coordinate system's status
    /// (<c>&amp;n??</c>, to see a program stop) is read every this many ticks it stands (a stop is seen at most that
    /// late); every tick while the buffer holds nothing past that block, and every tick while stopped. A tick
    /// otherwise reads M0 alone. 1: every tick M0 stands still.
    /// </summary>
    public int StatusEveryTicks { get; init; } = 10;

    /// <summary><c>pr</c> strategy: lines kept ahead in the buffer.</summary>
    public int PrTargetLines { get; init; } = 200;

    /// <summary><c>adaptive</c> strategy: least lead in seconds of motion kept in the buffer.</summary>
    public double AdaptiveMinLeadSeconds { get; init; } = 0.5;

    /// <summary><c>adaptive</c> strategy: most program lines sent in one batch.</summary>
    public int AdaptiveMaxBatchLines { get; init; } = 400;

    /// <summary>
    /// <c>full</c> strategy: most program lines sent in one batch. A batch holds the tick (operator commands and the
    /// M0 reading that frees the model's words wait for it), but one batch a tick is the strategy's throughput: 600
    /// lines a tick gave 69 underruns where 2,000 gave none (issue 28's bench), so 2,000 (about 70 WRITEBUFFER packets).
    /// </summary>
    public int FullMaxBatchLines { get; init; } = 2000;

    /// <summary>
    /// <c>full</c> strategy: WRITEBUFFER packets sent before their replies arrive (Ethernet; other links send one at a
    /// time). 1 keeps one request in flight. With more, every batch is sized within the free words the controller
    /// last reported less the words already in flight, counted as the controller counts them
    /// (<see cref="ControllerWords"/>), so a line cannot be refused for room; should one be refused anyway while later
    /// packets were stored behind it, the session aborts the coordinate system at once and ends the job at the last
    /// block executed, resumable from there (<see cref="StreamingSession"/>).
    /// </summary>
    public int PacketsInFlight { get; init; } = StreamingDefaults.PacketsInFlight;

    /// <summary><c>full</c> strategy with several packets in flight: most words (controller's count) one batch carries.</summary>
    public int WordsInFlight { get; init; } = StreamingDefaults.WordsInFlight;

    /// <summary>Feed control: <c>P500</c> (paper) or the <c>%</c> override; defaults to the manifest's mode.</summary>
    public FeedMode? Feed { get; init; }

    /// <summary>Single-block mode: each start (<c>&amp;n S</c>) runs one block.</summary>
    public bool SingleBlock { get; init; }

    /// <summary>Optional stop on: the controller stops at <c>M01</c> (the session sets <see cref="OptionalStopVariable"/> to 1 at the start).</summary>
    public bool OptionalStop { get; init; } = true;

    /// <summary>The optional-stop switch the library's <c>M01</c> routine reads (<c>P502</c>).</summary>
    public string OptionalStopVariable { get; init; } = Preparation.PreparationDefaults.OptionalStopVariable;

    /// <summary>
    /// Line-probe variable: every non-motion line is sent with a plain <c>P501=n</c> (its position), reset to 0 at the
    /// start. After a download broke off mid-way and the buffer drained, M0 tells the last move the controller got and
    /// the probe the last non-motion line, so sending resumes exactly after what arrived (nothing repeated, even M08).
    /// Null or empty turns it off (then a non-motion line right before a break may be sent twice).
    /// </summary>
    public string? LineProbeVariable { get; init; } = "P501";

    /// <summary>Set the tracking variable to 0 before starting, so a stale value from an earlier job is not read as progress.</summary>
    public bool ResetTrackVariable { get; init; } = true;

    /// <summary>
    /// The line at which the previous job on this controller completed (its job record's), or null. A rotary program
    /// has no end of its own: once its last line has run it waits for more, and the coordinate system still counts as
    /// running. A start that finds it running with nothing ahead (<c>PR</c> 0), no move executing or queued and the
    /// tracking variable still at this line takes it for that finished job and ends it (<c>&amp;n A</c>, nothing left
    /// to stop) instead of refusing. Null: any running program refuses the start.
    /// </summary>
    public int? CompletedJobLine { get; init; }
}
