using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preview;
using PmacStream.Streaming;

namespace PmacStream.Hmi;

/// <summary>
/// The real <see cref="IHmiBackend"/>: an adapter over the <see cref="JobService"/> the command line calls too, so a
/// job started here runs with the same gate, split, buffer, window and preamble as <c>pmacstream stream</c>, is
/// recorded in the same job store and can be resumed by <c>pmacstream resume</c> (and the other way round). The
/// machine profile comes with each call: the operator chooses it on the screen.
/// </summary>
public sealed class CoreHmiBackend(JobService service) : IHmiBackend
{
    /// <summary>Diagnostics listed at most (the counts stay exact; a screen of 10,000 rows is already plenty).</summary>
    public const int MaxListedDiagnostics = 10_000;

    /// <summary>The service every call goes to.</summary>
    public JobService Service { get; } = service;

    /// <inheritdoc />
    public IReadOnlyList<string> Strategies => JobService.Strategies;

    /// <inheritdoc />
    public Task<ControllerLink> ConnectAsync(ConnectionSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) =>
        Service.ConnectAsync(settings.ToSpec(), profile, cancellationToken);

    /// <inheritdoc />
    public async Task LoadLibraryAsync(ControllerLink controller, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(controller);

        // The built-in simulator gets the profile's library and tables (only while idle). Whether a real controller
        // runs that library is the job service's check at Execute and resume, the same as the command line's.
        if (controller.IsSimulator)
        {
            await Service.LoadLibraryAsync(controller, profile, cancellationToken).ConfigureAwait(false);
        }
    }

    /// <inheritdoc />
    public Task<HmiCheckResult> CheckAsync(string path, MachineProfile profile, HmiLanguage language, CancellationToken cancellationToken = default) =>
        Task.Run(() =>
        {
            // For this check only: the diagnostic culture follows the async flow, and this task is the check's own.
            DiagnosticText.Culture = HmiText.Culture(language);
            var c = Service.Check(path, profile, MaxListedDiagnostics, cancellationToken);
            return new HmiCheckResult(c.Diagnostics, c.Blocks, c.Errors, c.Warnings);
        }, cancellationToken);

