using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>What to prepare: a program, the run settings to cut it with and the machine profile to check it against.</summary>
/// <param name="SourcePath">The G-code program.</param>
/// <param name="Settings">The chunk shape (blocks per chunk, chunk words, tracking and feed variables ...) and the run settings.</param>
public sealed record PrepareRequest(string SourcePath, RunSettings Settings)
{
    /// <summary>The machine profile the program is checked against (and whose tail ends the last chunk).</summary>
    public MachineProfile Profile { get; init; } = MachineProfile.Default;

    /// <summary>Go on although the check found errors (what is not G-code is dropped), as <c>split --force</c> does.</summary>
    public bool Force { get; init; }

    /// <summary>Folder of the chunks; null: <c>&lt;name&gt;_chunks</c> beside the source, shared by every face.</summary>
    public string? OutDir { get; init; }

    /// <summary>Most errors a refusal lists (all are counted).</summary>
    public int MaxListedErrors { get; init; } = 10_000;

    /// <summary>
    /// The stored revision <see cref="SourcePath"/> holds (its bytes): its preparation is kept with it in the store and
    /// reused while the same inputs would make it (<see cref="JobService.PreparationsReused"/>); null: the split beside the file only.
    /// </summary>
    public long? ProgramId { get; init; }

    /// <summary>
    /// Without a <see cref="ProgramId"/>: store the file as a revision first (found by its SHA-256 and profile when
    /// stored already, else checked and decoded into the store), so that its preparation is kept with it and the job
    /// names it (<see cref="PreparedProgram.ProgramId"/>). A program with errors is stored with its diagnostics and
    /// refused as before. What <c>stream FILE</c> asks for.
    /// </summary>
    public bool Import { get; init; }
}

/// <summary>A checked, split program ready to run.</summary>
/// <param name="SourcePath">Full path of the source.</param>
/// <param name="Program">The chunks and their manifest.</param>
/// <param name="Profile">The profile it was checked against (start plans interpret with it).</param>
/// <param name="Reused">True when an earlier split with the same bytes and options was taken as it was.</param>
/// <param name="Warnings">Lexical warnings of a new split (0 when reused).</param>
public sealed record PreparedProgram(string SourcePath, ChunkedProgram Program, MachineProfile Profile, bool Reused, int Warnings)
{
    /// <summary>The stored revision it is (<see cref="PrepareRequest.ProgramId"/>, or the one <see cref="PrepareRequest.Import"/> found or stored); null: a file only.</summary>
    public long? ProgramId { get; init; }
}

/// <summary>A check's findings for the screen.</summary>
/// <param name="Diagnostics">Findings in line order (a huge list is cut; the counts are not).</param>
/// <param name="Blocks">Blocks in the program.</param>
/// <param name="Errors">Findings that stop the program.</param>
/// <param name="Warnings">Findings that let it run.</param>
/// <param name="EstimatedSeconds">Run time at programmed feeds.</param>
public sealed record ProgramCheck(IReadOnlyList<Diagnostic> Diagnostics, long Blocks, int Errors, int Warnings, double EstimatedSeconds);

/// <summary>A job to start on an open controller.</summary>
/// <param name="Program">The split program.</param>
/// <param name="Strategy">How the rotary buffer is fed.</param>
public sealed record JobRequest(ChunkedProgram Program, StrategyKind Strategy)
{
    /// <summary>Buffer words, window, tick period (and the safe Z the plan was made with).</summary>
    public RunSettings Settings { get; init; } = RunSettings.Default;

    /// <summary>Start at a block behind this plan's preamble (<see cref="JobService.PlanStart"/>); null: from the top.</summary>
    public StartPlan? Plan { get; init; }

    /// <summary>
    /// Selected blocks: the job ends after the block of this source line (a move; <see cref="JobService.CheckRange"/>
    /// checks it first), running the blocks from <see cref="Plan"/>'s line (or the top) to it and nothing after; null:
    /// to the program's end. The job record keeps it.
    /// </summary>
    public int? ToLine { get; init; }

    /// <summary>Single-block mode.</summary>
    public bool SingleBlock { get; init; }

    /// <summary>Optional stop on: the controller stops at <c>M01</c> (the switch is set on the controller at the start, and can be changed live).</summary>
    public bool OptionalStop { get; init; } = true;

    /// <summary>
    /// The coordinate system's feed override in percent (<c>&amp;n %</c>, 0-200), set before the start once the
    /// coordinate system is known idle, so a value left by an earlier job never carries over.
    /// </summary>
    public double FeedOverride { get; init; } = FeedOverrides.Default;

    /// <summary>The machine profile of the program (the move times of the ETA are interpreted with it).</summary>
    public MachineProfile Profile { get; init; } = MachineProfile.Default;

