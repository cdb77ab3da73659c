using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>What a job service needs from its host.</summary>
public sealed record JobServiceOptions
{
    /// <summary>The SQLite job store; null: <see cref="JobStore.DefaultPath"/> (shared by the command line and the HMI).</summary>
    public string? JobDatabase { get; init; }

    /// <summary>The store (<c>--store</c>); null: <see cref="JobDatabase"/>, else as <see cref="StoreLocation.Resolve"/> picks it.</summary>
    public StoreLocation? Store { get; init; }

    /// <summary>
    /// The store as a face spells it (<c>sqlite:PATH</c>, <c>postgres://...</c>, an Npgsql connection string) when
    /// <see cref="Store"/> is not given: the HMI's <c>--store</c>; null: <c>$PMACSTREAM_STORE</c>, else the default.
    /// </summary>
    public string? StoreUri { get; init; }

    /// <summary>Opens the built-in simulator (the host owns it); null: this host has none.</summary>
    public Func<CancellationToken, Task<SimulatorLink>>? Simulator { get; init; }

    /// <summary>Clock of sessions on real controllers; null: the system clock.</summary>
    public TimeProvider? Time { get; init; }

    /// <summary>
    /// The machine's rules for jobs (the operator's console): refuse a start or resume on an unhomed machine (unless
    /// <see cref="Machine.MachineRules.HomeCheck"/> is off) or with an alarm, and hold a job an alarm stops. Null: none (a
    /// host that drives a bare controller).
    /// </summary>
    public Machine.MachineRules? Rules { get; init; }

    /// <summary>
    /// How many times the first contact (<c>VERSION</c>) is tried before a controller counts as unreachable. Over a
    /// lossy link a lost SYN or first reply costs TCP's initial retransmission timeout (1 s, doubling), which alone can
    /// outlast one reply timeout; the query changes nothing, and a timed-out exchange resets the socket, so asking again
    /// on a new connection is safe. Default 3.
    /// </summary>
    public int ConnectAttempts { get; init; } = 3;
}

/// <summary>
/// The one job workflow every face calls (the command line's stream, resume and demo, the HMI presenter through its
/// adapter): prepare (check under a machine profile, split or reuse a split), connect (one spec parser, one device
/// facade, the library), plan a start from a line, start and run a job, find and resume an interrupted one.
/// See <c>Jobs/README.md</c>.
/// </summary>
public sealed partial class JobService
{
    private static readonly ILogger Log = Serilog.Log.ForContext<JobService>();
    private readonly JobServiceOptions _options;
    private readonly MoveTimeCache _moveTimes = new();

    /// <summary>Creates the service.</summary>
    public JobService(JobServiceOptions? options = null)
    {
        _options = options ?? new JobServiceOptions();
        Store = _options.Store ?? StoreLocation.Resolve(store: _options.StoreUri, jobDb: _options.JobDatabase);
        JobDatabase = Store.Engine == StoreEngine.Sqlite ? Store.Target : Store.Display;
    }

    /// <summary>The store jobs are recorded in.</summary>
    public StoreLocation Store { get; }

    /// <summary>The job store's file.</summary>
    public string JobDatabase { get; }

    /// <summary>Strategy names, the default first.</summary>
    public static IReadOnlyList<string> Strategies { get; } = ["chunk", "pr", "adaptive", "full"];

    /// <summary>
    /// Checks a program under <paramref name="profile"/> and lists what it finds (at most <paramref name="maxListed"/>;
    /// the counts are exact). Keeps the interpreter's move times for the ETA of a job started on it later.
    /// </summary>
    public ProgramCheck Check(string path, MachineProfile profile, int maxListed = 10_000, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(profile);
        var diagnostics = new List<Diagnostic>();
        var summary = new Checker(profile).CheckFile(
            path,
            d =>
            {
                if (diagnostics.Count < maxListed)
                {
                    diagnostics.Add(d);
                }
            },
            null,
            cancellationToken);
        Log.Information("Checked {Path:l}: {Summary:l}, estimated run time {Seconds:0} s", path, summary.ToString(), summary.EstimatedSeconds);
        return new ProgramCheck(diagnostics, summary.Blocks, summary.Errors, summary.Warnings, summary.EstimatedSeconds);
    }

