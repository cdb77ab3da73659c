using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// One job streaming a split program into a coordinate system's rotary buffer. The host calls <see cref="TickAsync"/>
/// from its timer, every <see cref="StreamingOptions.TickPeriod"/> (the HMI's
/// <c>timer1_Tick</c>); each tick reads the tracking variable (M0), lets the strategy send what it wants, and writes a
/// checkpoint when it changed. Operator commands (hold, resume, abort, feed, step) are sent between ticks, never while a buffer is open.
/// Whatever fails, no block is skipped, repeated or reordered: on an <c>ERRnnn</c> or a lost link the session stops
/// sending, keeps the exact position (or, when a download broke off mid-way, waits for the buffer to drain and
/// re-derives it from M0), and <see cref="RecoverAsync"/> or <see cref="ResumeAsync(Checkpoint, CancellationToken)"/> continues.
/// </summary>
/// <remarks>
/// The session keeps the tick, the state and the operator commands; its parts do the rest: <see cref="ControllerChannel"/>
/// (commands, the open-buffer rule) and <see cref="ControllerQueries"/> (M0, <c>PR</c>, status, feed, probe),
/// <see cref="StartSequence"/> (the atomic start), <see cref="RotaryBufferModel"/> (occupancy and free room),
/// <see cref="ProgramSender"/> (the sending primitives), <see cref="BufferDrain"/> and <see cref="JobRecovery"/> (drain
/// and recovery), <see cref="CompletionDetector"/> (underruns and the end), <see cref="CheckpointWriter"/>,
/// <see cref="ExecutionPace"/> (rate, lead, ETA) and <see cref="JobLog"/> (events and the status message).
/// </remarks>
public sealed partial class StreamingSession
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    private readonly IStreamingStrategy _strategy;
    private readonly TimeProvider _time;
    private readonly SemaphoreSlim _gate = new(1, 1);
    private readonly CoordinateSystemCommands _cs;
    private readonly ControllerChannel _channel;
    private readonly ControllerQueries _queries;
    private readonly RotaryBufferModel _buffer;
    private readonly ProgramSender _sender;
    private readonly BufferDrain _drain = new();
    private readonly CompletionDetector _completion = new();
    private readonly ProgramStopWatch _stops;
    private readonly ExecutedBlockCount _executed;
    private readonly CheckpointWriter _checkpoints;
    private readonly ExecutionPace _pace;
    private readonly StartSequence _start;
    private readonly JobLog _log;

    private SessionState _state = SessionState.Idle;
    private int _tracked;
    private int _currentChunk = 1;
    private bool _singleBlock;
    private bool _optionalStop;
    private bool _runSent;
    private long _ticks;
    private bool _resumedFromCheckpoint;

    /// <summary>Creates a session on a PComm-style device facade; downloads go through its <c>Download</c>.</summary>
    public StreamingSession(IPmacDevices devices, ChunkedProgram program, StreamingOptions options, ICheckpointSink? checkpoints = null, IMoveTimes? moveTimes = null, TimeProvider? time = null, IStreamingStrategy? strategy = null)
    {
        _channel = new ControllerChannel(devices[options.PmacNumber]);
        Program = program;
        Options = options;
        _time = time ?? TimeProvider.System;
        _strategy = strategy ?? StreamingStrategies.Create(options.Strategy);
        _cs = new CoordinateSystemCommands(options.CoordinateSystem, options.Feed ?? program.Manifest.Feed, program.Manifest.FeedVariable);
        _singleBlock = options.SingleBlock;
        _stops = new ProgramStopWatch(options.StatusEveryTicks);
        _executed = new ExecutedBlockCount(program);
        _optionalStop = options.OptionalStop;
        program.UseLineProbe(options.LineProbeVariable);
        _queries = new ControllerQueries(_channel, _cs, program.Sync);
        _buffer = new RotaryBufferModel(options.BufferWords, options.SafetyWords, Pipelined(_strategy, options) ? l => Math.Max(l.Words, ControllerWords.Of(l.Text)) : null);
        _checkpoints = new CheckpointWriter(checkpoints, () => Checkpoint);
        _sender = new ProgramSender(program, _channel, devices, options.PmacNumber, _buffer, () => SaveCheckpoint(durable: false));
        _pace = new ExecutionPace(_time, moveTimes, _cs.FeedMode);
        _start = new StartSequence(program, options, _cs, _channel, _queries, _sender, _buffer, () => SaveCheckpoint(durable: true), ct => DownloadNextChunkAsync(late: false, ct));
        _log = new JobLog(this);
        Context = new StreamingContext(this, _sender, _buffer, _channel, _pace);
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
    public IMoveTimes? MoveTimes => _pace.MoveTimes;

    /// <summary>The strategy feeding the buffer.</summary>
    public IStreamingStrategy Strategy => _strategy;

    /// <summary>
    /// The least lead (seconds of motion ahead of the executing block, from the move times) seen after a tick's send
    /// while the job ran with lines still to send; infinity before. What the link-fault bench reports per strategy.
    /// </summary>
    public double WorstLeadSeconds { get; private set; } = double.PositiveInfinity;

    private void NoteLead()
    {
        if (_state == SessionState.Running && Tracked > 0 && !_sender.AllSent)
        {
            WorstLeadSeconds = Math.Min(WorstLeadSeconds, Context.LeadSeconds());
        }
    }

    /// <summary>The state.</summary>
    public SessionState State => _state;

    /// <summary>Single-block mode: starts run one block (<c>&amp;n S</c>).</summary>
    public bool SingleBlock => _singleBlock;

    /// <summary>The next program line to send.</summary>
    public StreamPosition Next => _sender.Next;

    /// <summary>Raised after every tick and command with the new status (on the ticking thread).</summary>
    public event EventHandler<StreamingStatus>? StatusChanged;

    /// <summary>Raised for job events: downloads, late windows, chunk changes, faults, completion.</summary>
    public event EventHandler<StreamingEvent>? EventRaised
    {
        add => _log.Raised += value;
        remove => _log.Raised -= value;
    }

    internal StreamingContext Context { get; }

    internal int Tracked => _tracked;

    internal int CurrentChunk => _currentChunk;

    /// <summary>
    /// WRITEBUFFER packets the full strategy may keep in flight: the setting's, but one after a resume from a
    /// checkpoint, whose buffer may have been sized from the controller's memory to other than the setting (the
    /// one-in-flight strategy learns the real size from <c>ERR006</c>, which with several in flight would leave a gap).
    /// </summary>
    internal int PacketsInFlight => _resumedFromCheckpoint ? 1 : Options.PacketsInFlight;

    /// <summary>The status now.</summary>
    public StreamingStatus Status
    {
        get
        {
            var executed = _executed.Through(_tracked);
            var total = Math.Max(1, Program.Manifest.TotalMotionBlocks);
            var eta = _state == SessionState.Completed ? TimeSpan.Zero
                : MoveTimes is not null ? _pace.EtaByMoveTimes(_tracked, Program.FinalTrackedLine)
                : _pace.EtaByBlockRate(executed, Program.Manifest.TotalMotionBlocks);
            return new StreamingStatus(
                _state,
                Program.TotalChunks,
                Program.Manifest.TotalMotionBlocks,
                _currentChunk,
                _tracked,
                executed,
                Math.Clamp(100.0 * executed / total, 0, 100),
                _pace.Feed,
                _pace.Elapsed,
                eta,
                _sender.ChunksDownloaded,
                _buffer.LinesSent,
                _completion.Underruns,
                _log.Message,
                _state == SessionState.Stopped ? _stops.Stop : null);
        }
    }

    /// <summary>The checkpoint now (what a crash-safe resume needs).</summary>
    public Checkpoint Checkpoint => new(_tracked, _currentChunk, _sender.Next, _sender.NextExact, _sender.ChunksDownloaded, _state, _time.GetUtcNow(), _runSent, _start.Loaded || _runSent);

    /// <summary>True while the optional-stop switch is on: the controller stops at <c>M01</c>.</summary>
    public bool OptionalStop => _optionalStop;

    private string OptionalStopCommand => $"{Options.OptionalStopVariable}={(_optionalStop ? 1 : 0)}";

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
            _buffer.EnsureChunksFit(Program);

            // Recorded before anything is sent: a host that dies from here until the load completed resumes by
            // clearing and loading this same start again (which comes back here, to the check below).
            _checkpoints.RecordStart(new JobStart(fromLine, preamble is { Count: > 0 } ? preamble.ToList() : null, Program.LineProbeVariable));

            await _start.EnsureNotRunningAsync(cancellationToken).ConfigureAwait(false);
            await _start.PrepareAsync(cancellationToken).ConfigureAwait(false);
            await _channel.OnlineAsync(OptionalStopCommand, cancellationToken).ConfigureAwait(false);
            _stops.Reset(0);
            await ReadFeedAsync(cancellationToken).ConfigureAwait(false);
            _currentChunk = start.Chunk;
            _pace.Restart();
            _start.Plan(start, preamble);
            await _start.LoadAsync(cancellationToken).ConfigureAwait(false);
            _state = SessionState.Running;
            SaveCheckpoint(durable: true); // loaded, not started: a resume gives the run command
            await _channel.OnlineAsync(RunCommand, cancellationToken).ConfigureAwait(false);
            _runSent = true;
            Raise(StreamingEventKind.Started, fromLine is { } f ? $"started at line {f} ({_strategy.Name})" : $"started ({_strategy.Name})", _sender.Next.Chunk);
            SaveCheckpoint(durable: true);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            if (_buffer.LinesSent == 0 && _sender.NextExact && !_channel.BufferOpen)
            {
                // Nothing of the program reached the buffer: the start can simply be tried again.
                _state = SessionState.Idle;
                _log.Message = $"start failed: {e.Message}";
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
            await _start.EnsureNotRunningAsync(cancellationToken).ConfigureAwait(false);
        }
        finally
        {
            _gate.Release();
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

        if (JobRecovery.RouteOf(job) == ResumeRoute.FromCheckpoint)
        {
            return ResumeAsync(job.Checkpoint!, cancellationToken);
        }

        Log.Information("job {Job}: its start broke off while loading the buffer; clearing and loading it again", job.Id);
        return StartAsync(job.FromLine, job.Preamble, cancellationToken);
    }

    /// <summary>
    /// Continues a job after a host crash from its last checkpoint, with the controller as the truth: closes any buffer
    /// left open on this port, reads where the controller is (<c>PR</c>, M0, running, the line probe) and reconciles it
    /// with the checkpoint (<see cref="ResumeReconciliation"/>). Sending continues at the checkpoint's position when they
    /// agree; when a send was under way or the controller holds more than the checkpoint says was sent, once the buffer
    /// has drained, after the last line the controller got. Throws <see cref="ControllerLostJobException"/> when the
    /// controller stopped the job (restart from its line with a preamble) and <see cref="ResumeRefusedException"/> when
    /// the two disagree in a way that could repeat or skip a block; nothing but <c>CLOSE</c> and queries is sent then.
    /// </summary>
    public async Task ResumeAsync(Checkpoint checkpoint, CancellationToken cancellationToken = default)
    {
        if (_state != SessionState.Idle)
        {
            throw new InvalidOperationException($"the session is {_state}; resume needs a new session");
        }

        JobRecovery.EnsureLoaded(checkpoint);
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            _channel.BufferOpen = true; // unknown: the crashed host may have left it open
            await _channel.OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            var seen = await _queries.ReadAsync(Program.LineProbeVariable, cancellationToken).ConfigureAwait(false);
            if (!checkpoint.Started && RunCommandRule.WhyNot(seen, Program.Sync.Variable) is { } arrived)
            {
                // The crashed host gave the run command but died before recording it: the job is reconciled as started.
                Log.Information("resume: {Why:l}", arrived);
                checkpoint = checkpoint with { Started = true };
            }

            var decision = ResumeReconciliation.Decide(Program, checkpoint, seen, _buffer.BufferWords);
            if (!checkpoint.Started)
            {
                // The crashed host had begun sending but never gave the run command, and nothing has run.
                await _channel.OnlineAsync(RunCommand, cancellationToken).ConfigureAwait(false);
            }

            _runSent = true;
            _start.Loaded = true;
            _resumedFromCheckpoint = true;
            var m = seen.TrackedLine;
            await _channel.OnlineAsync(OptionalStopCommand, cancellationToken).ConfigureAwait(false);
            _stops.Reset(m);
            await ReadFeedAsync(cancellationToken).ConfigureAwait(false);
            _sender.Next = checkpoint.Next;
            _sender.NextExact = decision.Action == ResumeAction.Continue;
            _sender.ChunksDownloaded = checkpoint.ChunksDownloaded;
            _currentChunk = Program.ChunkOfTracked(m);
            _tracked = m;
            var lastSent = Math.Max(m, Program.LastTrackedBefore(_sender.Next));
            _pace.Restart();
            _buffer.Resumed(seen.LinesAhead, Program.Chunk(_currentChunk), m, lastSent);
            _drain.Begin(_sender.NextExact);
            _state = SessionState.Running;
            Raise(StreamingEventKind.Recovered, JobRecovery.ResumedMessage(m, _drain.Draining, decision.ControllerAhead, _sender.Next), _currentChunk);
            SaveCheckpoint(durable: true);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            // Nothing of the checkpoint was taken over: stay idle so the resume can simply be tried again.
            _state = SessionState.Idle;
            _log.Message = $"resume failed: {e.Message}; try again when the controller answers";
            throw;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }

    /// <summary>
    /// One timer tick: read M0, follow the chunk, let the strategy send, detect the end, write the checkpoint.
    /// A tick that finds the previous one still running returns at once (a slow download never overlaps itself).
    /// Faults do not throw: they set <see cref="State"/> to <see cref="SessionState.Faulted"/> with a message.
    /// </summary>
    public async Task TickAsync(CancellationToken cancellationToken = default)
    {
        if (_state is not (SessionState.Running or SessionState.Held or SessionState.Stopped))
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
            var downloadedBefore = _sender.ChunksDownloaded;
            var stateBefore = _state;
            var m = await _queries.TrackedLineAsync(cancellationToken).ConfigureAwait(false);
            FollowTrack(m);

            if (++_ticks % 20 == 0)
            {
                // The feed can change from the program (P500= lines) or the panel: refresh it about once a second.
                await ReadFeedAsync(cancellationToken).ConfigureAwait(false);
            }

            if (_drain.Draining)
            {
                await DrainStepAsync(cancellationToken).ConfigureAwait(false);
            }
            else
            {
                // Before the strategy and the dry check: a stopped program leaves the buffer unread, not dry.
                await WatchProgramStopAsync(m, cancellationToken).ConfigureAwait(false);
                await _strategy.TickAsync(Context, cancellationToken).ConfigureAwait(false);
                NoteLead();
                await CheckDryAndDoneAsync(cancellationToken).ConfigureAwait(false);
            }

            SaveCheckpoint(durable: _currentChunk != before || _sender.ChunksDownloaded != downloadedBefore || _state != stateBefore);
        }
        catch (PmacErrorException e) when (e.LinesStoredAfterGap > 0)
        {
            await StopBeforeGapAsync(e, cancellationToken).ConfigureAwait(false);
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
            return _state is SessionState.Running or SessionState.Held or SessionState.Stopped or SessionState.Completed;
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            _channel.BufferOpen = true;
            await _channel.OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            if (!_runSent && !await FinishBrokenStartAsync(cancellationToken).ConfigureAwait(false))
            {
                return false;
            }

            _strategy.Reset();
            _drain.Begin(_sender.NextExact);
            _state = SessionState.Running;
            Raise(StreamingEventKind.Recovered, _drain.Draining
                ? "link back; waiting for the buffer to drain to find where the broken download stopped"
                : $"recovered; sending continues at {_sender.Next}", _currentChunk);
            SaveCheckpoint(durable: true);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            _log.Message = $"still cannot continue: {e.Message}";
            return false;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
        return true;
    }

    // ---- what strategies use (through StreamingContext) and the start ----

    internal async Task<int> ReadLinesAheadAsync(CancellationToken cancellationToken)
    {
        var pr = await _queries.LinesAheadAsync(cancellationToken).ConfigureAwait(false);
        _buffer.LinesAhead(pr);
        return pr;
    }

    internal async Task DownloadNextChunkAsync(bool late, CancellationToken cancellationToken)
    {
        if (await _sender.DownloadNextChunkAsync(cancellationToken).ConfigureAwait(false) is not { } sent)
        {
            return;
        }

        var at = _state == SessionState.Idle ? "the start" : $"{Program.Sync.Variable}={_tracked}, {Program.FractionOfChunk(_currentChunk, _tracked):P0} of chunk {_currentChunk}";
        _log.Downloaded(sent, late, at, _tracked);
    }

    internal void Note(string message) => _log.Note(message);

    // ---- the tick's steps ----

    private void FollowTrack(int m)
    {
        _tracked = m;
        _buffer.Reached(m);
        _pace.Observe(m, _buffer.MovesReached, counting: _state == SessionState.Running);
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
        // Drained: everything the controller got has run, M0 names the last move that arrived and the line probe the
        // last non-motion line (M08, S, P500=...).
        var pr = await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        if (await _drain.StepAsync(_queries, Program, pr, _tracked, _sender.Next, cancellationToken).ConfigureAwait(false) is not { } next)
        {
            return;
        }

        _sender.Next = next;
        _sender.NextExact = true;
        _buffer.Drained(_tracked);
        _strategy.Reset();
        Note($"buffer drained at line {_tracked}; sending continues at {next}");
        Raise(StreamingEventKind.Recovered, _log.Message, _currentChunk);
    }

    /// <summary>
    /// A program stop: the controller stopped the program (its running bit off) while the job runs, the tracking
    /// variable on the stop block. Asked only when the variable stood still (see <see cref="ProgramStopWatch"/>). Not in
    /// single-block mode, where every block ends so.
    /// </summary>
    private async Task WatchProgramStopAsync(int m, CancellationToken cancellationToken)
    {
        // No move past the tracked block in the buffer: the dry check reads PR now, and a stop must not pass for an
        // underrun or the end. With moves still ahead, a stop leaves them uncalculated (PR above 0): no verdict yet.
        var nothingAhead = _buffer.LastSentLine <= m;
        if (_singleBlock || _queries.StatusUnknown || !_stops.MustAsk(m, _state == SessionState.Running, nothingAhead))
        {
            return;
        }

        if (await _queries.ProgramRunningAsync(cancellationToken).ConfigureAwait(false) is not { } running)
        {
            return;
        }

        // With paper placement the variable lags a block: the probe names the stop block (the last line calculated).
        var probe = !running && _stops.Stop is null && Program.ProbesEveryLine
            ? await _queries.ProbeAsync(Program.LineProbeVariable!, cancellationToken).ConfigureAwait(false)
            : (long?)null;
        if (_stops.Observe(running, () => Program.StopAt(m, probe), out var left) is { } stop && _state == SessionState.Running)
        {
            _state = SessionState.Stopped;
            Raise(StreamingEventKind.ProgramStop, stop.ToString(), _currentChunk);
        }
        else if (left is not null && _state == SessionState.Stopped)
        {
            // Continued at the controller (its panel, another host): the job runs on.
            _state = SessionState.Running;
            Raise(StreamingEventKind.Command, $"the controller continued after the {left}", _currentChunk);
        }
    }

    private async Task CheckDryAndDoneAsync(CancellationToken cancellationToken)
    {
        var final = Program.FinalTrackedLine;
        var allSent = _sender.AllSent;
        if (!_completion.NeedsLinesAhead(allSent, _buffer.LastSentLine, _tracked))
        {
            return;
        }

        // Everything sent has been reached: ask the controller whether the buffer is empty.
        var pr = await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        switch (_completion.Observe(allSent, pr, _tracked, final, running: _state == SessionState.Running))
        {
            case BufferVerdict.Underrun:
                Raise(StreamingEventKind.Underrun, $"rotary buffer ran dry at line {_tracked}", _currentChunk);
                break;
            case BufferVerdict.Completed when !await _queries.MotionStoppedAsync(cancellationToken).ConfigureAwait(false):
                // Nothing left in the rotary buffer is not the end: the last moves are still executing (the tracking
                // variable's synchronous assignment names a move when it starts, and it stands still through a long
                // one). The job ends when the motion has.
                break;
            case BufferVerdict.Completed:
                _state = SessionState.Completed;
                Note($"completed: {Program.BlocksThrough(_tracked)} of {Program.Manifest.TotalMotionBlocks} blocks reached");
                Raise(StreamingEventKind.Completed, _log.Message, _currentChunk);
                break;
        }
    }

    private async Task ReadFeedAsync(CancellationToken cancellationToken) =>
        _pace.Feed = await _queries.FeedAsync(cancellationToken).ConfigureAwait(false);

    /// <summary>True when the strategy sends with several packets in flight (the full strategy, more than one allowed).</summary>
    private static bool Pipelined(IStreamingStrategy strategy, StreamingOptions options) => strategy is FullBufferStrategy && options.PacketsInFlight > 1;

    /// <summary>
    /// A line was refused while later packets were in flight, and the controller stored their lines behind the gap
    /// (the refused line and the rest of its packet). Nothing can take lines back out of a rotary buffer, and the gap
    /// lies at least the lead ahead of execution (a second of motion), so the coordinate system is aborted at once
    /// (<c>&amp;n A</c>: it breaks into the trajectory and stops, Turbo PMAC User Manual p. 319; a feed hold would
    /// decelerate over Isx95 and stay resumable into the gap with <c>R</c>). The job ends aborted at the block M0 names,
    /// recorded durably before anything is sent: its resume restarts there with a preamble on a cleared buffer, the
    /// way an operator's abort does, never running a line behind the gap.
    /// </summary>
    private async Task StopBeforeGapAsync(PmacErrorException e, CancellationToken cancellationToken)
    {
        _state = SessionState.Aborted;
        var why = $"ERR{e.Number:000} refused '{e.Command}' while {e.LinesStoredAfterGap} lines of later packets were stored after it";
        _log.Message = $"{why}: aborting before execution reaches the gap";
        SaveCheckpoint(durable: true);
        try
        {
            await _channel.TryCloseAsync(cancellationToken).ConfigureAwait(false);
            await _channel.OnlineAsync(_cs.Abort, cancellationToken).ConfigureAwait(false);
            FollowTrack(await _queries.TrackedLineAsync(cancellationToken).ConfigureAwait(false));
            _log.Message = $"{why}: aborted at line {_tracked}, before the gap; resume restarts there";
        }
        catch (Exception x) when (x is PmacLinkException or PmacErrorException)
        {
            _log.Message = $"{why}: the abort could not be sent ({x.Message}); stop the machine before it reaches the gap";
        }

        Log.Error("Streaming stopped: {Message}", _log.Message);
        Raise(StreamingEventKind.Fault, _log.Message, _currentChunk);
        SaveCheckpoint(durable: true);
    }

    private void Fault(Exception e)
    {
        _state = SessionState.Faulted;
        _log.Message = JobRecovery.FaultMessage(e, _tracked, _sender.Next);
        Log.Error("Streaming stopped: {Message}", _log.Message);
        Raise(StreamingEventKind.Fault, _log.Message, _currentChunk);
        SaveCheckpoint(durable: true);
    }

    private void SaveCheckpoint(bool durable) => _checkpoints.Save(durable);

    private void Raise(StreamingEventKind kind, string message, int chunk) => _log.Raise(kind, message, chunk, _tracked);

    private void PublishStatus() => StatusChanged?.Invoke(this, Status);
}