    /// <summary>
    /// What the job does about the controller's PROG 1000/1001 library before anything is recorded or sent: verify it
    /// is the library of <see cref="Profile"/> (the default), load it first (only while the coordinate system is idle),
    /// or only warn (forced).
    /// </summary>
    public LibraryPolicy Library { get; init; } = LibraryPolicy.Verify;

    /// <summary>Record the job and its checkpoints in the job store (resumable); the demo does not.</summary>
    public bool Record { get; init; } = true;

    /// <summary>The program revision in the store that runs (its id), or null.</summary>
    public long? ProgramId { get; init; }

    /// <summary>The station (this PC) as the history names it; null: the host name.</summary>
    public string? Station { get; init; }

    /// <summary>The machine as the history names it; null: its connection (host:port, serial device, sim).</summary>
    public string? Machine { get; init; }
}

/// <summary>An unfinished job whose program is unchanged and whose split is readable.</summary>
/// <param name="Record">The job as recorded.</param>
/// <param name="Program">Its split.</param>
/// <param name="RestartLine">Where a restart starts behind a preamble: the block that was executing, else the job's own start line; null: from the top.</param>
/// <param name="Chunk">The chunk holding that line.</param>
/// <param name="Settings">The run settings the job started with; null in records of older versions.</param>
public sealed record ResumableJob(JobRecord Record, ChunkedProgram Program, int? RestartLine, int Chunk, RunSettings? Settings)
{
    /// <summary>The first line not known to have executed (what the screen shows).</summary>
    public int ResumeLine => RestartLine ?? Program.Manifest.Chunks[0].FirstSourceLine;
}

/// <summary>A resume of an unfinished job on an open controller (<see cref="JobService.ResumeAsync"/>).</summary>
/// <param name="Job">The job, opened by <see cref="JobService.OpenResumable"/>.</param>
/// <param name="Settings">The run settings it goes on with (the job's own, unless the operator says otherwise).</param>
/// <param name="ConfirmRestart">Asked when the controller lost the job: true starts it again behind the proposal's preamble.</param>
public sealed record ResumeRequest(ResumableJob Job, RunSettings Settings, Func<RestartProposal, Task<bool>> ConfirmRestart)
{
    /// <summary>The feed override in percent, set on the continued job at once or before the restart; null leaves the controller's.</summary>
    public double? FeedOverride { get; init; }

    /// <summary>The machine profile the job ran under (<see cref="JobService.ProfileOf(JobRecord, string?)"/>); null: <see cref="MachineProfile.Default"/>.</summary>
    public MachineProfile? Profile { get; init; }

    /// <summary>Resume although the program uses codes the controller cannot run yet, or its split was forced past errors.</summary>
    public bool Force { get; init; }

    /// <summary>Optional stop on: the controller stops at <c>M01</c>.</summary>
    public bool OptionalStop { get; init; } = true;

    /// <summary>The library check before anything reaches the controller; null: <see cref="LibraryPolicy.Force"/> when forced, else <see cref="LibraryPolicy.Verify"/>.</summary>
    public LibraryPolicy? Library { get; init; }

    /// <summary>The station resuming it (the history records it); null: keep the recorded one.</summary>
    public string? Station { get; init; }
}

/// <summary>How a resume goes on.</summary>
public enum ResumeKind
{
    /// <summary>The controller still holds the job: sending continues where it stopped; the job runs.</summary>
    Continued,

    /// <summary>The job's start had not finished loading: it was cleared and loaded again; the job runs.</summary>
    Reloaded,

    /// <summary>The controller lost the job: a new start at <see cref="ResumableJob.RestartLine"/>; call <see cref="Job.StartAsync"/>.</summary>
    Restart,

    /// <summary>The operator declined the restart; nothing was sent.</summary>
    Declined,

    /// <summary>
    /// The job record and the controller disagree in a way that could repeat or skip a block: nothing but <c>CLOSE</c>
    /// and queries was sent, no restart is proposed; <see cref="ResumeResult.Reason"/> gives both positions and the
    /// operator's choices.
    /// </summary>
    Refused,
}

/// <summary>What a resume did.</summary>
/// <param name="Kind">How it goes on.</param>
/// <param name="Job">The job (null when declined or refused).</param>
/// <param name="Reason">Why the controller could not continue (restarts), why the resume was refused, else null.</param>
public sealed record ResumeResult(ResumeKind Kind, Job? Job, string? Reason = null)
{
    /// <summary>The line a restart was proposed at (declined), or where a start from a line would begin once the controller stopped (refused); null when none is named.</summary>
    public int? RestartLine { get; init; }
}

/// <summary>A restart the operator is asked about: its plan (null: from the top) and why the job cannot simply continue.</summary>
/// <param name="Line">The line it restarts at, null from the top.</param>
/// <param name="Plan">The start plan with its preamble.</param>
/// <param name="Reason">Why the controller could not continue, when it was asked.</param>
public sealed record RestartProposal(int? Line, StartPlan? Plan, string? Reason);
