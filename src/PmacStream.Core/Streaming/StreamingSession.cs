using System.Diagnostics;
using System.Globalization;
using PmacStream.Pmac;
using PmacStream.Program;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// One job streaming a split program into a coordinate system's rotary buffer. The host calls <see cref="TickAsync"/>
/// (or <see cref="Tick"/>) from its timer, every <see cref="StreamingOptions.TickPeriod"/> (the paper's
/// <c>timer1_Tick</c>); each tick reads the tracking variable (M0), lets the strategy send what it wants, and writes a
/// checkpoint. Operator commands (hold, resume, abort, feed, step) are sent between ticks, never while a buffer is open.
/// Whatever fails, no block is skipped, repeated or reordered: on an <c>ERRnnn</c> or a lost link the session stops
/// sending, keeps the exact position (or, when a download broke off mid-way, waits for the buffer to drain and
/// re-derives it from M0), and <see cref="RecoverAsync"/> or <see cref="ResumeAsync(Checkpoint, CancellationToken)"/> continues.
/// </summary>
public sealed class StreamingSession
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    private readonly IPmacConnection _conn;
    private readonly IPmacDevices _devices;
    private readonly IStreamingStrategy _strategy;
    private readonly ICheckpointSink? _sink;
    private readonly TimeProvider _time;
    private readonly SemaphoreSlim _gate = new(1, 1);
    private readonly Queue<(int Tag, int Words, bool Marker)> _occupancy = new();
    private readonly string _cs;
    private readonly string _track;
    private readonly FeedMode _feedMode;

    private SessionState _state = SessionState.Idle;
    private int _tracked;
    private int _currentChunk = 1;
    private StreamPosition _next = new(1, 0);
    private bool _nextExact = true;
    private int _chunksDownloaded;
    private long _linesSent;
    private int _underruns;
    private string _message = string.Empty;
    private bool _bufferOpen;
    private bool _draining;
    private int _drainStableReads;
    private int _drainLastTracked = -1;
    private int _completeStableReads;
    private int _completeLastTracked = -1;
    private bool _dry;
    private long _startTimestamp;
    private int _occWords;
    private int _markersAhead;
    private int _lastSentTag;
    private long _markersSent;
    private double _rttSeconds;
    private double _blocksPerSecond;
    private long _rateTimestamp;
    private long _rateMarkersExecuted;
    private double? _feed;
    private bool _singleBlock;
    private int _lastDurableChunk;
    private bool _runSent;
    private bool _loaded;
    private StreamPosition _startAt = new(1, 0);
    private List<ProgramLine>? _preamble;
    private long _ticks;
    private bool _statusUnsupported;
    private readonly EtaEstimator _eta = new();
    private readonly long _etaOrigin;

    /// <summary>Creates a session on a PComm-style device facade; downloads go through its <c>Download</c>.</summary>
    public StreamingSession(IPmacDevices devices, ChunkedProgram program, StreamingOptions options, ICheckpointSink? checkpoints = null, IMoveTimes? moveTimes = null, TimeProvider? time = null, IStreamingStrategy? strategy = null)
    {
        _devices = devices;
        _conn = devices[options.PmacNumber];
        Program = program;
        Options = options;
        _sink = checkpoints;
        MoveTimes = moveTimes;
        _time = time ?? TimeProvider.System;
        _strategy = strategy ?? StreamingStrategies.Create(options.Strategy);
        _cs = "&" + options.CoordinateSystem.ToString(CultureInfo.InvariantCulture);
        _track = string.IsNullOrWhiteSpace(program.Manifest.TrackVariable) ? "M0" : program.Manifest.TrackVariable.Trim();
        _feedMode = options.Feed ?? program.Manifest.Feed;
        _singleBlock = options.SingleBlock;
        program.UseLineProbe(options.LineProbeVariable);
        Context = new StreamingContext(this);
        _startTimestamp = _time.GetTimestamp();
        _etaOrigin = _startTimestamp;
    }

    /// <summary>Creates a session on a bare connection, configured as the options' device in the one PComm-style facade.</summary>
    public StreamingSession(IPmacConnection connection, ChunkedProgram program, StreamingOptions options, ICheckpointSink? checkpoints = null, IMoveTimes? moveTimes = null, TimeProvider? time = null, IStreamingStrategy? strategy = null)
        : this(PmacDevices.Of(options.PmacNumber, connection), program, options, checkpoints, moveTimes, time, strategy)
    {
    }

    /// <summary>The program being streamed.</summary>
    public ChunkedProgram Program { get; }

    /// <summary>The session's settings.</summary>
    public StreamingOptions Options { get; }

    /// <summary>Move times used for the ETA and the adaptive lead (null: measured block rate).</summary>
    public IMoveTimes? MoveTimes { get; }

    /// <summary>The strategy feeding the buffer.</summary>
    public IStreamingStrategy Strategy => _strategy;

    /// <summary>The state.</summary>
    public SessionState State => _state;

    /// <summary>Single-block mode: starts run one block (<c>&amp;n S</c>).</summary>
    public bool SingleBlock => _singleBlock;

    /// <summary>The next program line to send.</summary>
    public StreamPosition Next => _next;

    /// <summary>Raised after every tick and command with the new status (on the ticking thread).</summary>
    public event EventHandler<StreamingStatus>? StatusChanged;

    /// <summary>Raised for job events: downloads, late windows, chunk changes, faults, completion.</summary>
    public event EventHandler<StreamingEvent>? EventRaised;

    internal StreamingContext Context { get; }

    internal int Tracked => _tracked;

    internal int CurrentChunk => _currentChunk;

    internal bool AllSent => Program.IsEnd(_next);

    internal double RoundTripSeconds => _rttSeconds;

    internal int FreeWords => Math.Max(0, Options.BufferWords - Options.SafetyWords - _occWords);

    /// <summary>The status now.</summary>
    public StreamingStatus Status
    {
        get
        {
            var executed = _tracked > 0 ? Program.BlocksThrough(_tracked) : 0;
            var total = Math.Max(1, Program.Manifest.TotalMotionBlocks);
            var elapsed = _time.GetElapsedTime(_startTimestamp);
            TimeSpan? eta = null;
            if (_state == SessionState.Completed)
            {
                eta = TimeSpan.Zero;
            }
            else if (MoveTimes is not null)
            {
                // Real time: program seconds left, scaled by the live feed and the rate measured so far.
                eta = _eta.Estimate(MoveTimes.SecondsBetween(_tracked - 1, Program.FinalTrackedLine), LiveFeedFactor);
            }
            else if (executed > 0 && _blocksPerSecond > 0)
            {
                eta = TimeSpan.FromSeconds((Program.Manifest.TotalMotionBlocks - executed) / _blocksPerSecond);
            }

            return new StreamingStatus(
                _state,
                Program.TotalChunks,
                Program.Manifest.TotalMotionBlocks,
                _currentChunk,
                _tracked,
                executed,
                Math.Clamp(100.0 * executed / total, 0, 100),
                _feed,
                elapsed,
                eta,
                _chunksDownloaded,
                _linesSent,
                _underruns,
                _message);
        }
    }

    /// <summary>The checkpoint now (what a crash-safe resume needs).</summary>
    public Checkpoint Checkpoint => new(_tracked, _currentChunk, _next, _nextExact, _chunksDownloaded, _state, _time.GetUtcNow(), _runSent, _loaded || _runSent);

    /// <summary>
    /// How much faster than programmed the live feed runs the moves: the % override over 100 in override mode, the
    /// feed variable (P500) over the programmed F at the executing block in paper mode; 1 when either is unknown.
    /// </summary>
    private double LiveFeedFactor
    {
        get
        {
            if (_feed is not > 0)
            {
                return 1.0;
            }

            if (_feedMode == FeedMode.Override)
            {
                return _feed.Value / 100.0;
            }

            return MoveTimes?.ProgrammedFeedAt(_tracked) is double f && f > 0 ? _feed.Value / f : 1.0;
        }
    }

    /// <summary>The ETA's measured rate: predicted over actual wall seconds (1 until measured).</summary>
    internal double MeasuredRate => _eta.Rate;

    /// <summary>
    /// Sets up and starts: <c>CLOSE</c>, (optionally) define the rotary buffer, reset the tracking variable,
    /// <c>&amp;n B0</c> before the first <c>OPEN ROT</c>, the preamble (start from a line), the first chunk, then
    /// <c>&amp;n R</c> (or <c>&amp;n S</c> in single-block mode).
    /// </summary>
    /// <param name="fromLine">Start at the block of this source line instead of the first (null: from the start).</param>
    /// <param name="preamble">Program lines restoring modal state and approaching safely, sent before that block.</param>
    /// <param name="cancellationToken">Cancels waiting for the link.</param>
    public async Task StartAsync(int? fromLine = null, IReadOnlyList<string>? preamble = null, CancellationToken cancellationToken = default)
    {
        if (_state != SessionState.Idle)
        {
            throw new InvalidOperationException($"the session is {_state}; start needs a new session");
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var start = fromLine is { } line
                ? Program.PositionOfBlock(line) ?? throw new ArgumentOutOfRangeException(nameof(fromLine), $"line {line} lies after the last block of the program")
                : new StreamPosition(1, 0);
            CheckChunksFit();

            // Recorded before anything is sent: a host that dies from here until the load completed resumes by
            // clearing and loading this same start again (which comes back here, to the check below).
            _sink?.RecordStart(new JobStart(fromLine, preamble is { Count: > 0 } ? preamble.ToList() : null, Program.LineProbeVariable));

            await EnsureNotRunningAsync(cancellationToken).ConfigureAwait(false);
            if (Options.DefineBuffer)
            {
                await OnlineAsync("DELETE GATHER", cancellationToken).ConfigureAwait(false);
                await OnlineIgnoringAsync($"{_cs} DELETE ROT", cancellationToken).ConfigureAwait(false);
                await OnlineAsync($"{_cs} DEFINE ROT {Options.BufferWords}", cancellationToken).ConfigureAwait(false);
            }

            if (Options.ResetTrackVariable)
            {
                await OnlineAsync($"{_track}=0", cancellationToken).ConfigureAwait(false);
            }

            if (Program.LineProbeVariable is { } probe)
            {
                // A probe value left by an earlier job would read as lines of this one.
                await OnlineAsync($"{probe}=0", cancellationToken).ConfigureAwait(false);
            }

            // B0 must precede the first OPEN ROT: inside an open buffer it would be a B-axis move.
            await OnlineAsync($"{_cs} B0", cancellationToken).ConfigureAwait(false);
            await ReadFeedAsync(cancellationToken).ConfigureAwait(false);

            _startAt = start;
            _currentChunk = start.Chunk;
            _startTimestamp = _time.GetTimestamp();
            _rateTimestamp = _startTimestamp;
            _preamble = preamble is { Count: > 0 } ? preamble.Select(p => Program.Classify(p) with { TrackedLine = 0 }).ToList() : null;
            await LoadAsync(cancellationToken).ConfigureAwait(false);
            _state = SessionState.Running;
            SaveCheckpoint(durable: true); // loaded, not started: a resume gives the run command
            await OnlineAsync(_singleBlock ? $"{_cs} S" : $"{_cs} R", cancellationToken).ConfigureAwait(false);
            _runSent = true;
            Raise(StreamingEventKind.Started, fromLine is { } f ? $"started at line {f} ({_strategy.Name})" : $"started ({_strategy.Name})", _next.Chunk);
            SaveCheckpoint(durable: true);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            if (_linesSent == 0 && _nextExact && !_bufferOpen)
            {
                // Nothing of the program reached the buffer: the start can simply be tried again.
                _state = SessionState.Idle;
                _message = $"start failed: {e.Message}";
            }
            else
            {
                Fault(e);
            }

            throw;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }

    /// <summary>
    /// Throws <see cref="InvalidOperationException"/> when the coordinate system is running a program (another host's
    /// job, or one started at the controller); sends only <c>CLOSE</c> and a status query. <see cref="StartAsync"/>
    /// checks this itself; a caller that sets anything on the controller before the start (the HMI sets the feed)
    /// calls it first, so a refused start leaves the other program untouched.
    /// </summary>
    public async Task EnsureIdleAsync(CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            await EnsureNotRunningAsync(cancellationToken).ConfigureAwait(false);
        }
        finally
        {
            _gate.Release();
        }
    }

    private async Task EnsureNotRunningAsync(CancellationToken cancellationToken)
    {
        await OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        if (await ProgramRunningAsync(cancellationToken).ConfigureAwait(false) == true)
        {
            // Redefining the rotary buffer or sending B0 under a running program would break it off (a real PMAC
            // answers ERR001). Refuse before anything reaches a buffer.
            throw new InvalidOperationException($"{_cs} is running a program: stop it or let it finish, then start again");
        }
    }

    /// <summary>
    /// Continues a job from its record after a host crash: uses the line-probe variable the job recorded; when the
    /// job's start had not finished loading the buffer (no checkpoint yet, or one taken while loading: nothing has
    /// run, how much of the preamble and first chunk arrived is unknown) it clears the buffer and loads the recorded
    /// start again (preamble, first chunk, then the run command); otherwise as <see cref="ResumeAsync(Checkpoint, CancellationToken)"/>.
    /// Throws <see cref="InvalidOperationException"/> when the controller lost the job, or when a start from a line
    /// must be loaded again but the record holds no preamble (a record of an older version): restart from the line.
    /// </summary>
    public Task ResumeAsync(JobRecord job, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(job);
        if (_state != SessionState.Idle)
        {
            throw new InvalidOperationException($"the session is {_state}; resume needs a new session");
        }

        // The lines already in the controller carry the recorded variable: the drain must read that one.
        if (Program.UseLineProbe(job.LineProbeVariable))
        {
            Log.Information("job {Job} was recorded with line probe {Probe}; using it", job.Id, job.LineProbeVariable ?? "(none)");
        }

        if (job.Checkpoint is { } cp && (cp.Loaded || cp.Started))
        {
            return ResumeAsync(cp, cancellationToken);
        }

        if (job.FromLine is { } line && job.Preamble is null)
        {
            throw new InvalidOperationException(
                $"job {job.Id} broke off while loading its start at line {line} and the record holds no preamble: restart from line {line} with a preamble");
        }

        Log.Information("job {Job}: its start broke off while loading the buffer; clearing and loading it again", job.Id);
        return StartAsync(job.FromLine, job.Preamble, cancellationToken);
    }

    /// <summary>
    /// Continues a job after a host crash from its last checkpoint: closes any buffer left open on this port, reads M0,
    /// and continues sending at the checkpoint's position (or, when a download had broken off, once the buffer has
    /// drained, after the block M0 reports). Throws <see cref="InvalidOperationException"/> when the controller lost
    /// the job (M0 went back): restart from the line with a preamble instead.
    /// </summary>
    public async Task ResumeAsync(Checkpoint checkpoint, CancellationToken cancellationToken = default)
    {
        if (_state != SessionState.Idle)
        {
            throw new InvalidOperationException($"the session is {_state}; resume needs a new session");
        }

        if (!checkpoint.Loaded && !checkpoint.Started)
        {
            // Nothing ran and the buffer holds an unknown part of the start: only the start itself can be loaded again.
            throw new InvalidOperationException(
                "the job's start broke off while loading the buffer (nothing has run): start it again (resume from the job record loads the recorded start)");
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            _bufferOpen = true; // unknown: the crashed host may have left it open
            await OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            if (!checkpoint.Started)
            {
                // The crashed host had begun sending but never gave the run command.
                await OnlineAsync(_singleBlock ? $"{_cs} S" : $"{_cs} R", cancellationToken).ConfigureAwait(false);
            }

            _runSent = true;
            _loaded = true;
            var m = await ReadTrackAsync(cancellationToken).ConfigureAwait(false);
            if (m < checkpoint.LastExecutedLine)
            {
                throw new InvalidOperationException(
                    $"the controller reports {_track}={m} but the job had reached line {checkpoint.LastExecutedLine}: it lost the job (reset or abort); restart from line {checkpoint.LastExecutedLine} with a preamble");
            }

            if (checkpoint.Started && await ProgramRunningAsync(cancellationToken).ConfigureAwait(false) == false)
            {
                throw new InvalidOperationException(
                    $"the controller is not running the job (aborted, stopped or reset) at {_track}={m}: restart from line {Math.Max(m, checkpoint.LastExecutedLine)} with a preamble");
            }

            await ReadFeedAsync(cancellationToken).ConfigureAwait(false);
            _next = checkpoint.Next;
            _nextExact = checkpoint.NextExact;
            _chunksDownloaded = checkpoint.ChunksDownloaded;
            _currentChunk = Program.ChunkOfTracked(m);
            _tracked = m;
            _lastSentTag = Math.Max(m, Program.LastTrackedBefore(_next));
            _startTimestamp = _time.GetTimestamp();
            _rateTimestamp = _startTimestamp;
            var pr = await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
            SeedOccupancy(pr);
            _draining = !_nextExact;
            _state = SessionState.Running;
            Raise(StreamingEventKind.Recovered, _draining
                ? $"resumed at line {m}; waiting for the buffer to drain to find where sending broke off"
                : $"resumed at line {m}; sending continues at {_next}", _currentChunk);
            SaveCheckpoint(durable: true);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            // Nothing of the checkpoint was taken over: stay idle so the resume can simply be tried again.
            _state = SessionState.Idle;
            _message = $"resume failed: {e.Message}; try again when the controller answers";
            throw;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }

    /// <summary>
    /// Loads what must be in the buffer before the run command: clears the rotary buffer (leftovers of an earlier job
    /// or of a start that broke off would run first), then the preamble and the first chunk (from the start block).
    /// </summary>
    private async Task LoadAsync(CancellationToken cancellationToken)
    {
        _loaded = false;
        _next = _startAt;
        _nextExact = true;
        _occupancy.Clear();
        _occWords = 0;
        _markersAhead = 0;
        _markersSent = 0;
        _lastSentTag = 0;
        _linesSent = 0;
        _chunksDownloaded = 0;

        // Durable before the buffer is touched: whatever the last checkpoint said about the buffer (a broken first
        // load) stops being true with the CLEAR; a resume from here loads the recorded start again.
        SaveCheckpoint(durable: true);
        _bufferOpen = true;
        await SendAsync("OPEN ROT", cancellationToken).ConfigureAwait(false);
        await SendAsync("CLEAR", cancellationToken).ConfigureAwait(false);
        await SendOnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        if (_preamble is not null)
        {
            await SendBatchAsync(_preamble, advance: false, oneByOne: false, cancellationToken).ConfigureAwait(false);
        }

        await DownloadNextChunkAsync(late: false, cancellationToken).ConfigureAwait(false);
        _loaded = true;
    }

    /// <summary>Timer tick, blocking (for a WinForms timer's <c>Tick</c> handler that cannot await).</summary>
    public void Tick() => TickAsync().GetAwaiter().GetResult();

    /// <summary>
    /// One timer tick: read M0, follow the chunk, let the strategy send, detect the end, write the checkpoint.
    /// A tick that finds the previous one still running returns at once (a slow download never overlaps itself).
    /// Faults do not throw: they set <see cref="State"/> to <see cref="SessionState.Faulted"/> with a message.
    /// </summary>
    public async Task TickAsync(CancellationToken cancellationToken = default)
    {
        if (_state is not (SessionState.Running or SessionState.Held))
        {
            return;
        }

        if (!await _gate.WaitAsync(0, cancellationToken).ConfigureAwait(false))
        {
            return;
        }

        try
        {
            var before = _currentChunk;
            var downloadedBefore = _chunksDownloaded;
            var m = await ReadTrackAsync(cancellationToken).ConfigureAwait(false);
            FollowTrack(m);

            if (++_ticks % 20 == 0)
            {
                // The feed can change from the program (P500= lines) or the panel: refresh it about once a second.
                await ReadFeedAsync(cancellationToken).ConfigureAwait(false);
            }

            if (_draining)
            {
                await DrainStepAsync(cancellationToken).ConfigureAwait(false);
            }
            else
            {
                await _strategy.TickAsync(Context, cancellationToken).ConfigureAwait(false);
                await CheckDryAndDoneAsync(cancellationToken).ConfigureAwait(false);
            }

            SaveCheckpoint(durable: _currentChunk != before || _chunksDownloaded != downloadedBefore || _state == SessionState.Completed);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            Fault(e);
        }
        catch (Exception e) when (e is IOException or InvalidDataException or UnauthorizedAccessException)
        {
            // A chunk file that cannot be read or changed since the split: read before any of its lines is sent,
            // so sending stops at a block boundary and the job stays resumable once the file is right again.
            Fault(e);
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }

    /// <summary>
    /// After a fault, when the link is back or the cause is fixed: closes any buffer left open, and continues (after
    /// the buffer drains when a download broke off). Returns false (still faulted) when the controller cannot be reached.
    /// </summary>
    public async Task<bool> RecoverAsync(CancellationToken cancellationToken = default)
    {
        if (_state != SessionState.Faulted)
        {
            return _state is SessionState.Running or SessionState.Held or SessionState.Completed;
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            _bufferOpen = true;
            await OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            if (!_runSent)
            {
                // The start broke off before the run command, so nothing has run yet. When the loading (preamble,
                // first chunk) broke off, how much of it arrived is not known: clear the buffer and load it again.
                if (!_loaded && await ProgramRunningAsync(cancellationToken).ConfigureAwait(false) != true)
                {
                    await LoadAsync(cancellationToken).ConfigureAwait(false);
                    SaveCheckpoint(durable: true);
                }

                await OnlineAsync(_singleBlock ? $"{_cs} S" : $"{_cs} R", cancellationToken).ConfigureAwait(false);
                _runSent = true;
            }

            _strategy.Reset();
            _draining = !_nextExact;
            _drainStableReads = 0;
            _drainLastTracked = -1;
            _state = SessionState.Running;
            Raise(StreamingEventKind.Recovered, _draining
                ? "link back; waiting for the buffer to drain to find where the broken download stopped"
                : $"recovered; sending continues at {_next}", _currentChunk);
            SaveCheckpoint(durable: true);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            _message = $"still cannot continue: {e.Message}";
            return false;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
        return true;
    }

    /// <summary>Feed hold (<c>&amp;n H</c>).</summary>
    public Task HoldAsync(CancellationToken cancellationToken = default) =>
        CommandAsync($"{_cs} H", "hold", SessionState.Held, cancellationToken);

    /// <summary>Resume motion after a hold (<c>&amp;n R</c>, or <c>&amp;n S</c> in single-block mode).</summary>
    public Task ResumeMotionAsync(CancellationToken cancellationToken = default) =>
        CommandAsync(_singleBlock ? $"{_cs} S" : $"{_cs} R", _singleBlock ? "step" : "resume", SessionState.Running, cancellationToken);

    /// <summary>Run one more block (<c>&amp;n S</c>), the single-block start.</summary>
    public Task StepAsync(CancellationToken cancellationToken = default) =>
        CommandAsync($"{_cs} S", "step", SessionState.Running, cancellationToken);

    /// <summary>Abort (<c>&amp;n A</c>): motion stops at once; the job stays resumable from the last executed line.</summary>
    public Task AbortAsync(CancellationToken cancellationToken = default) =>
        CommandAsync($"{_cs} A", "abort", SessionState.Aborted, cancellationToken);

    /// <summary>Single-block mode on or off: following starts run one block each.</summary>
    public void SetSingleBlock(bool on)
    {
        _singleBlock = on;
        Raise(StreamingEventKind.Command, on ? "single-block mode on" : "single-block mode off", _currentChunk);
    }

    /// <summary>
    /// Live feed change: <c>P500=value</c> in paper mode (feed units), <c>&amp;n %value</c> in override mode (percent).
    /// Sent between ticks, never into an open buffer.
    /// </summary>
    public Task SetFeedAsync(double value, CancellationToken cancellationToken = default)
    {
        if (value < 0 || double.IsNaN(value) || double.IsInfinity(value))
        {
            throw new ArgumentOutOfRangeException(nameof(value), "feed must be a finite non-negative number");
        }

        var v = value.ToString("0.###", CultureInfo.InvariantCulture);
        var cmd = _feedMode == FeedMode.Paper ? $"{FeedVariable}={v}" : $"{_cs} %{v}";
        return CommandAsync(cmd, $"feed {v}", null, cancellationToken, () => _feed = value);
    }

    private string FeedVariable => string.IsNullOrWhiteSpace(Program.Manifest.FeedVariable) ? "P500" : Program.Manifest.FeedVariable.Trim();

    private async Task CommandAsync(string command, string what, SessionState? then, CancellationToken cancellationToken, Action? onSent = null)
    {
        if (_state is SessionState.Idle or SessionState.Completed)
        {
            throw new InvalidOperationException($"cannot {what}: the session is {_state}");
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            await OnlineAsync(command, cancellationToken).ConfigureAwait(false);
            onSent?.Invoke();
            if (then is { } s && _state is not (SessionState.Faulted or SessionState.Completed))
            {
                _state = s;
            }

            Raise(StreamingEventKind.Command, what, _currentChunk);
            SaveCheckpoint(durable: then == SessionState.Aborted);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            Fault(e);
            throw;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }

    // ---- what strategies use (through StreamingContext) ----

    internal double ChunkFraction
    {
        get
        {
            var c = Program.Chunk(_currentChunk);
            var size = Math.Max(1, c.LastSourceLine - c.FirstSourceLine + 1);
            var pos = _tracked - c.FirstSourceLine + 1;
            return (double)pos / size;
        }
    }

    internal async Task<int> ReadLinesAheadAsync(CancellationToken cancellationToken)
    {
        var text = await OnlineAsync("PR", cancellationToken).ConfigureAwait(false);
        var pr = ParseInt(text, "PR");
        while (_occupancy.Count > pr)
        {
            Dequeue();
        }

        return pr;
    }

    internal async Task<bool> HasRoomForRestOfChunkAsync(CancellationToken cancellationToken)
    {
        var need = WordsOfRestOfChunk();
        await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        return need <= FreeWords;
    }

    internal async Task DownloadNextChunkAsync(bool late, CancellationToken cancellationToken)
    {
        var p = Program.Normalize(_next);
        _next = p;
        if (p.Chunk > Program.TotalChunks)
        {
            return;
        }

        if (p.Line > 0)
        {
            var rest = Program.Body(p.Chunk).Skip(p.Line).ToList();
            await SendBatchAsync(rest, advance: true, oneByOne: false, cancellationToken).ConfigureAwait(false);
            Raise(StreamingEventKind.ChunkDownloaded, $"rest of chunk {p.Chunk} sent ({rest.Count} lines)", p.Chunk);
            return;
        }

        var body = Program.Body(p.Chunk);
        var path = Program.SendPath(p.Chunk, out var temporary);
        _nextExact = false;
        SaveCheckpoint(durable: false);
        _bufferOpen = true;
        var sw = Stopwatch.StartNew();

        // The paper's call: Download(pmacNumber, file, macro, map, log, dnld) with all four flags true.
        DownloadReport report;
        try
        {
            report = await _devices.DownloadAsync(Options.PmacNumber, path, new DownloadOptions(true, true, true, true), cancellationToken).ConfigureAwait(false);
        }
        finally
        {
            if (temporary)
            {
                DeleteQuietly(Path.GetDirectoryName(path)!);
            }
        }

        Log.Debug("download {File} -> {Success} {Lines} lines in {Ms:0.0} ms", path, report.Success, report.LinesSent, sw.Elapsed.TotalMilliseconds);
        if (report.Success)
        {
            _bufferOpen = false;
            foreach (var l in body)
            {
                Accept(l);
            }

            _next = new StreamPosition(p.Chunk + 1, 0);
            _nextExact = true;
            _chunksDownloaded++;
            var at = _state == SessionState.Idle ? "the start" : $"{_track}={_tracked}, {ChunkFraction:P0} of chunk {_currentChunk}";
            Log.Information("{Kind} chunk {Chunk} ({Lines} lines) at {At}", late ? "late download of" : "downloaded", p.Chunk, body.Count, at);
            Raise(late ? StreamingEventKind.ChunkDownloadedLate : StreamingEventKind.ChunkDownloaded,
                late ? $"chunk {p.Chunk} downloaded late (window missed) at {at}" : $"chunk {p.Chunk} downloaded at {at}", p.Chunk);
            return;
        }

        if (report.Error is { } err)
        {
            // Lines before the refused one are in the buffer; continue exactly there later.
            var accepted = 0;
            foreach (var l in body)
            {
                if (l.FileLine >= err.Line)
                {
                    break;
                }

                Accept(l);
                accepted++;
            }

            _next = new StreamPosition(p.Chunk, accepted);
            _nextExact = true;
            await TryCloseAsync(cancellationToken).ConfigureAwait(false);
            throw new PmacErrorException(err.Number, err.Text);
        }

        throw new PmacLinkException($"download of {path} failed without a reason");
    }

    internal Task SendLinesAsync(int maxLines, int maxWords, bool oneByOne, CancellationToken cancellationToken)
    {
        var lines = new List<ProgramLine>();
        var words = 0;
        var p = Program.Normalize(_next);
        while (lines.Count < maxLines && p.Chunk <= Program.TotalChunks)
        {
            var l = Program.Body(p.Chunk)[p.Line];
            if (words + l.Words > maxWords)
            {
                break;
            }

            lines.Add(l);
            words += l.Words;
            p = Program.Normalize(new StreamPosition(p.Chunk, p.Line + 1));
        }

        return lines.Count == 0 ? Task.CompletedTask : SendBatchAsync(lines, advance: true, oneByOne, cancellationToken);
    }

    internal double LeadSeconds() => LeadSecondsThrough(_lastSentTag, _markersAhead);

    internal Task SendUntilLeadAsync(double targetSeconds, int maxLines, CancellationToken cancellationToken)
    {
        var lines = new List<ProgramLine>();
        var words = 0;
        var free = FreeWords;
        var tag = _lastSentTag;
        var markers = _markersAhead;
        var p = Program.Normalize(_next);
        while (lines.Count < maxLines && p.Chunk <= Program.TotalChunks)
        {
            var l = Program.Body(p.Chunk)[p.Line];
            if (words + l.Words > free)
            {
                break;
            }

            lines.Add(l);
            words += l.Words;
            if (l.TrackedLine > 0)
            {
                tag = l.TrackedLine;
                markers++;
                if (LeadSecondsThrough(tag, markers) >= targetSeconds)
                {
                    p = Program.Normalize(new StreamPosition(p.Chunk, p.Line + 1));
                    break;
                }
            }

            p = Program.Normalize(new StreamPosition(p.Chunk, p.Line + 1));
        }

        // Non-motion lines right after the last move go with it, so a batch ends at a block boundary.
        while (p.Chunk <= Program.TotalChunks && lines.Count < maxLines + 16)
        {
            var l = Program.Body(p.Chunk)[p.Line];
            if (l.TrackedLine > 0 || words + l.Words > free)
            {
                break;
            }

            lines.Add(l);
            words += l.Words;
            p = Program.Normalize(new StreamPosition(p.Chunk, p.Line + 1));
        }

        return lines.Count == 0 ? Task.CompletedTask : SendBatchAsync(lines, advance: true, oneByOne: false, cancellationToken);
    }

    internal void Note(string message)
    {
        _message = message;
        Log.Information("{Message}", message);
    }

    // ---- internals ----

    private double LeadSecondsThrough(int lastTag, int markersAhead)
    {
        if (MoveTimes is not null)
        {
            return MoveTimes.SecondsBetween(_tracked, lastTag) / LiveFeedFactor;
        }

        return _blocksPerSecond > 0 ? markersAhead / _blocksPerSecond : 0;
    }

    private int WordsOfRestOfChunk()
    {
        var p = Program.Normalize(_next);
        if (p.Chunk > Program.TotalChunks)
        {
            return 0;
        }

        var body = Program.Body(p.Chunk);
        var words = 0;
        for (var i = p.Line; i < body.Count; i++)
        {
            words += body[i].Words;
        }

        return words;
    }

    private void CheckChunksFit()
    {
        var room = Options.BufferWords - Options.SafetyWords;
        foreach (var c in Program.Manifest.Chunks)
        {
            // The line probe adds a word to each non-motion line (feed-variable lines included: at most one line per
            // source block), or to every line with paper placement (at most two lines per block).
            var probeWords = Program.LineProbeVariable is null ? 0 : Program.ProbesEveryLine ? 2 * c.BlockCount : c.BlockCount;
            if (c.EstimatedWords + probeWords > room)
            {
                throw new InvalidOperationException(
                    $"chunk {c.Index} ({c.FileName}) needs about {c.EstimatedWords + probeWords} words (line probe included) but the rotary buffer holds {Options.BufferWords} (less {Options.SafetyWords} margin): split into smaller chunks or define a larger buffer");
            }
        }
    }

    private async Task SendBatchAsync(List<ProgramLine> lines, bool advance, bool oneByOne, CancellationToken cancellationToken)
    {
        if (advance)
        {
            _nextExact = false;
            SaveCheckpoint(durable: false);
        }

        _bufferOpen = true;
        var accepted = 0;
        try
        {
            if (oneByOne)
            {
                await SendAsync("OPEN ROT", cancellationToken).ConfigureAwait(false);
                foreach (var l in lines)
                {
                    await SendAsync(l.Text, cancellationToken).ConfigureAwait(false);
                    if (advance)
                    {
                        Accept(l);
                        Advance();
                    }

                    accepted++;
                }

                await SendAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            }
            else
            {
                var batch = new List<string>(lines.Count + 2) { "OPEN ROT" };
                batch.AddRange(lines.Select(l => l.Text));
                batch.Add("CLOSE");
                var sw = Stopwatch.StartNew();
                await _conn.DownloadAsync(batch, cancellationToken).ConfigureAwait(false);
                MeasureRoundTrip(sw.Elapsed.TotalSeconds);
                Log.Debug("{Device} sent {Count} program lines ({Ms:0.0} ms)", _conn.Description, lines.Count, sw.Elapsed.TotalMilliseconds);
                if (advance)
                {
                    foreach (var l in lines)
                    {
                        Accept(l);
                        Advance();
                    }
                }

                accepted = lines.Count;
            }

            _bufferOpen = false;
            if (advance)
            {
                _nextExact = true;
            }
        }
        catch (PmacErrorException e)
        {
            if (!oneByOne && advance && e.LineInBatch is { } i)
            {
                // Index 0 was OPEN ROT: lines 1..i-1 of the batch were accepted.
                for (var k = 0; k < Math.Min(i - 1, lines.Count); k++)
                {
                    Accept(lines[k]);
                    Advance();
                }

                _nextExact = true;
            }
            else if (oneByOne && advance)
            {
                _nextExact = true;
            }

            await TryCloseAsync(cancellationToken).ConfigureAwait(false);
            throw;
        }
    }

    /// <summary>Tracked (move) lines from <paramref name="from"/> up to, not including, <paramref name="to"/>; stops counting past <paramref name="limit"/>.</summary>
    private int MovesBetween(StreamPosition from, StreamPosition to, int limit)
    {
        var n = 0;
        for (var p = Program.Normalize(from); Compare(p, to) < 0 && p.Chunk <= Program.TotalChunks; p = Program.Normalize(new StreamPosition(p.Chunk, p.Line + 1)))
        {
            if (Program.Body(p.Chunk)[p.Line].TrackedLine > 0 && ++n > limit)
            {
                break;
            }
        }

        return n;
    }

    private static void DeleteQuietly(string folder)
    {
        try
        {
            Directory.Delete(folder, recursive: true);
        }
        catch (IOException e)
        {
            Log.Warning("could not delete {Folder}: {Error}", folder, e.Message);
        }
        catch (UnauthorizedAccessException e)
        {
            Log.Warning("could not delete {Folder}: {Error}", folder, e.Message);
        }
    }

    private void Advance() => _next = Program.Normalize(new StreamPosition(_next.Chunk, _next.Line + 1));

    private void Accept(ProgramLine l)
    {
        _linesSent++;
        if (l.TrackedLine > 0)
        {
            _lastSentTag = l.TrackedLine;
            _markersAhead++;
            _markersSent++;
        }

        _occupancy.Enqueue((_lastSentTag, l.Words, l.TrackedLine > 0));
        _occWords += l.Words;
    }

    private void Dequeue()
    {
        var (_, words, marker) = _occupancy.Dequeue();
        _occWords -= words;
        if (marker)
        {
            _markersAhead--;
        }
    }

    private void SeedOccupancy(int linesAhead)
    {
        var c = Program.Chunk(_currentChunk);
        var perLine = c.BlockCount > 0 ? Math.Max(1, (int)Math.Ceiling((double)c.EstimatedWords / c.BlockCount)) : 6;
        for (var i = 0; i < linesAhead; i++)
        {
            _occupancy.Enqueue((_tracked + 1, perLine, true));
            _occWords += perLine;
            _markersAhead++;
        }
    }

    private async Task TryCloseAsync(CancellationToken cancellationToken)
    {
        try
        {
            await SendAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            _bufferOpen = false;
        }
        catch (PmacErrorException)
        {
            _bufferOpen = false; // CLOSE refused: nothing was open
        }
        catch (PmacLinkException)
        {
            // Left for recovery, which sends CLOSE first.
        }
    }

    private void FollowTrack(int m)
    {
        _tracked = m;
        if (MoveTimes is not null)
        {
            var wall = _time.GetElapsedTime(_etaOrigin).TotalSeconds;
            _eta.Observe(wall, m > 0 ? MoveTimes.SecondsBetween(0, m - 1) : 0, LiveFeedFactor, counting: _state == SessionState.Running);
        }

        while (_occupancy.Count > 0 && _occupancy.Peek().Tag < m)
        {
            Dequeue();
        }

        var now = _time.GetTimestamp();
        var executed = _markersSent - _markersAhead;
        var dt = _time.GetElapsedTime(_rateTimestamp, now).TotalSeconds;
        if (dt >= 0.25 && executed > _rateMarkersExecuted)
        {
            var rate = (executed - _rateMarkersExecuted) / dt;
            _blocksPerSecond = _blocksPerSecond <= 0 ? rate : (0.7 * _blocksPerSecond) + (0.3 * rate);
            _rateTimestamp = now;
            _rateMarkersExecuted = executed;
        }

        var chunk = Program.ChunkOfTracked(m);
        if (chunk != _currentChunk)
        {
            var from = _currentChunk;
            _currentChunk = chunk;
            Raise(StreamingEventKind.ChunkEntered, $"execution entered chunk {chunk} (from {from}) at line {m}", chunk);
        }
    }

    private async Task DrainStepAsync(CancellationToken cancellationToken)
    {
        // Drained means every line calculated (PR 0) and every calculated move done: with lookahead M0 still lags
        // the calculated lines until motion stops, so the coordinate system status must say "not moving" as well.
        var pr = await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        var still = pr == 0 && await MotionStoppedAsync(cancellationToken).ConfigureAwait(false);
        if (still && _tracked == _drainLastTracked)
        {
            _drainStableReads++;
        }
        else
        {
            _drainStableReads = 0;
        }

        _drainLastTracked = _tracked;
        if (_drainStableReads < (_statusUnsupported ? 5 : 1))
        {
            return;
        }

        // Everything the controller got has run: M0 names the last move that arrived, the line probe the last
        // non-motion line (M08, S, P500=...). Sending resumes after the later of the two, never before _next.
        var after = Program.PositionAfterBlock(_tracked) ?? _next;
        if (Compare(after, _next) > 0)
        {
            _next = after;
        }

        if (Program.LineProbeVariable is { } probe)
        {
            var value = await ReadProbeAsync(probe, cancellationToken).ConfigureAwait(false);
            if (Program.PositionAfterProbe(value) is { } afterProbe && Compare(afterProbe, _next) > 0)
            {
                // Only lines without a move can lie between M0's block and the probe's line (a move that arrived
                // would have moved M0; with paper placement M0 lags by one move). Anything else is not this job's
                // value (a program or PLC wrote the variable): not trusted, so nothing is skipped on its word.
                if (MovesBetween(after, afterProbe, Program.ProbesEveryLine ? 1 : 0) <= (Program.ProbesEveryLine ? 1 : 0))
                {
                    Log.Information("line probe {Probe}={Value}: the controller got lines up to {Position}", probe, value, afterProbe);
                    _next = afterProbe;
                }
                else
                {
                    Log.Warning("line probe {Probe}={Value} points past moves M0={Tracked} did not reach: ignored (is {Probe} used elsewhere?)", probe, value, _tracked, probe);
                }
            }
        }

        while (_occupancy.Count > 0)
        {
            Dequeue();
        }

        _lastSentTag = _tracked;
        _nextExact = true;
        _draining = false;
        _strategy.Reset();
        Note($"buffer drained at line {_tracked}; sending continues at {_next}");
        Raise(StreamingEventKind.Recovered, _message, _currentChunk);
    }

    /// <summary>
    /// Reads the coordinate system status (<c>&amp;n??</c>): true when no move is executing or queued (second word:
    /// bit 17 in position, bit 21 segments queued). A controller that does not answer it in that shape is treated as
    /// stopped, and the drain then waits for several stable readings instead.
    /// </summary>
    private async Task<bool> MotionStoppedAsync(CancellationToken cancellationToken)
    {
        if (_statusUnsupported)
        {
            return true;
        }

        // An ERR reply here is a fault like any other (it must not be mistaken for "stopped").
        var text = FirstValue(await OnlineAsync($"{_cs}??", cancellationToken).ConfigureAwait(false)).Replace(" ", string.Empty, StringComparison.Ordinal);
        if (text.Length >= 12 && int.TryParse(text.AsSpan(6, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var w2))
        {
            return (w2 & (1 << 17)) != 0 && (w2 & (1 << 21)) == 0;
        }

        Log.Warning("unexpected status reply '{Text}' to {Cs}??; the drain falls back to stable M0 readings", text, _cs);
        _statusUnsupported = true;
        return true;
    }

    /// <summary>Program-running bit of the coordinate system status (first word, bit 0); null when the reply is not understood.</summary>
    private async Task<bool?> ProgramRunningAsync(CancellationToken cancellationToken)
    {
        var text = FirstValue(await OnlineAsync($"{_cs}??", cancellationToken).ConfigureAwait(false)).Replace(" ", string.Empty, StringComparison.Ordinal);
        return text.Length >= 6 && int.TryParse(text.AsSpan(0, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var w1)
            ? (w1 & 1) != 0
            : null;
    }

    private async Task CheckDryAndDoneAsync(CancellationToken cancellationToken)
    {
        var final = Program.FinalTrackedLine;
        var sentAll = AllSent;
        if (!sentAll && _lastSentTag > _tracked)
        {
            _dry = false;
            return;
        }

        // Everything sent has been reached: ask the controller whether the buffer is empty.
        var pr = await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        if (!sentAll)
        {
            if (pr == 0 && !_dry && _state == SessionState.Running)
            {
                _dry = true;
                _underruns++;
                Raise(StreamingEventKind.Underrun, $"rotary buffer ran dry at line {_tracked}", _currentChunk);
            }
            else if (pr > 0)
            {
                _dry = false;
            }

            return;
        }

        if (pr == 0 && _tracked == _completeLastTracked)
        {
            _completeStableReads++;
        }
        else
        {
            _completeStableReads = 0;
        }

        _completeLastTracked = _tracked;
        if (pr == 0 && (_tracked >= final || _completeStableReads >= 2))
        {
            _state = SessionState.Completed;
            Note($"completed: {Program.BlocksThrough(_tracked)} of {Program.Manifest.TotalMotionBlocks} blocks reached");
            Raise(StreamingEventKind.Completed, _message, _currentChunk);
        }
    }

    private static int Compare(StreamPosition a, StreamPosition b) =>
        a.Chunk != b.Chunk ? a.Chunk.CompareTo(b.Chunk) : a.Line.CompareTo(b.Line);

    private async Task<int> ReadTrackAsync(CancellationToken cancellationToken)
    {
        var sw = Stopwatch.StartNew();
        var text = await OnlineAsync(_track, cancellationToken).ConfigureAwait(false);
        MeasureRoundTrip(sw.Elapsed.TotalSeconds);
        return ParseInt(text, _track);
    }

    private async Task<long> ReadProbeAsync(string probe, CancellationToken cancellationToken)
    {
        var text = FirstValue(await OnlineAsync(probe, cancellationToken).ConfigureAwait(false));
        return double.TryParse(text, NumberStyles.Float, CultureInfo.InvariantCulture, out var v) && v >= 0 && v < 1e15
            ? (long)Math.Round(v)
            : throw new PmacLinkException($"unexpected reply '{text}' to {probe}");
    }

    private async Task ReadFeedAsync(CancellationToken cancellationToken)
    {
        try
        {
            var text = await OnlineAsync(_feedMode == FeedMode.Paper ? FeedVariable : $"{_cs} %", cancellationToken).ConfigureAwait(false);
            _feed = double.TryParse(FirstValue(text), NumberStyles.Float, CultureInfo.InvariantCulture, out var v) ? v : null;
        }
        catch (PmacErrorException)
        {
            _feed = null;
        }
    }

    private void MeasureRoundTrip(double seconds) =>
        _rttSeconds = _rttSeconds <= 0 ? seconds : (0.8 * _rttSeconds) + (0.2 * seconds);

    private static string FirstValue(string text)
    {
        var t = text.Trim();
        var nl = t.IndexOf('\n');
        return nl >= 0 ? t[..nl].Trim() : t;
    }

    private static int ParseInt(string text, string what)
    {
        var t = FirstValue(text);
        if (double.TryParse(t, NumberStyles.Float, CultureInfo.InvariantCulture, out var v))
        {
            return (int)Math.Round(v);
        }

        throw new PmacLinkException($"unexpected reply '{text}' to {what}");
    }

    /// <summary>An online command: refused while this session has a buffer open (it would be stored, not run).</summary>
    private Task<string> OnlineAsync(string command, CancellationToken cancellationToken)
    {
        if (_bufferOpen && !command.Equals("CLOSE", StringComparison.OrdinalIgnoreCase))
        {
            throw new InvalidOperationException($"'{command}' must not be sent while a buffer is open on this port (it would be stored in the buffer)");
        }

        return SendOnlineAsync(command, cancellationToken);
    }

    private async Task<string> SendOnlineAsync(string command, CancellationToken cancellationToken)
    {
        var reply = await SendAsync(command, cancellationToken).ConfigureAwait(false);
        if (command.Equals("CLOSE", StringComparison.OrdinalIgnoreCase))
        {
            _bufferOpen = false;
        }

        return reply;
    }

    private async Task OnlineIgnoringAsync(string command, CancellationToken cancellationToken)
    {
        try
        {
            await OnlineAsync(command, cancellationToken).ConfigureAwait(false);
        }
        catch (PmacErrorException e)
        {
            Log.Debug("{Command} refused (ERR{Number:000}), ignored", command, e.Number);
        }
    }

    private async Task<string> SendAsync(string command, CancellationToken cancellationToken)
    {
        var sw = Stopwatch.StartNew();
        var reply = await _conn.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
        Log.Debug("{Device} {Command} -> {Reply} ({Ms:0.000} ms)", _conn.Description, command, reply, sw.Elapsed.TotalMilliseconds);
        return reply;
    }

    private void Fault(Exception e)
    {
        _state = SessionState.Faulted;
        var at = $"last executed line {_tracked}, sending stopped at {_next}";
        _message = e switch
        {
            PmacLinkException => $"link to the controller lost ({e.Message}); {at}. The controller keeps running the lines it holds. When the link is back, resume (pmacstream resume, or Resume in the HMI): nothing is lost or repeated.",
            PmacErrorException pe => $"controller refused '{pe.Command}' with ERR{pe.Number:000} ({PmacErrors.Describe(pe.Number)}); {at}. Fix the cause, then resume.",
            IOException or InvalidDataException or UnauthorizedAccessException => $"{e.Message}; {at}. The controller runs the lines it holds, then stops. Put the chunk right (or split again), then resume: nothing is lost or repeated.",
            _ => $"{e.Message}; {at}",
        };
        Log.Error("Streaming stopped: {Message}", _message);
        Raise(StreamingEventKind.Fault, _message, _currentChunk);
        SaveCheckpoint(durable: true);
    }

    private void SaveCheckpoint(bool durable)
    {
        if (_sink is null)
        {
            return;
        }

        if (_currentChunk != _lastDurableChunk)
        {
            durable = true;
            _lastDurableChunk = _currentChunk;
        }

        _sink.Save(Checkpoint, durable);
    }

    private void Raise(StreamingEventKind kind, string message, int chunk)
    {
        if (kind is StreamingEventKind.Fault or StreamingEventKind.ChunkDownloadedLate or StreamingEventKind.Underrun or StreamingEventKind.Completed or StreamingEventKind.Recovered)
        {
            _message = message;
        }

        if (kind != StreamingEventKind.ChunkDownloaded)
        {
            Log.Information("{Kind}: {Message}", kind, message);
        }

        EventRaised?.Invoke(this, new StreamingEvent(kind, message, chunk, _tracked));
    }

    private void PublishStatus() => StatusChanged?.Invoke(this, Status);
}

/// <summary>What a strategy may see and do inside a tick; the session keeps order, the open-buffer rule and checkpoints.</summary>
public sealed class StreamingContext
{
    private readonly StreamingSession _s;

    internal StreamingContext(StreamingSession session) => _s = session;

    /// <summary>The session's options.</summary>
    public StreamingOptions Options => _s.Options;

    /// <summary>The program.</summary>
    public ChunkedProgram Program => _s.Program;

    /// <summary>The tracking variable read this tick.</summary>
    public int TrackedLine => _s.Tracked;

    /// <summary>The chunk executing (from the tracking variable).</summary>
    public int CurrentChunk => _s.CurrentChunk;

    /// <summary>Where M0 lies in the current chunk, as a fraction of its source lines (0.65 = line 650 of 1000).</summary>
    public double ChunkFraction => _s.ChunkFraction;

    /// <summary>The next program line to send.</summary>
    public StreamPosition Next => _s.Next;

    /// <summary>True when every line was sent.</summary>
    public bool AllSent => _s.AllSent;

    /// <summary>Measured round trip of a query, seconds (smoothed).</summary>
    public double RoundTripSeconds => _s.RoundTripSeconds;

    /// <summary>Estimated free words in the rotary buffer.</summary>
    public int FreeWords => _s.FreeWords;

    /// <summary>Reads <c>PR</c> (lines ahead) and updates the occupancy estimate.</summary>
    public Task<int> ReadLinesAheadAsync(CancellationToken cancellationToken) => _s.ReadLinesAheadAsync(cancellationToken);

    /// <summary>Reads <c>PR</c>; true when the rest of the next chunk fits in the free words.</summary>
    public Task<bool> HasRoomForRestOfChunkAsync(CancellationToken cancellationToken) => _s.HasRoomForRestOfChunkAsync(cancellationToken);

    /// <summary>Downloads the next chunk (the whole file through <c>Download</c>, or the rest of a broken-off one).</summary>
    public Task DownloadNextChunkAsync(bool late, CancellationToken cancellationToken) => _s.DownloadNextChunkAsync(late, cancellationToken);

    /// <summary>Sends up to <paramref name="maxLines"/> lines within <paramref name="maxWords"/> words, in one batch or line by line.</summary>
    public Task SendLinesAsync(int maxLines, int maxWords, bool oneByOne, CancellationToken cancellationToken) => _s.SendLinesAsync(maxLines, maxWords, oneByOne, cancellationToken);

    /// <summary>Seconds of motion in the buffer ahead of the executing block (move times, or the measured block rate).</summary>
    public double LeadSeconds() => _s.LeadSeconds();

    /// <summary>Sends lines until the lead reaches <paramref name="targetSeconds"/>, bounded by free words and <paramref name="maxLines"/>.</summary>
    public Task SendUntilLeadAsync(double targetSeconds, int maxLines, CancellationToken cancellationToken) => _s.SendUntilLeadAsync(targetSeconds, maxLines, cancellationToken);

    /// <summary>Logs a note and shows it in the status message.</summary>
    public void Note(string message) => _s.Note(message);
}
