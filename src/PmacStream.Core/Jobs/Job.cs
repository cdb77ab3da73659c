using System.Globalization;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>How a job's tick loop ended.</summary>
public enum JobOutcome
{
    /// <summary>Every block executed.</summary>
    Completed,

    /// <summary>Stopped by a fault or an abort; resumable from its checkpoint.</summary>
    Stopped,

    /// <summary>The host stopped ticking (Ctrl-C); the controller keeps what it holds; resumable.</summary>
    Interrupted,
}

/// <summary>
/// One job on one controller: its streaming session, its record and checkpoints in the job store, and the operator's
/// commands. <see cref="RunAsync"/> is the tick loop of a host without a timer of its own (the command line); a
/// screen calls <see cref="TickAsync"/> from its timer instead.
/// </summary>
public sealed class Job : IAsyncDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<Job>();
    private readonly IJobStore? _store;
    private readonly double? _feedOverride;
    private volatile ProgramStop? _continueFrom; // the stop the operator's Enter was for
    private ProgramStop? _lastStop;
    private int _stops;

    internal Job(ControllerLink controller, StreamingSession session, RunSettings settings, StartPlan? plan, double? feedOverride, IJobStore? store, long? id)
    {
        Controller = controller;
        Session = session;
        Settings = settings;
        Plan = plan;
        _feedOverride = feedOverride;
        _store = store;
        Id = id;
    }

    /// <summary>
    /// The machine's axes whose alarms hold the job (<see cref="JobServiceOptions.Rules"/>): when the program stops and
    /// a limit or a fault kill is the cause, the job ends faulted with an exact checkpoint instead of waiting at a
    /// program stop. Null: not watched.
    /// </summary>
    internal IReadOnlyList<Machine.MachineAxis>? AlarmAxes { get; init; }

    /// <summary>The machine profile the program was checked under (plans the block after an alarm's, see <see cref="HaltOnAlarmAsync"/>).</summary>
    internal GCode.MachineProfile Profile { get; init; } = GCode.MachineProfile.Default;

    /// <summary>Plans a start at a line (from the store for a stored revision); null: re-interpret the source with <see cref="Profile"/>.</summary>
    internal Func<int, StartPlan>? Planner { get; init; }

    /// <summary>The job record's id; null when the job is not recorded.</summary>
    public long? Id { get; }

    /// <summary>The controller it runs on.</summary>
    public ControllerLink Controller { get; }

    /// <summary>The streaming session (status, events, checkpoint).</summary>
    public StreamingSession Session { get; }

    /// <summary>The settings it runs with.</summary>
    public RunSettings Settings { get; }

    /// <summary>The start plan (preamble) of a start from a line, or null.</summary>
    public StartPlan? Plan { get; }

    /// <summary>The split program.</summary>
    public ChunkedProgram Program => Session.Program;

    /// <summary>The status after the last tick or command; its feed is the feed override in percent.</summary>
    public StreamingStatus Status => Session.Status;

    /// <summary>
    /// The programmed feed (F, program units per minute) in force at the executing block, from the interpreter's move
    /// table (what P500 carries in paper mode), without asking the controller; null before the first block or unknown.
    /// </summary>
    public double? ProgrammedFeed => Session.Status.CurrentLine > 0 ? Session.MoveTimes?.ProgrammedFeedAt(Session.Status.CurrentLine) : null;

    /// <summary>The status in the job service's words, for a screen that does not read streaming's types.</summary>
    public JobView View
    {
        get
        {
            var s = Session.Status;
            var state = s.State switch
            {
                SessionState.Running => JobState.Running,
                SessionState.Held => JobState.Held,
                SessionState.Completed => JobState.Completed,
                SessionState.Aborted => JobState.Aborted,
                SessionState.Faulted => JobState.Faulted,
                SessionState.Stopped => JobState.Stopped,
                _ => JobState.Idle,
            };
            return new JobView(state, s.CurrentChunk, s.CurrentLine, s.Percent, s.Feed, ProgrammedFeed, s.Elapsed, s.Eta, s.Message,
                s.Stop is { } stop ? new JobStop(stop.Line, stop.Code) : null, Session.OptionalStop);
        }
    }

    /// <summary>Job events: downloads, late windows, chunk changes, faults, completion.</summary>
    public event EventHandler<StreamingEvent>? EventRaised
    {
        add => Session.EventRaised += value;
        remove => Session.EventRaised -= value;
    }

    /// <summary>
    /// Starts the job: when a feed override is given, first makes sure the coordinate system runs nothing (the override
    /// of a running program is not touched) and sets it; then the session's start (buffer, preamble, first chunk, run
    /// command). A failure is kept as the job's message and thrown.
    /// </summary>
    public async Task StartAsync(CancellationToken cancellationToken = default)
    {
        try
        {
            if (_feedOverride is { } percent)
            {
                await Session.EnsureIdleAsync(cancellationToken).ConfigureAwait(false);
                await SetOverrideBeforeStartAsync(percent, cancellationToken).ConfigureAwait(false);
            }

            await Session.StartAsync(Plan?.Line, Plan?.PmacLines, cancellationToken).ConfigureAwait(false);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException or InvalidOperationException)
        {
            SetMessage(e.Message);
            throw;
        }

        Log.Information("Job {Job} started on {Device:l}: {Chunks} chunks, strategy {Strategy:l}{From:l}", Id, Controller.Description,
            Program.TotalChunks, Session.Options.Strategy.ToString().ToLowerInvariant(), Plan is { } p ? $", from line {p.Line}" : string.Empty);
    }

    /// <summary>One timer period of streaming work (read M0, download the next chunk once, write the checkpoint).</summary>
    public Task TickAsync(CancellationToken cancellationToken = default) => Session.TickAsync(cancellationToken);

    /// <summary>Feed hold.</summary>
    public Task HoldAsync(CancellationToken cancellationToken = default) => Session.HoldAsync(cancellationToken);

    /// <summary>Resume after a hold or at a program stop, or the next block in single-block mode.</summary>
    public Task ResumeMotionAsync(CancellationToken cancellationToken = default) =>
        Session.SingleBlock && Session.State == SessionState.Running ? Session.StepAsync(cancellationToken) : Session.ResumeMotionAsync(cancellationToken);

    /// <summary>Abort; the job stays resumable from its checkpoint.</summary>
    public Task AbortAsync(CancellationToken cancellationToken = default) => Session.AbortAsync(cancellationToken);

    /// <summary>Live feed override change (percent, <c>&amp;n %</c>): applies at once, the program's feeds stay as programmed.</summary>
    public Task SetFeedOverrideAsync(double percent, CancellationToken cancellationToken = default) =>
        Session.SetFeedAsync(FeedOverrides.Validate(percent), cancellationToken);

    /// <summary>Single-block mode on or off.</summary>
    public void SetSingleBlock(bool on) => Session.SetSingleBlock(on);

    /// <summary>The optional-stop switch on or off (<c>M01</c> stops or not), live.</summary>
    public Task SetOptionalStopAsync(bool on, CancellationToken cancellationToken = default) => Session.SetOptionalStopAsync(on, cancellationToken);

    /// <summary>
    /// What <see cref="RunAsync"/> does at a program stop: false (the default) waits for the operator
    /// (<see cref="ContinueFromStop"/>, or a resume command); true gives the run command by itself, for scripted runs and
    /// the simulator (<c>--stops continue</c>).
    /// </summary>
    public bool ContinueAtStops { get; set; }

    /// <summary>
    /// The operator continues from the program stop the job waits at (pressed Enter): <see cref="RunAsync"/> gives the
    /// run command on its next tick. Ignored unless the job is stopped at a program stop now.
    /// </summary>
    public void ContinueFromStop()
    {
        if (Session.State == SessionState.Stopped)
        {
            _continueFrom = Session.Status.Stop;
        }
    }

    /// <summary>
    /// Whether the loop gives the run command now: stopped, and either told to go on at every stop or the operator's
    /// continue was for this very stop. A continue for a stop the controller has left since (continued from its panel)
    /// must not carry over to the next stop.
    /// </summary>
    internal static bool ContinuesNow(StreamingStatus status, bool continueAtStops, ProgramStop? continueFrom) =>
        status.State == SessionState.Stopped && (continueAtStops || (continueFrom is not null && continueFrom == status.Stop));

    /// <summary>
    /// The timer loop (timer1_Tick of the HMI) for a host without a timer: tick, report, wait one period and, when the
    /// host steps the simulator's clock, advance it by the tick's virtual time. Ends when the job completes or stops, or
    /// when <paramref name="cancellationToken"/> fires (sending stops; the controller keeps the lines it holds).
    /// </summary>
    public async Task<JobOutcome> RunAsync(Action<StreamingStatus>? onTick = null, CancellationToken cancellationToken = default)
    {
        var step = Controller.Simulator?.Step;
        var outcome = JobOutcome.Interrupted;
        while (true)
        {
            await Session.TickAsync(CancellationToken.None).ConfigureAwait(false);
            if (Session.State == SessionState.Stopped && AlarmAxes is { } axes)
            {
                await HaltOnAlarmAsync(axes).ConfigureAwait(false);
            }

            var s = Session.Status;
            onTick?.Invoke(s);
            if (s.State == SessionState.Stopped && s.Stop is { } stop && stop != _lastStop)
            {
                _lastStop = stop;
                _stops++;
            }
            if (s.State is SessionState.Completed or SessionState.Faulted or SessionState.Aborted)
            {
                outcome = s.State == SessionState.Completed ? JobOutcome.Completed : JobOutcome.Stopped;
                break;
            }

            if (cancellationToken.IsCancellationRequested)
            {
                break;
            }

            if (ContinuesNow(s, ContinueAtStops, _continueFrom))
            {
                _continueFrom = null;
                await ContinueAsync(s.Stop).ConfigureAwait(false);
            }
            else if (s.State != SessionState.Stopped)
            {
                _continueFrom = null;
            }

            try
            {
                await Task.Delay(Settings.TickPeriod, cancellationToken).ConfigureAwait(false);
            }
            catch (OperationCanceledException)
            {
                break;
            }

            step?.Invoke(Session.Options.TickPeriod);
        }

        SetMessage(Session.Status.Message);
        Log.Information("Job {Job} {Outcome} at line {Line}: {Executed} of {Total} blocks", Id, outcome, Session.Status.CurrentLine,
            Session.Status.ExecutedBlocks, Session.Status.TotalBlocks);
        return outcome;
    }

    /// <summary>
    /// The program stopped: when an alarm (a limit, a fault kill) of the machine's axes is why, the controller aborted
    /// it, and the job ends faulted at its last executed block (a resume after the alarm is cleared restarts there).
    /// </summary>
    private async Task HaltOnAlarmAsync(IReadOnlyList<Machine.MachineAxis> axes)
    {
        try
        {
            var (_, alarms) = await Machine.MachineConsole.ReadinessAsync(Controller.Connection, axes, CancellationToken.None).ConfigureAwait(false);
            if (alarms.Count > 0)
            {
                var line = Session.Status.CurrentLine;
                await MarkCompletedBlockAsync(axes, line).ConfigureAwait(false);
                await Session.HaltOnAlarmAsync($"alarm at line {line}: {string.Join("; ", alarms.Select(a => a.Text))}. Clear it (pmacstream alarms clear, jog off a limit), then resume: pmacstream resume --job {Id}", CancellationToken.None).ConfigureAwait(false);
            }
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            Log.Warning("Alarm status not read: {Message:l}", e.Message);
        }
    }

    /// <summary>
    /// The tracking variable names the block that started last; the alarm may have stopped the program after that
    /// block's motion had ended (a dry buffer waiting for lines), and a restart there would run it twice. When the axes
    /// are commanded exactly where the next block starts (work coordinates: motor positions plus following errors, as a
    /// motor killed on a fault stands off by its error, less the displacement the library applies),
    /// the block is done (<see cref="StandsAt"/>): the tracking variable is moved on to the next block, so the resume restarts there.
    /// </summary>
    private async Task MarkCompletedBlockAsync(IReadOnlyList<Machine.MachineAxis> axes, int line)
    {
        if (line <= 0 || Program.ProbesEveryLine)
        {
            return;
        }

        StartPlan next;
        try
        {
            next = Planner is { } plan ? plan(line + 1) : StartFromLine.Plan(Program.Manifest.SourcePath, line + 1, Settings.ToStartPlanOptions(Program.Manifest, Profile));
        }
        catch (ArgumentOutOfRangeException)
        {
            return; // the last block: its end is the job's end
        }

        var work = await Machine.MachineConsole.WorkPositionAsync(Controller.Connection, axes, new LibraryMap(), Session.Options.CoordinateSystem, CancellationToken.None).ConfigureAwait(false);
        var start = next.Start.InMillimetres(next.State.Units);
        if (work is { } w && StandsAt(w, start, axes) && Program.PositionOfBlock(next.Line) is not null)
        {
            Log.Information("Job {Job}: the block of line {Line} had ended when the alarm stopped the program (the axes stand at line {Next}'s start): {Variable}={Next}", Id, line, next.Line, Program.Sync.Variable);
            await Controller.Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"{Program.Sync.Variable}={next.Line}"), CancellationToken.None).ConfigureAwait(false);
        }
    }

    /// <summary>
    /// Whether the commanded position <paramref name="work"/> is <paramref name="end"/>, to the controller's position
    /// report: the rule a resume needs is that a block counts executed only when the controller's trajectory reached its
    /// end. A Turbo PMAC stops a move's trajectory on a servo cycle, so an aborted move stands at its end exactly or a
    /// servo cycle's travel (micrometres) short of it; the window is the report's rounding (1/32 count for position and
    /// following error each, SRM p. 260), 1/16 count in all, plus the chunk files' 5 decimals (1e-5 mm). A move short
    /// by more is re-run whole from its start (the restart approaches over its start point); the simulator finds a move
    /// ended within twice this (<c>SimOptions.AbortAtEndCounts</c>), so its executed-move log agrees.
    /// </summary>
    internal static bool StandsAt(GCode.Point3 work, GCode.Point3 end, IReadOnlyList<Machine.MachineAxis> axes)
    {
        double Tolerance(string name) => (axes.FirstOrDefault(a => a.Name == name) is { CountsPerMm: > 0 } a ? 1.0 / 16 / a.CountsPerMm : 1.0 / 16) + 1e-5;
        return Math.Abs(work.X - end.X) <= Tolerance("X") && Math.Abs(work.Y - end.Y) <= Tolerance("Y") && Math.Abs(work.Z - end.Z) <= Tolerance("Z");
    }

    /// <summary>The run command at a program stop, from the tick loop; a link fault there faults the session (the loop then ends).</summary>
    private async Task ContinueAsync(ProgramStop? stop)
    {
        try
        {
            await Session.ResumeMotionAsync(CancellationToken.None).ConfigureAwait(false);
            Log.Information("Job {Job} continued after the {Stop}", Id, stop?.ToString() ?? "program stop");
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            // Already the session's fault, with what to do: the loop ends at the next tick.
        }
    }

    /// <summary>Keeps the reason the job stopped and how it ended with its record, and closes the job store.</summary>
    public ValueTask DisposeAsync()
    {
        SetMessage(Session.Status.Message);
        if (_store is not null && Id is { } id)
        {
            var s = Session.Status;
            var outcome = s.State switch
            {
                SessionState.Completed => "completed",
                SessionState.Aborted => "aborted",
                SessionState.Faulted => "alarm",
                _ => "interrupted", // the face stopped it (Ctrl-C, closed) before the end: resumable
            };
            try
            {
                _store.RecordEnd(id, outcome, s.ExecutedBlocks, s.TotalBlocks, _stops, s.State == SessionState.Faulted ? 1 : 0);
            }
            catch (JobStoreException e)
            {
                Log.Warning("Job {Job}: its end could not be recorded: {Error:l}", id, e.Message);
            }
        }

        _store?.Dispose();
        return ValueTask.CompletedTask;
    }

    internal void SetMessage(string message)
    {
        if (_store is not null && Id is { } id && !string.IsNullOrEmpty(message))
        {
            _store.SetMessage(id, message);
        }
    }

    /// <summary>The operator's feed override is in force before the first block is calculated (no buffer is open then).</summary>
    private async Task SetOverrideBeforeStartAsync(double percent, CancellationToken cancellationToken)
    {
        var connection = Controller.Connection;
        await connection.GetResponseAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        var command = string.Create(CultureInfo.InvariantCulture, $"&{Session.Options.CoordinateSystem} %{FeedOverrides.Validate(percent):0.###}");
        await connection.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
    }
}