    /// <summary>
    /// Checks and splits a program: reuses the split beside it when the source and every split option match
    /// (<see cref="SplitCache"/>), else splits with the check in the same pass. Refuses a program with errors under the
    /// profile unless forced, listing every error; nothing is written then.
    /// </summary>
    /// <exception cref="ProgramRefusedException">The check found errors, or a block fits no chunk.</exception>
    /// <exception cref="JobException">Bad settings or no such file (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public Task<PreparedProgram> PrepareAsync(PrepareRequest request, IProgress<SplitProgress>? progress = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(request);
        return Task.Run(() => Prepare(request, progress, cancellationToken), cancellationToken);
    }

    /// <summary>
    /// Opens a controller: the built-in simulator through the host, anything else through <see cref="PmacConnections"/>;
    /// proves the link (<c>VERSION</c>) and loads the PROG 1000/1001 library of <paramref name="profile"/> and the
    /// machine's tables into the simulator (which starts empty), only while it is idle (one still running a job keeps
    /// the library it runs). The library a real controller
    /// runs is checked by <see cref="CreateJobAsync"/> and <see cref="ResumeAsync"/>, before the first chunk.
    /// </summary>
    /// <exception cref="JobException">No simulator in this host, or the controller cannot be reached.</exception>
    public async Task<ControllerLink> ConnectAsync(ConnectionSpec spec, MachineProfile? profile = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(spec);
        SimulatorLink? sim = null;
        IPmacConnection connection;
        if (spec.IsSimulator)
        {
            var open = _options.Simulator ?? throw new JobException(
                "no built-in simulator in this build: run `pmacstream sim` and connect over Ethernet to 127.0.0.1:1025", JobErrorKind.BadRequest);
            sim = await open(cancellationToken).ConfigureAwait(false);
            connection = sim.Connection;
        }
        else
        {
            connection = PmacConnections.Create(spec);
        }

        try
        {
            var version = await ProbeAsync(connection, cancellationToken).ConfigureAwait(false);

            if (sim is not null)
            {
                // A simulator that outlived its host may still run that host's job: it keeps the library it runs (a
                // resume checks it is the job's).
                if (await LibraryDownloadGuard.BusyAsync(connection, LibraryDownloadScope.Default, cancellationToken).ConfigureAwait(false) is { } busy)
                {
                    Log.Information("{Device:l}: {Busy:l}; the library it runs is kept", connection.Description, busy);
                }
                else
                {
                    await ControllerLibrary.EnsureAsync(connection, profile, LibraryPolicy.Load, cancellationToken).ConfigureAwait(false);
                }
            }

            Log.Information("Connected to {Device:l} ({Spec:l}), firmware {Version:l}", connection.Description, spec.ToString(), version);
            return new ControllerLink(spec, connection, sim);
        }
        catch (PmacLinkException e)
        {
            await connection.DisposeAsync().ConfigureAwait(false);
            throw new JobException($"cannot reach the controller at {spec}: {e.Message}", JobErrorKind.Failed, e);
        }
        catch
        {
            await connection.DisposeAsync().ConfigureAwait(false);
            throw;
        }
    }

    // First contact: any reply (even an ERR) proves a controller is there; a link failure is tried again (see
    // JobServiceOptions.ConnectAttempts) and the last one thrown.
    private async Task<string> ProbeAsync(IPmacConnection connection, CancellationToken cancellationToken)
    {
        for (var attempt = 1; ; attempt++)
        {
            try
            {
                return (await connection.GetResponseAsync("VERSION", cancellationToken).ConfigureAwait(false)).Trim();
            }
            catch (PmacErrorException e)
            {
                return $"(VERSION answered ERR{e.Number:000})";
            }
            catch (PmacLinkException e) when (attempt < Math.Max(1, _options.ConnectAttempts))
            {
                Log.Warning("{Device:l}: no answer to the first contact ({Error:l}); trying again ({Attempt} of {Attempts})",
                    connection.Description, e.Message, attempt + 1, _options.ConnectAttempts);
            }
        }
    }

    /// <summary>
    /// Plans a start at the block of <paramref name="line"/>: modal state restored, a safe approach (the settings' safe
    /// Z rule), shown before it runs. The one planner of every face.
    /// </summary>
    /// <exception cref="JobException">The line is out of the program or has no block after it (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public StartPlan PlanStart(ChunkedProgram program, int line, RunSettings settings, MachineProfile? profile = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(program);
        ArgumentNullException.ThrowIfNull(settings);
        if (line < 1)
        {
            throw new JobException($"start line must be 1 or more (got {line})", JobErrorKind.BadRequest);
        }

        StartPlan plan;
        try
        {
            plan = StartFromLine.Plan(program.Manifest.SourcePath, line, settings.ToStartPlanOptions(program.Manifest, profile ?? MachineProfile.Default), cancellationToken);
        }
        catch (ArgumentOutOfRangeException e)
        {
            throw new JobException(e.Message.Split(Environment.NewLine)[0], JobErrorKind.BadRequest, e);
        }

        return program.PositionOfBlock(plan.Line) is null
            ? throw new JobException($"line {line}: no block to start at after it", JobErrorKind.BadRequest)
            : plan;
    }

    /// <summary>
    /// A new job on an open controller, recorded in the job store unless <see cref="JobRequest.Record"/> is off. First
    /// the library check of <see cref="JobRequest.Library"/> (<see cref="ControllerLibrary.EnsureAsync(IPmacConnection, MachineProfile?, LibraryPolicy, LibraryDownloadScope, CancellationToken)"/>):
    /// the controller must run the library of the request's profile, or get it loaded while idle; nothing else is sent
    /// until <see cref="Job.StartAsync"/>.
    /// </summary>
    /// <exception cref="JobException">The controller runs no library or another one, or a load was asked while it runs a program; nothing recorded.</exception>
    public async Task<Job> CreateJobAsync(ControllerLink controller, JobRequest request, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(controller);
        ArgumentNullException.ThrowIfNull(request);
        FeedOverrides.Validate(request.FeedOverride);
        // Selected blocks (A..B): the range runs as a program of its own, so nothing after B reaches the controller.
        var program = request.ToLine is { } to ? CutRange(request.Program, request.Plan?.Line, to, request.Profile) : request.Program;
        var times = await JobMoveTimesAsync(request.ProgramId, program, request.Plan?.Line, request.ToLine, request.Profile, cancellationToken).ConfigureAwait(false);
        var store = request.Record ? JobStores.Open(Store) : null;
        try
        {
            // The previous job here completed: its rotary program may still wait for lines (the start ends it).
            var completed = CompletedJobLine(store, controller);
            var options = request.Settings.ToStreamingOptions(request.Strategy, request.SingleBlock, defineBuffer: controller.IsSimulator, controller.Simulator?.ClockFactor ?? 1)
                with { OptionalStop = request.OptionalStop, CompletedJobLine = completed };
            await ControllerLibrary.EnsureAsync(controller.Connection, request.Profile, request.Library, ScopeOf(options, program, completed), cancellationToken).ConfigureAwait(false);
            await EnsureMachineReadyAsync(controller, request.Profile, cancellationToken).ConfigureAwait(false);
            var id = store?.CreateJob(program.Manifest.SourcePath, program.Manifest.SourceSha256, Path.Combine(program.Folder, ChunkManifest.FileName),
                request.Strategy, controller.Spec.ToString(), request.Plan?.Line, options.LineProbeVariable, RunSettingsFile.ToJson(request.Settings, withShape: false),
                (request.Profile.Source, request.Profile.Identity),
                new JobHistoryStart(request.ProgramId, request.Station, request.Machine ?? MachineName(controller.Spec), program.Manifest.TotalMotionBlocks) { ToLine = request.ToLine });
            StreamingSession? session = null;
            session = new StreamingSession(controller.Devices, program, options, id is { } i ? SourceLocations.Track(store!.SinkFor(i, () => session?.Status.ExecutedBlocks), store!, i, SourceLocations.MapOf(program.Folder)) : null, times, TimeOf(controller));
            return new Job(controller, session, request.Settings, request.Plan, request.FeedOverride, store, id)
            {
                AlarmAxes = _options.Rules?.Axes, Planner = PlannerOf(request.ProgramId, program, request.Settings, request.Profile),
            };
        }
        catch
        {
            store?.Dispose();
            throw;
        }
    }

    /// <summary>The machine as the history names it when not told: its connection without the scheme (host:port, the serial device, sim).</summary>
    public static string MachineName(ConnectionSpec spec)
    {
        ArgumentNullException.ThrowIfNull(spec);
        var text = spec.ToString();
        var scheme = text.IndexOf("://", StringComparison.Ordinal);
        return scheme >= 0 ? text[(scheme + 3)..] : text.StartsWith("serial:", StringComparison.Ordinal) ? text["serial:".Length..].Split('@')[0] : text;
    }

    /// <summary>Every recorded job, newest first (the job history); empty when nothing was recorded yet.</summary>
    public IReadOnlyList<JobRecord> ListJobs()
    {
        if (!JobStores.Exists(Store))
        {
            return [];
        }

        using var store = JobStores.Open(Store);
        return store.List();
    }

    /// <summary>A recorded job: by id, or the newest unfinished one.</summary>
    /// <exception cref="JobException">No job database, or no such job (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public JobRecord FindJob(long? id)
    {
        using var store = OpenExistingStore();
        return id is { } n
            ? store.Get(n) ?? throw new JobException($"no job {n} in {store.Path}", JobErrorKind.BadRequest)
            : store.LatestUnfinished() ?? throw new JobException($"no unfinished job in {store.Path}", JobErrorKind.BadRequest);
    }

    /// <summary>
    /// Loads the profile's PROG 1000/1001 library and the machine's tables into the controller (the HMI's profile change
    /// on the built-in simulator, as <c>--load-library</c> does before a job): refused unless the coordinate system is
    /// idle; the completed job's rotary program, still waiting for lines after its end, is ended first.
    /// </summary>
    /// <exception cref="JobException">A program runs or a move is in progress.</exception>
    public async Task LoadLibraryAsync(ControllerLink controller, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(controller);
        int? completed;
        using (var store = JobStores.Exists(Store) ? JobStores.Open(Store) : null)
        {
            completed = CompletedJobLine(store, controller);
        }

        await ControllerLibrary.EnsureAsync(controller.Connection, profile, LibraryPolicy.Load, LibraryDownloadScope.Default with { CompletedJobLine = completed }, cancellationToken)
            .ConfigureAwait(false);
    }

    /// <summary>
    /// The machine's rules before a job's first line: no alarm that stops motion, and every axis homed unless the
    /// rules say the machine needs no homing (absolute encoders) or the operator overrode it (<c>--no-home-check</c>).
    /// </summary>
    /// <exception cref="JobException">An alarm is active or an axis is not homed; nothing was sent.</exception>
    private async Task EnsureMachineReadyAsync(ControllerLink controller, MachineProfile profile, CancellationToken cancellationToken)
    {
        if (_options.Rules is not { } rules)
        {
            return;
        }

        var (unhomed, alarms) = await Machine.MachineConsole.ReadinessAsync(controller.Connection, AxesOf(profile) ?? rules.Axes, cancellationToken).ConfigureAwait(false);
        if (alarms.Count > 0)
        {
            throw new JobException($"an alarm is active: {alarms[0].Text}; clear it first (pmacstream alarms clear)", JobErrorKind.Failed);
        }

        // A machine with absolute encoders knows its position at power-on (the profile says so): no homing needed.
        if (rules.HomeCheck && !profile.AbsoluteEncoders && unhomed.Count > 0)
        {
            throw new JobException($"not homed: {string.Concat(unhomed)}; home the machine first (pmacstream home), or give --no-home-check if its position is known (absolute encoders)", JobErrorKind.Failed);
        }
    }

    /// <summary>The machine's axes: the profile's when it lists them, else the rules' (X Y Z on motors 1-3); null without rules.</summary>
    private IReadOnlyList<Machine.MachineAxis>? AxesOf(MachineProfile? profile) =>
        _options.Rules is null ? null : profile is { Axes.Count: > 0 } ? Machine.MachineAxis.Of(profile) : _options.Rules.Axes;

    /// <summary>The last line of the newest job on this controller when it completed (its rotary program may still wait for lines); else null.</summary>
    private static int? CompletedJobLine(IJobStore? store, ControllerLink controller) =>
        store?.Latest(controller.Spec.ToString())?.Checkpoint is { State: SessionState.Completed } done ? done.LastExecutedLine : null;

    /// <summary>The newest job recorded for a program, whoever started it, when it did not complete; else null.</summary>
    public ResumableJob? FindInterrupted(string sourcePath)
    {
        if (!JobStores.Exists(Store))
        {
            return null;
        }

        JobRecord? record;
        using (var store = JobStores.Open(Store))
        {
            var full = Path.GetFullPath(sourcePath);
            var comparison = OperatingSystem.IsWindows() ? StringComparison.OrdinalIgnoreCase : StringComparison.Ordinal;
            record = store.List().FirstOrDefault(j => string.Equals(j.ProgramPath, full, comparison));
        }

        return record is { Unfinished: true } ? OpenResumable(record) : null;
    }

    /// <summary>
    /// The machine profile a recorded job ran under, read again from where it came from (a built-in name, a file),
    /// or <paramref name="requested"/> when the face names one. Refuses a profile that is not the one the job ran
    /// under (another name, or the same file with other contents): the program was judged, split and its move times
    /// made under that one. A record of an older version, which does not say, takes <paramref name="requested"/> or
    /// the default.
    /// </summary>
    /// <exception cref="JobException">The profile cannot be read, or it is not the job's (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public static MachineProfile ProfileOf(JobRecord record, string? requested = null) => ProfileOf(record, requested, null);

    /// <summary>
    /// <see cref="ProfileOf(JobRecord, string?)"/> with <paramref name="adjust"/> applied to the profile read before it is
    /// compared with the job's (the tool table at the machine over the profile's, as the start applied it).
    /// </summary>
    /// <exception cref="JobException">The profile cannot be read, or it is not the job's (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public static MachineProfile ProfileOf(JobRecord record, string? requested, Func<MachineProfile, MachineProfile>? adjust)
    {
        ArgumentNullException.ThrowIfNull(record);
        var source = requested ?? record.Profile;
        MachineProfile profile;
        try
        {
            profile = MachineProfile.Resolve(source);
            profile = adjust?.Invoke(profile) ?? profile;
        }
        catch (Exception e) when (e is InvalidDataException or IOException or UnauthorizedAccessException)
        {
            throw new JobException($"job {record.Id}: its machine profile {source} cannot be read ({e.Message}); resume needs the profile the job ran under", JobErrorKind.BadRequest, e);
        }

        if (record.ProfileIdentity is { } ran && !string.Equals(ran, profile.Identity, StringComparison.Ordinal))
        {
            var now = requested is null ? $"{source} now reads as {profile.Identity}" : $"the profile asked for, {requested}, is {profile.Identity}";
            throw new JobException(
                $"job {record.Id} ran under machine profile {record.Profile} ({ran}); {now}: the profile changed since the job started, so the program's check, split and start plans would not be the job's. Resume with the profile the job ran under, or start the program again from a line",
                JobErrorKind.BadRequest);
        }

        return profile;
    }

    /// <summary>
    /// Checks that an unfinished job can go on: its program unchanged (SHA-256), its split readable and of that
    /// program; says where a restart would start.
    /// </summary>
    /// <exception cref="JobException">It cannot (<see cref="JobErrorKind.Failed"/>), with what to do instead.</exception>
    public ResumableJob OpenResumable(JobRecord record, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(record);
        if (!File.Exists(record.ProgramPath))
        {
            throw new JobException($"job {record.Id}: the program {record.ProgramPath} is gone");
        }

        if (!FileHash.SameDigest(FileHash.Sha256Hex(record.ProgramPath, cancellationToken), record.ProgramSha256))
        {
            throw new JobException($"job {record.Id}: {record.ProgramPath} changed since the job started (SHA-256 differs); refusing to resume. Start it again (split it and start from a line).");
        }

        ChunkedProgram program;
        try
        {
            program = ChunkedProgram.Open(record.ManifestPath);
        }
        catch (Exception e) when (e is IOException or JsonException or InvalidDataException)
        {
            throw new JobException($"job {record.Id}: its split ({record.ManifestPath}) cannot be read ({e.Message}): split the program again and start from a line", JobErrorKind.Failed, e);
        }

        if (!FileHash.SameDigest(program.Manifest.SourceSha256, record.ProgramSha256))
        {
            throw new JobException($"job {record.Id}: the split in {program.Folder} does not match the program: split it again and start from a line");
        }

        var cp = record.Checkpoint;
        if (RecordMismatch(record, program) is { } mismatch)
        {
            throw new JobException($"job {record.Id}: {mismatch}: the record does not fit its program and cannot be resumed from it (check where the machine is, then start the program again from a line)");
        }

        var restart = cp is { LastExecutedLine: > 0 } ? cp.LastExecutedLine : record.FromLine;
        var chunk = cp?.CurrentChunk ?? (restart is { } r ? program.PositionOfBlock(r)?.Chunk : null) ?? 1;
        return new ResumableJob(record, program, restart, chunk, RecordedSettings(record, program.Manifest));
    }

    /// <summary>
    /// Resumes a job, with the controller as the truth. When the controller may still hold it (a checkpoint, not
    /// aborted, and not a simulator made for this link), the session reconciles the record with what the controller
    /// reports: sending continues where the controller's lines end (or a start that broke off while loading is loaded
    /// again) and the job runs. When the controller stopped the job it restarts at the controller's line (else at
    /// <see cref="ResumableJob.RestartLine"/>) behind a preamble, once <see cref="ResumeRequest.ConfirmRestart"/> agrees:
    /// the job is returned ready for <see cref="Job.StartAsync"/>. When the record and the controller disagree in a way
    /// that could repeat or skip a block the result is <see cref="ResumeKind.Refused"/>, with both positions and the
    /// operator's choices; nothing was sent. A <see cref="ResumeRequest.FeedOverride"/> (percent) is set on the
    /// continued job at once, or before the restart. The job gate runs first (<see cref="ProgramGate"/>): a program with
    /// codes the controller cannot run yet, or a split forced past errors, is resumed only when forced. Before anything
    /// else reaches the controller, the library check of <see cref="ResumeRequest.Library"/>; a load is refused while the
    /// controller still runs the job.
    /// </summary>
    /// <exception cref="JobException">The controller could not be asked (link or ERR), or runs another library.</exception>
    /// <exception cref="ProgramRefusedException">The gate refused it; nothing was sent.</exception>
    public async Task<ResumeResult> ResumeAsync(ControllerLink controller, ResumeRequest request, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(controller);
        ArgumentNullException.ThrowIfNull(request);
        var job = request.Job;
        var record = job.Record;
        var profile = request.Profile ?? MachineProfile.Default;

        // The gate again: a job forced past it at its start is resumed only when forced again.
        ProgramGate.EnsureRunnable(record.ProgramPath, job.Program.Manifest, profile, request.Force, cancellationToken);
        var times = await JobMoveTimesAsync(record.History.ProgramId, job.Program, record.FromLine, record.ToLine, profile, cancellationToken).ConfigureAwait(false);
        var store = OpenExistingStore();
        try
        {
            var options = request.Settings.ToStreamingOptions(record.Strategy, singleBlock: false, defineBuffer: controller.IsSimulator, controller.Simulator?.ClockFactor ?? 1)
                with { OptionalStop = request.OptionalStop };
            var library = request.Library ?? (request.Force ? LibraryPolicy.Force : LibraryPolicy.Verify);
            await ControllerLibrary.EnsureAsync(controller.Connection, request.Profile, library, ScopeOf(options, job.Program, null), cancellationToken).ConfigureAwait(false);
            await EnsureMachineReadyAsync(controller, profile, cancellationToken).ConfigureAwait(false);
            store.RecordResume(record.Id, request.Station);
            StreamingSession? current = null;
            var origins = SourceLocations.MapOf(job.Program.Folder);
            StreamingSession NewSession() => current = new(controller.Devices, job.Program, options, SourceLocations.Track(store.SinkFor(record.Id, () => current?.Status.ExecutedBlocks), store, record.Id, origins), times, TimeOf(controller));
            var outcome = new ContinueOutcome(null, null, job.RestartLine);
            if (record.Checkpoint is { State: not SessionState.Aborted } && controller.Simulator?.Fresh != true)
            {
                outcome = await ContinueAsync(controller, request, store, NewSession(), _options.Rules, cancellationToken).ConfigureAwait(false);
                if (outcome.Result is { } done)
                {
                    if (done.Job is null)
                    {
                        store.Dispose();
                    }

                    return done;
                }
            }

            var plan = outcome.RestartLine is { } line ? PlanStartFor(record.History.ProgramId, job.Program, line, request.Settings, request.Profile, cancellationToken) : null;
            if (!await request.ConfirmRestart(new RestartProposal(outcome.RestartLine, plan, outcome.Reason)).ConfigureAwait(false))
            {
                Log.Information("Restart of job {Job} declined", record.Id);
                store.Dispose();
                return new ResumeResult(ResumeKind.Declined, null, outcome.Reason) { RestartLine = outcome.RestartLine };
            }

            return new ResumeResult(ResumeKind.Restart, new Job(controller, NewSession(), request.Settings, plan, request.FeedOverride, store, record.Id)
            {
                AlarmAxes = _options.Rules?.Axes, Profile = profile, Planner = PlannerOf(record.History.ProgramId, job.Program, request.Settings, profile),
            }, outcome.Reason);
        }
        catch
        {
            store.Dispose();
            throw;
        }
    }

    /// <summary>
    /// Continues a job the controller may still hold, from its record. The outcome is the result when the job runs on
    /// or the resume is refused; else (the controller stopped the job) why, and the line a restart starts at.
    /// </summary>
    private static async Task<ContinueOutcome> ContinueAsync(ControllerLink controller, ResumeRequest request, IJobStore store, StreamingSession session, Machine.MachineRules? rules, CancellationToken cancellationToken)
    {
        var record = request.Job.Record;
        var cp = record.Checkpoint!;
        try
        {
            // From the record: its line probe, and a start that broke off while loading is loaded again.
            await session.ResumeAsync(record, cancellationToken).ConfigureAwait(false);
        }
        catch (ResumeRefusedException e)
        {
            // The record and the controller disagree: neither position is safe, so no restart is proposed.
            Log.Error("Job {Job}: resume refused: {Message:l}", record.Id, e.Message);
            return new ContinueOutcome(new ResumeResult(ResumeKind.Refused, null, $"cannot resume job {record.Id}: {e.Message}") { RestartLine = e.RestartLine }, null, null);
        }
        catch (InvalidOperationException e)
        {
            // The streaming session's word for "the controller stopped the job" (or a start that cannot be loaded
            // again): restart where it stopped (its M0), not where the record says.
            var line = (e as ControllerLostJobException)?.RestartLine ?? request.Job.RestartLine;
            Log.Warning("Job {Job}: {Message:l}; restarting at line {Line} with the restore preamble", record.Id, e.Message, line);
            return new ContinueOutcome(null, e.Message, line);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            throw new JobException($"cannot resume job {record.Id}: {e.Message}", JobErrorKind.Failed, e);
        }

        var reloaded = cp is { Loaded: false, Started: false };
        Log.Information("Job {Job} resumed from its checkpoint at line {Line}{How:l}", record.Id, cp.LastExecutedLine, reloaded ? " (its start loaded again)" : string.Empty);
        var continued = new Job(controller, session, request.Settings, null, request.FeedOverride, store, record.Id) { AlarmAxes = rules?.Axes, Profile = request.Profile ?? GCode.MachineProfile.Default };
        if (request.FeedOverride is { } percent)
        {
            await continued.SetFeedOverrideAsync(percent, cancellationToken).ConfigureAwait(false);
        }

        return new ContinueOutcome(new ResumeResult(reloaded ? ResumeKind.Reloaded : ResumeKind.Continued, continued), null, null);
    }

    /// <summary>What continuing from the record gave: a result (runs on, refused), or a restart with its reason and line.</summary>
    private sealed record ContinueOutcome(ResumeResult? Result, string? Reason, int? RestartLine);

    private PreparedProgram Prepare(PrepareRequest request, IProgress<SplitProgress>? progress, CancellationToken cancellationToken)
    {
        var source = Path.GetFullPath(request.SourcePath);
        if (Directory.Exists(source))
        {
            throw new JobException($"{request.SourcePath}: is a directory, expected a G-code file", JobErrorKind.BadRequest);
        }

        if (!File.Exists(source))
        {
            throw new JobException($"{request.SourcePath}: no such file", JobErrorKind.BadRequest);
        }

        SplitOptions options;
        try
        {
            request.Settings.Validate();
            options = request.Settings.ToSplitOptions(request.Profile, request.OutDir, request.Force) with { MaxReportedErrors = request.MaxListedErrors };
            options.Validate();
        }
        catch (ArgumentException e)
        {
            throw new JobException(e.Message, JobErrorKind.BadRequest, e);
        }

        var outDir = Path.GetFullPath(options.OutDir ?? Splitter.DefaultOutDir(source));
        var revision = request.ProgramId;
        PreparedProgram? importedWithSplit = null;
        if (revision is null && request.Import)
        {
            (revision, importedWithSplit) = RevisionOf(request, source, options, outDir, progress, cancellationToken);
        }

        PreparedProgram prepared;
        if (importedWithSplit is { } split)
        {
            prepared = split;
        }
        else if (revision is { } programId && PrepareStored(programId, request, source, options, outDir, progress, cancellationToken) is { } stored)
        {
            prepared = stored;
        }
        else if (SplitCache.TryOpen(source, outDir, options, cancellationToken) is { } reused)
        {
            Log.Information("Prepared {Source:l}: the split in {Folder:l} matches the program and the options; reused", source, outDir);
            prepared = new PreparedProgram(source, reused, request.Profile, true, 0);
        }
        else
        {
            prepared = Split(request, source, options with { OutDir = outDir }, progress, cancellationToken);
        }

        // The split is kept either way (it is the program's, and reusable): what the gate refuses is running it.
        ProgramGate.EnsureRunnable(source, prepared.Program.Manifest, request.Profile, request.Force, cancellationToken);
        if (request.Force && prepared.Program.Manifest.NotYetCodes is { Count: > 0 } forced)
        {
            Log.Information("Forced: {Source:l} uses codes the controller cannot run yet under {Profile:l}: {Codes:l}", source, request.Profile.Name, ProgramGate.Describe(forced));
        }

        return prepared with { ProgramId = revision };
    }

    /// <summary>Splits a program (the check in the same pass); a refusal lists every error.</summary>
    private static PreparedProgram Split(PrepareRequest request, string source, SplitOptions options, IProgress<SplitProgress>? progress, CancellationToken cancellationToken)
    {
        try
        {
            var result = Splitter.Split(source, options, progress, cancellationToken);
            return new PreparedProgram(source, ChunkedProgram.FromManifest(result.Manifest, result.OutputDirectory), request.Profile, false, result.Warnings);
        }
        catch (SplitException e)
        {
            throw Refused(request, source, e);
        }
    }

    /// <summary>A split refused: logged, with every error for the caller.</summary>
    private static ProgramRefusedException Refused(PrepareRequest request, string source, SplitException e)
    {
        var why = e.FromChecker || e.ErrorCount > 0 ? $"{e.ErrorCount} error(s) under the {request.Profile.Name} profile" : e.Message;
        Log.Information("Refused {Source:l}: {Why:l}; nothing split, nothing sent", source, why);
        return new ProgramRefusedException(source, e.Diagnostics, e.ErrorCount, e.Message, e) { Profile = request.Profile.Name };
    }

    private async Task<IMoveTimes?> MoveTimesAsync(string sourcePath, MachineProfile profile, CancellationToken cancellationToken) =>
        File.Exists(sourcePath) ? await Task.Run(() => _moveTimes.Get(sourcePath, profile), cancellationToken).ConfigureAwait(false) : null;

    private static LibraryDownloadScope ScopeOf(StreamingOptions options, ChunkedProgram program, int? completedJobLine) =>
        new(options.CoordinateSystem, program.Sync.Variable, completedJobLine);

    private TimeProvider? TimeOf(ControllerLink controller) => controller.Simulator?.Time ?? _options.Time;

    private IJobStore OpenExistingStore()
    {
        // Reading jobs must not leave an empty database (and its folders) behind a mistyped path.
        return JobStores.Exists(Store)
            ? JobStores.Open(Store)
            : throw new JobException($"{JobDatabase}: no job database there; jobs are recorded when they start", JobErrorKind.BadRequest);
    }

    /// <summary>What in a job's record lies outside its program (a chunk or line it does not have), or null.</summary>
    private static string? RecordMismatch(JobRecord record, ChunkedProgram program)
    {
        var chunks = program.TotalChunks;
        var last = program.FinalTrackedLine;
        var lastSourceLine = program.Manifest.Chunks.Count > 0 ? program.Manifest.Chunks[^1].LastSourceLine : 0;
        if (record.FromLine is { } from && from > lastSourceLine)
        {
            return $"its start line {from} is beyond the program's last block (line {lastSourceLine})";
        }

        return record.Checkpoint switch
        {
            null => null,
            { CurrentChunk: var c } when c > chunks => $"its checkpoint's current chunk {c} is beyond the split's {chunks} chunks",
            { Next.Chunk: var n } when n > chunks + 1 => $"its checkpoint's next chunk {n} is beyond the split's {chunks} chunks",
            { ChunksDownloaded: var d } when d > chunks => $"its checkpoint counts {d} chunks downloaded of {chunks}",
            { LastExecutedLine: var l } when l > last => $"its checkpoint's last executed line {l} is beyond the program's last block (line {last})",
            _ => null,
        };
    }

    /// <summary>
    /// The settings a job started with: its record's, with the chunk shape of its split (the record keeps the shape
    /// once, in the manifest it names; a record of an older version carries it in its settings too, and a manifest of
    /// an older version has none, so then the record's applies).
    /// </summary>
    private static RunSettings? RecordedSettings(JobRecord record, ChunkManifest manifest)
    {
        if (record.Settings is not { Length: > 0 } json)
        {
            return null;
        }

        try
        {
            var recorded = RunSettingsFile.Read(RunSettings.Default, Encoding.UTF8.GetBytes(json), $"job {record.Id}");
            return manifest.Shape is { } shape ? recorded with { Shape = shape } : recorded;
        }
        catch (RunSettingsException e)
        {
            Log.Warning("Job {Job}: its recorded settings cannot be read ({Message:l}); the current settings apply", record.Id, e.Message);
            return null;
        }
    }
}
