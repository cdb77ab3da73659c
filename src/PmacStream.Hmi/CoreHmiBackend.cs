using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preview;

namespace PmacStream.Hmi;

/// <summary>
/// The real <see cref="IHmiBackend"/>: an adapter over the <see cref="JobService"/> the command line calls too, so a
/// job started here runs with the same gate, split, buffer, window and preamble as <c>pmacstream stream</c>, is
/// recorded in the same job store and can be resumed by <c>pmacstream resume</c> (and the other way round). The
/// machine profile comes with each call: the operator chooses it on the screen. It holds the controller link the
/// operator opened; splits and jobs pass through as the service's views.
/// </summary>
public sealed partial class CoreHmiBackend(JobService service) : IHmiBackend, IConsoleBackend, IStoreBackend, IAsyncDisposable
{
    /// <summary>Diagnostics listed at most (the counts stay exact; a screen of 10,000 rows is already plenty).</summary>
    public const int MaxListedDiagnostics = 10_000;

    private ControllerLink? _link;
    private StationSettings? _stationSettings;

    /// <summary>The service every call goes to.</summary>
    public JobService Service { get; } = service;

    /// <summary>
    /// This station's name for leases and the job history (<c>--station</c>); null: the settings file's <c>station</c>,
    /// else the host name, as the command line.
    /// </summary>
    public string? Station { get; init; }

    /// <summary>The machine's name for its lease and the job history (<c>--machine</c>); null: its connection.</summary>
    public string? Machine { get; init; }

    /// <summary>The station's settings (lease heartbeat and expiry, station name); null: the default settings file's.</summary>
    public StationSettings? StationSettings { get; init; }

    private StationSettings Settings => _stationSettings ??= StationSettings ?? Jobs.StationSettings.Load(null);

    /// <summary>
    /// The lease of the connected machine for this station, taken before a job sends anything, as <c>stream</c> and
    /// <c>resume</c> take it (refused with who holds it); null for the built-in simulator, which is this process's own.
    /// </summary>
    private Task<MachineLease?> LeaseAsync(string? recorded = null)
    {
        var link = Link;
        if (link.IsSimulator)
        {
            return Task.FromResult<MachineLease?>(null);
        }

        var settings = Settings;
        var machine = Machine ?? recorded ?? JobService.MachineName(link.Spec);
        return Task.Run<MachineLease?>(() => Service.TakeLease(machine, settings.StationName(Station), settings));
    }

    /// <inheritdoc />
    public IReadOnlyList<string> Strategies => JobService.Strategies;

    /// <inheritdoc />
    public async Task<string> ConnectAsync(ConnectionSettings settings, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(settings);
        if (_link is { } open)
        {
            return open.Description;
        }

        _link = await Service.ConnectAsync(settings.ToSpec(), profile, cancellationToken).ConfigureAwait(false);
        _profile = profile;
        return _link.Description;
    }

    /// <inheritdoc />
    public async Task DisconnectAsync()
    {
        if (_link is { } link)
        {
            _link = null;
            _console = null;
            await link.DisposeAsync().ConfigureAwait(false);
        }
    }

    /// <inheritdoc />
    public ValueTask DisposeAsync() => new(DisconnectAsync());

    /// <inheritdoc />
    public async Task LoadLibraryAsync(MachineProfile profile, CancellationToken cancellationToken = default)
    {
        // The built-in simulator gets the profile's library and tables (only while idle). Whether a real controller
        // runs that library is the job service's check at Execute and resume, the same as the command line's.
        if (_link is { IsSimulator: true } link)
        {
            await Service.LoadLibraryAsync(link, profile, cancellationToken).ConfigureAwait(false);
        }

        ProfileChosen(profile);
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
    public Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) =>
        PrepareAsync(sourcePath, settings, profile, null, cancellationToken);

