using PmacStream.GCode;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>The calls of a screen that holds views of splits and jobs, not preparation's and streaming's types (the HMI).</summary>
public sealed partial class JobService
{
    /// <summary>Prepares a program (<see cref="PrepareAsync"/>) and returns its split as a view, naming the stored revision it is.</summary>
    /// <exception cref="ProgramRefusedException">The check found errors, or a block fits no chunk.</exception>
    /// <exception cref="JobException">Bad settings or no such file, or (<see cref="PrepareRequest.Import"/>) the store cannot keep it.</exception>
    public async Task<SplitView> PrepareViewAsync(PrepareRequest request, CancellationToken cancellationToken = default)
    {
        var prepared = await PrepareAsync(request, null, cancellationToken).ConfigureAwait(false);
        return SplitView.Of(prepared.Program, prepared.ProgramId);
    }

    /// <summary>The restore preamble of a start at the block of <paramref name="line"/> (<see cref="PlanStart"/>): what is shown and sent.</summary>
    /// <exception cref="JobException">The line is out of the program or has no block after it.</exception>
    public IReadOnlyList<string> PreambleOf(SplitView program, int line, RunSettings settings, MachineProfile? profile = null, CancellationToken cancellationToken = default) =>
        PlanStart(ProgramOf(program), line, settings, profile, cancellationToken).GCode;

    /// <summary>
    /// The restore preamble of a start at the block of <paramref name="line"/> of a program prepared from the stored
    /// revision <paramref name="programId"/> (<see cref="PlanStartFromStore"/>: the block's state read from the store);
    /// null: <see cref="PreambleOf"/>.
    /// </summary>
    /// <exception cref="JobException">The line is out of the program or has no block after it.</exception>
    public IReadOnlyList<string> PreambleFor(SplitView program, long? programId, int line, RunSettings settings, MachineProfile? profile = null, CancellationToken cancellationToken = default) =>
        PlanStartFor(programId, ProgramOf(program), line, settings, profile, cancellationToken).GCode;

    /// <summary>Which rows of chunk <paramref name="chunk"/> (1-based) carry a block's tracked line, as the session reads the chunk.</summary>
    public ChunkRows RowsOf(SplitView program, int chunk)
    {
        var markers = ProgramOf(program).Body(chunk).Where(l => l.TrackedLine > 0).ToList();
        return new ChunkRows(markers.Select(l => l.TrackedLine).ToArray(), markers.Select(l => l.FileLine).ToArray());
    }

    /// <summary>
    /// Plans the start (when <see cref="SplitJobRequest.FromLine"/>), creates the job (<see cref="CreateJobAsync"/>)
    /// and starts it; a job that fails to start is closed.
    /// </summary>
    /// <exception cref="JobException">The line has no block after it, or the controller runs no library or another one.</exception>
    public async Task<Job> StartJobAsync(ControllerLink controller, SplitJobRequest request, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(request);
        var program = ProgramOf(request.Program);
        var plan = request.FromLine is { } from
            ? await Task.Run(() => PlanStartFor(request.ProgramId, program, from, request.Settings, request.Profile, cancellationToken), cancellationToken).ConfigureAwait(false)
            : null;
        if (request.ToLine is { } to)
        {
            await Task.Run(() => CheckRange(request.ProgramId, program, request.FromLine, to, request.Settings, request.Profile, cancellationToken), cancellationToken).ConfigureAwait(false);
        }

        var strategy = string.IsNullOrWhiteSpace(request.Strategy) ? StrategyKind.Chunk : StreamingStrategies.Parse(request.Strategy);
        var job = await CreateJobAsync(controller, new JobRequest(program, strategy)
        {
            Settings = request.Settings,
            Plan = plan,
            ToLine = request.ToLine,
            SingleBlock = request.SingleBlock,
            FeedOverride = request.FeedOverride,
            Profile = request.Profile,
            OptionalStop = request.OptionalStop,
            ProgramId = request.ProgramId,
            Station = request.Station,
            Machine = request.Machine,
        }, cancellationToken).ConfigureAwait(false);
        try
        {
            await job.StartAsync(cancellationToken).ConfigureAwait(false);
            return job;
        }
        catch
        {
            await job.DisposeAsync().ConfigureAwait(false);
            throw;
        }
    }

    /// <summary>The newest job recorded for a program that did not complete (<see cref="FindInterrupted"/>), as a view; else null.</summary>
    public InterruptedJobView? FindInterruptedView(string sourcePath) =>
        FindInterrupted(sourcePath) is { } r
            ? new InterruptedJobView(r.Record.Id, SplitView.Of(r.Program, r.Record.History.ProgramId), r.ResumeLine, r.Chunk, r.Record.Strategy.ToString().ToLowerInvariant(), r.Record.Checkpoint?.TimeUtc ?? r.Record.Created)
            {
                Resumable = r,
            }
            : null;

    /// <summary>
    /// Resumes an interrupted job a screen showed (<see cref="ResumeAsync"/>) under the profile it ran under (another
    /// <paramref name="profile"/> is refused), with its recorded settings (else <paramref name="settings"/>). The
    /// operator confirmed the restart preamble of the record's line before, so a restart there goes ahead; a restart
    /// at another line is declined (its preamble was not shown).
    /// </summary>
    /// <exception cref="JobException">The profile is not the job's, or the controller could not be asked.</exception>
    public async Task<ResumeResult> ResumeViewAsync(ControllerLink controller, InterruptedJobView job, RunSettings settings, MachineProfile profile, double feedOverride, bool optionalStop,
        CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(job);
        ArgumentNullException.ThrowIfNull(profile);
        var resumable = job.Resumable ?? OpenResumable(FindJob(job.JobId), cancellationToken);
        var ran = ProfileOf(resumable.Record, profile.Source); // the job's own profile, or a clear refusal
        var request = new ResumeRequest(resumable, resumable.Settings ?? settings, p => Task.FromResult(p.Line == resumable.RestartLine))
        {
            FeedOverride = feedOverride,
            Profile = ran,
            OptionalStop = optionalStop,
        };
        return await ResumeAsync(controller, request, cancellationToken).ConfigureAwait(false);
    }

    /// <summary>The split behind a view: the one the service read, else read from its folder.</summary>
    private static ChunkedProgram ProgramOf(SplitView view)
    {
        ArgumentNullException.ThrowIfNull(view);
        return view.Program ?? ChunkedProgram.Open(view.Folder);
    }
}