    /// <inheritdoc />
    public async Task<HmiSplitResult> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        var prepared = await Service.PrepareAsync(new PrepareRequest(sourcePath, settings) { Profile = profile, MaxListedErrors = MaxListedDiagnostics }, null, cancellationToken)
            .ConfigureAwait(false);
        return new HmiSplitResult(prepared.Program.Manifest, prepared.Program.Folder);
    }

    /// <inheritdoc />
    public async Task<IReadOnlyList<string>> BuildPreambleAsync(HmiSplitResult program, int line, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) =>
        (await Task.Run(() => Service.PlanStart(Program(program), line, settings, profile, cancellationToken), cancellationToken).ConfigureAwait(false)).GCode;

    /// <inheritdoc />
    public async Task<IHmiJob> StartAsync(ControllerLink controller, HmiJobRequest request, CancellationToken cancellationToken = default)
    {
        var program = Program(request.Program);
        var plan = request.FromLine is { } from
            ? await Task.Run(() => Service.PlanStart(program, from, request.Settings, request.Profile, cancellationToken), cancellationToken).ConfigureAwait(false)
            : null;
        var job = await Service.CreateJobAsync(controller, new JobRequest(program, Strategy(request.Strategy))
        {
            Settings = request.Settings,
            Plan = plan,
            SingleBlock = request.SingleBlock,
            FeedOverride = request.FeedOverride,
            Profile = request.Profile,
            OptionalStop = request.OptionalStop,
        }, cancellationToken).ConfigureAwait(false);
        return await StartedAsync(job, cancellationToken).ConfigureAwait(false);
    }

    /// <inheritdoc />
    public Task<HmiInterruptedJob?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) =>
        Task.Run(() => Service.FindInterrupted(sourcePath) is { } r
            ? new HmiInterruptedJob(r.Record.Id, new HmiSplitResult(r.Program.Manifest, r.Program.Folder), r.ResumeLine, r.Chunk,
                r.Record.Strategy.ToString().ToLowerInvariant(), r.Record.Checkpoint?.TimeUtc ?? r.Record.Created, r)
            : null, cancellationToken);

    /// <inheritdoc />
    /// <remarks>
    /// The operator confirmed the restart preamble of the record's line before (the presenter shows it), so a restart
    /// there goes ahead; a restart at another line (the controller stopped elsewhere) is refused with what to do, since
    /// its preamble was not shown.
    /// </remarks>
    public async Task<IHmiJob> ResumeInterruptedAsync(ControllerLink controller, HmiInterruptedJob job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop,
        CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(profile);
        var resumable = job.Record as ResumableJob ?? throw new ArgumentException("not a job recorded in the job store", nameof(job));
        var ran = JobService.ProfileOf(resumable.Record, profile.Source); // the job's own profile, or a clear refusal
        int? proposed = null;
        var result = await Service.ResumeAsync(controller, resumable, resumable.Settings ?? settings, p =>
            {
                proposed = p.Line;
                return Task.FromResult(p.Line == resumable.RestartLine);
            }, feedOverride, ran, cancellationToken, optionalStop: optionalStop)
            .ConfigureAwait(false);
        var resumed = result.Job ?? throw new InvalidOperationException(
            $"the controller stopped the job at line {proposed}, not at line {job.ResumeLine} of the job record: nothing was sent. Select line {proposed} and start from it to see its preamble first.");
        return result.Kind == ResumeKind.Restart
            ? await StartedAsync(resumed, cancellationToken).ConfigureAwait(false)
            : new SessionJob(resumed);
    }

    /// <inheritdoc />
    public IToolpathSource OpenToolpath(string sourcePath, MachineProfile profile) => new GCodeToolpathSource(sourcePath, profile);

    private static ChunkedProgram Program(HmiSplitResult split) => ChunkedProgram.FromManifest(split.Manifest, split.Directory);

    private static StrategyKind Strategy(string name) => string.IsNullOrWhiteSpace(name) ? StrategyKind.Chunk : StreamingStrategies.Parse(name);

    private static async Task<IHmiJob> StartedAsync(Job job, CancellationToken cancellationToken)
    {
        try
        {
            await job.StartAsync(cancellationToken).ConfigureAwait(false);
            return new SessionJob(job);
        }
        catch
        {
            await job.DisposeAsync().ConfigureAwait(false);
            throw;
        }
    }

    /// <summary>A job as the presenter drives it.</summary>
    private sealed class SessionJob(Job job) : IHmiJob
    {
        public HmiJobStatus Status
        {
            get
            {
                var s = job.Status;
                var state = s.State switch
                {
                    SessionState.Running => HmiJobState.Running,
                    SessionState.Held => HmiJobState.Held,
                    SessionState.Completed => HmiJobState.Completed,
                    SessionState.Aborted => HmiJobState.Aborted,
                    SessionState.Faulted => HmiJobState.Failed,
                    SessionState.Stopped => HmiJobState.Stopped,
                    _ => HmiJobState.Idle,
                };
                return new HmiJobStatus(state, s.CurrentChunk, s.CurrentLine, s.Percent, s.Feed, job.ProgrammedFeed, s.Elapsed, s.Eta,
                    string.IsNullOrEmpty(s.Message) ? null : s.Message, s.Stop, job.Session.OptionalStop);
            }
        }

        public Task TickAsync(CancellationToken cancellationToken = default) => job.TickAsync(cancellationToken);

        public Task HoldAsync(CancellationToken cancellationToken = default) => job.HoldAsync(cancellationToken);

        public Task ResumeAsync(CancellationToken cancellationToken = default) => job.ResumeMotionAsync(cancellationToken);

        public Task AbortAsync(CancellationToken cancellationToken = default) => job.AbortAsync(cancellationToken);

        public Task SetFeedOverrideAsync(double percent, CancellationToken cancellationToken = default) => job.SetFeedOverrideAsync(percent, cancellationToken);

        public Task SetOptionalStopAsync(bool on, CancellationToken cancellationToken = default) => job.SetOptionalStopAsync(on, cancellationToken);

        public Task SetSingleBlockAsync(bool on, CancellationToken cancellationToken = default)
        {
            job.SetSingleBlock(on);
            return Task.CompletedTask;
        }

        public ValueTask DisposeAsync() => job.DisposeAsync();
    }
}
