namespace PmacStream.Streaming;

/// <summary>Where a session is.</summary>
public enum SessionState
{
    /// <summary>Created, nothing sent yet.</summary>
    Idle,

    /// <summary>Running: the timer feeds the buffer.</summary>
    Running,

    /// <summary>Held by the operator (<c>H</c>); feeding continues, motion stands.</summary>
    Held,

    /// <summary>Every block executed.</summary>
    Completed,

    /// <summary>Stopped by a controller error or a lost link; resumable.</summary>
    Faulted,

    /// <summary>Aborted by the operator (<c>A</c>); resumable from the last executed line with a preamble.</summary>
    Aborted,

    /// <summary>
    /// At a program stop (<c>M00</c>, <c>M01</c> with optional stop on, any code whose routine says <c>STOP</c>): the
    /// controller stopped the program and waits for the run command (<see cref="StreamingStatus.Stop"/> says where);
    /// feeding goes on, no underrun is counted.
    /// </summary>
    Stopped,
}

/// <summary>Where the program stopped on the controller.</summary>
/// <param name="Line">The source line of the stop block (the tracking variable names it).</param>
/// <param name="Code">The stop code of that block (<c>M00</c>), or null when the block holds none (the program was stopped otherwise).</param>
public sealed record ProgramStop(int Line, string? Code)
{
    /// <summary><c>program stop (M00) at line 12</c>.</summary>
    public override string ToString() => Code is null ? $"program stop at line {Line}" : $"program stop ({Code}) at line {Line}";
}

/// <summary>What the HMI and CLI show about a session (the status panel).</summary>
/// <param name="State">Session state.</param>
/// <param name="TotalChunks">Chunks in the program.</param>
/// <param name="TotalBlocks">Motion blocks in the program.</param>
/// <param name="CurrentChunk">Chunk executing now (1-based).</param>
/// <param name="CurrentLine">Source line executing now (the tracking variable; 0 before the first block).</param>
/// <param name="ExecutedBlocks">Motion blocks executed so far (from the tracking variable).</param>
/// <param name="Percent">Progress in percent of motion blocks.</param>
/// <param name="Feed">Feed set (P500 value in paper mode, % in override mode); null when unknown.</param>
/// <param name="Elapsed">Time since start.</param>
/// <param name="Eta">Estimated time to finish in the session clock's (wall) time: move times scaled by the live feed and the measured rate (<see cref="EtaEstimator"/>); null when unknown.</param>
/// <param name="ChunksDownloaded">Chunks completely sent.</param>
/// <param name="LinesSent">Program lines sent.</param>
/// <param name="Underruns">Times the host saw the buffer run dry before the end.</param>
/// <param name="Message">The last notable event, for a status bar (fault text with what to do).</param>
/// <param name="Stop">Where the program stopped while <paramref name="State"/> is <see cref="SessionState.Stopped"/>, else null.</param>
public sealed record StreamingStatus(
    SessionState State,
    int TotalChunks,
    int TotalBlocks,
    int CurrentChunk,
    int CurrentLine,
    int ExecutedBlocks,
    double Percent,
    double? Feed,
    TimeSpan Elapsed,
    TimeSpan? Eta,
    int ChunksDownloaded,
    long LinesSent,
    int Underruns,
    string Message,
    ProgramStop? Stop = null);

/// <summary>Kinds of session events (job log).</summary>
public enum StreamingEventKind
{
    /// <summary>Session set-up done and execution started.</summary>
    Started,

    /// <summary>A chunk was downloaded (inside its window).</summary>
    ChunkDownloaded,

    /// <summary>A chunk was downloaded after its window had passed.</summary>
    ChunkDownloadedLate,

    /// <summary>Execution entered the next chunk.</summary>
    ChunkEntered,

    /// <summary>The buffer ran dry before the end.</summary>
    Underrun,

    /// <summary>An operator command was sent (hold, resume, abort, feed, single block).</summary>
    Command,

    /// <summary>A controller error or lost link stopped the session.</summary>
    Fault,

    /// <summary>The session recovered from a fault and continues.</summary>
    Recovered,

    /// <summary>Every block executed.</summary>
    Completed,

    /// <summary>The program stopped at a program stop and waits for the run command.</summary>
    ProgramStop,
}

/// <summary>One event of a session.</summary>
/// <param name="Kind">What happened.</param>
/// <param name="Message">Human-readable text.</param>
/// <param name="Chunk">The chunk concerned, 0 when none.</param>
/// <param name="TrackedLine">The tracking variable when it happened.</param>
public sealed record StreamingEvent(StreamingEventKind Kind, string Message, int Chunk, int TrackedLine);

/// <summary>A crash-safe checkpoint: what was executed and what was sent, written every tick on which it changed.</summary>
/// <param name="LastExecutedLine">Tracking variable (source line) read last.</param>
/// <param name="CurrentChunk">Chunk executing.</param>
/// <param name="Next">Next program line to send.</param>
/// <param name="NextExact">False when a download broke off and how much arrived is not known.</param>
/// <param name="ChunksDownloaded">Chunks completely sent.</param>
/// <param name="State">Session state.</param>
/// <param name="TimeUtc">When it was taken (a tick that changes nothing writes none: in the job store, when the position last changed).</param>
/// <param name="Started">True once the run command (<c>&amp;n R</c>) was given.</param>
/// <param name="Loaded">
/// False while the start loads the buffer (clear, preamble, first chunk) and until that load completed: how much of
/// it arrived is unknown and nothing has run, so a resume clears and loads the job's recorded start again
/// (<see cref="JobStart"/>) instead of running what is there.
/// </param>
public sealed record Checkpoint(int LastExecutedLine, int CurrentChunk, StreamPosition Next, bool NextExact, int ChunksDownloaded, SessionState State, DateTimeOffset TimeUtc, bool Started = true, bool Loaded = true);

/// <summary>How a job starts: what a resume needs to load the start again when it broke off before the run command.</summary>
/// <param name="FromLine">The source line of the start block, or null for the program start.</param>
/// <param name="Preamble">The PMAC lines sent before that block (restore modal state, safe approach), or null.</param>
/// <param name="LineProbeVariable">The line-probe variable the job's lines carry (null: none).</param>
public sealed record JobStart(int? FromLine, IReadOnlyList<string>? Preamble, string? LineProbeVariable);

/// <summary>Where checkpoints go (the job store; tests use memory).</summary>
public interface ICheckpointSink
{
    /// <summary>Records a checkpoint; <paramref name="durable"/> asks for a synchronous commit (chunk boundaries, faults, end).</summary>
    void Save(Checkpoint checkpoint, bool durable);

    /// <summary>Records how the job starts (durably), before the start sends anything; the job store keeps it for resume.</summary>
    void RecordStart(JobStart start)
    {
    }
}

/// <summary>Move times by source line, for ETA and the adaptive lead.</summary>
public interface IMoveTimes
{
    /// <summary>Seconds of motion (at programmed feed) of the tracked blocks after <paramref name="afterLine"/> up to and including <paramref name="throughLine"/>.</summary>
    double SecondsBetween(int afterLine, int throughLine);

    /// <summary>The programmed feed (F) in force for the block at or before <paramref name="line"/>; null when not known.</summary>
    double? ProgrammedFeedAt(int line) => null;
}