    /// <inheritdoc />
    /// <remarks>
    /// A file (no <paramref name="programId"/>) is stored first, as <c>stream FILE</c> stores it: found in the store by
    /// its SHA-256 and profile, else imported (<see cref="PrepareRequest.Import"/>), and the split names the revision.
    /// A store that cannot keep it does not stop the operator running the file: it is prepared as a file, without a
    /// revision, and the split says why (<see cref="SplitView.NotStored"/>). A program with errors is still refused.
    /// </remarks>
    public async Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, long? programId, CancellationToken cancellationToken = default)
    {
        var request = new PrepareRequest(sourcePath, settings) { Profile = profile, MaxListedErrors = MaxListedDiagnostics, ProgramId = programId, Import = programId is null };
        try
        {
            return await Service.PrepareViewAsync(request, cancellationToken).ConfigureAwait(false);
        }
        catch (JobException e) when (request.Import && StoreCannotKeep(e))
        {
            // The presenter logs why (one warning in the operator's log pane, which the global logger also feeds).
            var split = await Service.PrepareViewAsync(request with { Import = false }, cancellationToken).ConfigureAwait(false);
            return split with { NotStored = e.Message };
        }
    }

    /// <summary>The import failed in the store (it cannot be read or written), not in the program: the file can still run.</summary>
    private static bool StoreCannotKeep(JobException e) =>
        e.Kind == JobErrorKind.BadRequest && e.InnerException is System.Data.Common.DbException or IOException or UnauthorizedAccessException;

    /// <inheritdoc />
    /// <remarks>The split of a stored revision plans from the store's states (<see cref="JobService.PreambleFor"/>), as its job will.</remarks>
    public Task<IReadOnlyList<string>> BuildPreambleAsync(SplitView program, int line, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) =>
        Task.Run(() => Service.PreambleFor(program, program.ProgramId, line, settings, profile, cancellationToken), cancellationToken);

    /// <inheritdoc />
    public ChunkRows ReadChunkRows(SplitView program, int chunk) => Service.RowsOf(program, chunk);

    /// <inheritdoc />
    public async Task<IHmiJob> StartAsync(HmiJobRequest request, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(request);
        var lease = await LeaseAsync().ConfigureAwait(false);
        try
        {
            var job = await Service.StartJobAsync(Link, new SplitJobRequest(request.Program, request.Strategy)
            {
                FromLine = request.FromLine,
                ToLine = request.ToLine,
                Settings = request.Settings,
                SingleBlock = request.SingleBlock,
                FeedOverride = request.FeedOverride,
                Profile = request.Profile,
                OptionalStop = request.OptionalStop,
                ProgramId = request.ProgramId ?? request.Program.ProgramId,
                Station = lease is null ? null : Settings.StationName(Station),
                Machine = lease?.Machine,
            }, cancellationToken).ConfigureAwait(false);
            lease?.SetJob(job.Id);
            return Track(new SessionJob(job, SourceLocations.MapOf(request.Program.Folder), lease), request.Program.SourcePath, request.Strategy);
        }
        catch
        {
            await ReleaseAsync(lease).ConfigureAwait(false);
            throw;
        }
    }

    private static async Task ReleaseAsync(MachineLease? lease)
    {
        if (lease is not null)
        {
            await lease.DisposeAsync().ConfigureAwait(false);
        }
    }

    /// <summary>" (O1002 line 7, call 3 of 4 from line 12)" for a line of an expanded program, else empty.</summary>
    private static string Origin(string folder, int? line) =>
        line is { } l && SourceLocations.Describe(SourceLocations.MapOf(folder), l) is { } text ? $" ({text})" : string.Empty;

    /// <inheritdoc />
    public Task<InterruptedJobView?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) =>
        Task.Run(() => Service.FindInterruptedView(sourcePath), cancellationToken);

    /// <inheritdoc />
    /// <remarks>
    /// The operator confirmed the restart preamble of the record's line before (the presenter shows it), so a restart
    /// there goes ahead; a restart at another line (the controller stopped elsewhere) is refused with what to do, since
    /// its preamble was not shown.
    /// </remarks>
    public async Task<IHmiJob> ResumeInterruptedAsync(InterruptedJobView job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop,
        CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(job);
        var lease = await LeaseAsync(Service.RecordedMachine(job.JobId)).ConfigureAwait(false);
        try
        {
            lease?.SetJob(job.JobId);
            return await ResumeLeasedAsync(job, feedOverride, settings, profile, optionalStop, lease, cancellationToken).ConfigureAwait(false);
        }
        catch
        {
            await ReleaseAsync(lease).ConfigureAwait(false);
            throw;
        }
    }

    private async Task<IHmiJob> ResumeLeasedAsync(InterruptedJobView job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop,
        MachineLease? lease, CancellationToken cancellationToken)
    {
        var result = await Service.ResumeViewAsync(Link, job, settings, profile, feedOverride, optionalStop, cancellationToken).ConfigureAwait(false);
        switch (result.Kind)
        {
            case ResumeKind.Refused:
                // The screen shows the refusal as it shows every job step refused.
                throw new JobException(result.Reason ?? $"cannot resume job {job.JobId}");
            case ResumeKind.Declined:
                throw new InvalidOperationException(
                    $"the controller stopped the job at line {result.RestartLine}{Origin(job.Program.Folder, result.RestartLine)}, not at line {job.ResumeLine} of the job record: nothing was sent. Select line {result.RestartLine} and start from it to see its preamble first.");
        }

        var resumed = result.Job!;
        if (result.Kind != ResumeKind.Restart)
        {
            return Track(new SessionJob(resumed, SourceLocations.MapOf(job.Program.Folder), lease), job.Program.SourcePath, job.Strategy);
        }

        try
        {
            await resumed.StartAsync(cancellationToken).ConfigureAwait(false);
            return Track(new SessionJob(resumed, SourceLocations.MapOf(job.Program.Folder), lease), job.Program.SourcePath, job.Strategy);
        }
        catch
        {
            await resumed.DisposeAsync().ConfigureAwait(false);
            throw;
        }
    }

    /// <inheritdoc />
    public IToolpathSource OpenToolpath(string sourcePath, MachineProfile profile) => new GCodeToolpathSource(sourcePath, profile);

    /// <inheritdoc />
    /// <remarks>
    /// The stored blocks were interpreted under the import's profile: under another one (or when the store cannot be
    /// read) the file is drawn, as the job would be prepared from it.
    /// </remarks>
    public IToolpathSource OpenStoredToolpath(long programId, string sourcePath, MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return Service.StoredBlocksOf(programId) is { } stored && string.Equals(stored.Profile, profile.Name, StringComparison.OrdinalIgnoreCase)
            ? new DecodedBlockToolpathSource(stored.Read, stored.Blocks, stored.Name, stored.Errors, stored.ErrorCount)
            : OpenToolpath(sourcePath, profile);
    }

    private ControllerLink Link => _link ?? throw new InvalidOperationException("Connect to a controller first.");

    /// <summary>A job as the presenter drives it.</summary>
    private sealed class SessionJob(Job job, GCode.Expansion.ExpansionMap? origins = null, MachineLease? lease = null) : IHmiJob
    {
        private MachineLease? _lease = lease;

        public long? Id => job.Id;

        public HmiJobStatus Status
        {
            get
            {
                var s = job.View;
                var state = s.State switch
                {
                    JobState.Running => HmiJobState.Running,
                    JobState.Held => HmiJobState.Held,
                    JobState.Completed => HmiJobState.Completed,
                    JobState.Aborted => HmiJobState.Aborted,
                    JobState.Faulted => HmiJobState.Failed,
                    JobState.Stopped => HmiJobState.Stopped,
                    _ => HmiJobState.Idle,
                };
                return new HmiJobStatus(state, s.CurrentChunk, s.CurrentLine, s.Percent, s.FeedOverride, s.ProgrammedFeed, s.Elapsed, s.Eta,
                    string.IsNullOrEmpty(s.Message) ? null : s.Message, s.Stop, s.OptionalStop)
                {
                    SourceLocation = SourceLocations.Describe(origins, s.CurrentLine),
                };
            }
        }

        public async Task TickAsync(CancellationToken cancellationToken = default)
        {
            await job.TickAsync(cancellationToken).ConfigureAwait(false);
            if (job.View.State is JobState.Completed or JobState.Aborted or JobState.Faulted)
            {
                await ReleaseLeaseAsync().ConfigureAwait(false); // the job's end gives the machine back, as the command line's does
            }
        }

        /// <summary>Gives the machine's lease back (once).</summary>
        public async Task ReleaseLeaseAsync()
        {
            if (Interlocked.Exchange(ref _lease, null) is { } held)
            {
                await held.DisposeAsync().ConfigureAwait(false);
            }
        }

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

        public async ValueTask DisposeAsync()
        {
            await job.DisposeAsync().ConfigureAwait(false);
            await ReleaseLeaseAsync().ConfigureAwait(false);
        }
    }
}
