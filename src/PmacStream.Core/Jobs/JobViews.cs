using PmacStream.GCode;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>A chunk of a split as a screen lists it.</summary>
/// <param name="Number">1-based chunk number.</param>
/// <param name="FileName">The chunk file's name in <see cref="SplitView.Folder"/>.</param>
/// <param name="FirstSourceLine">First source line of its blocks.</param>
/// <param name="LastSourceLine">Last source line of its blocks.</param>
/// <param name="BlockCount">Source blocks in it.</param>
public sealed record ChunkView(int Number, string FileName, int FirstSourceLine, int LastSourceLine, int BlockCount);

/// <summary>
/// A split program as the faces see it: its chunks and where their files are, without preparation's manifest types.
/// Made by the job service (<see cref="JobService.PrepareViewAsync"/>), which keeps the split it read behind it; one
/// made elsewhere (a test's) is read from <see cref="Folder"/> when the service needs the split.
/// </summary>
/// <param name="SourcePath">The G-code program.</param>
/// <param name="Folder">Folder of the manifest and the chunk files.</param>
/// <param name="Chunks">The chunks in order.</param>
/// <param name="TotalBlocks">Source blocks in the program.</param>
public sealed record SplitView(string SourcePath, string Folder, IReadOnlyList<ChunkView> Chunks, long TotalBlocks)
{
    /// <summary>The split as the service read it; null: read it from <see cref="Folder"/>.</summary>
    internal ChunkedProgram? Program { get; init; }

    /// <summary>
    /// The stored revision the split was prepared from (<see cref="PreparedProgram.ProgramId"/>): a job of it records
    /// it, a start from a line reads its stored states and the preview its stored blocks; null: a file only.
    /// </summary>
    public long? ProgramId { get; init; }

    /// <summary>
    /// Why the program is not a stored revision although the face asked for one (the store could not keep it, so it
    /// was prepared as a file, as before the store); null otherwise.
    /// </summary>
    public string? NotStored { get; init; }

    /// <summary>Full path of a chunk file.</summary>
    public string ChunkPath(ChunkView chunk)
    {
        ArgumentNullException.ThrowIfNull(chunk);
        return Path.Combine(Folder, chunk.FileName);
    }

    /// <summary>The view of a split, of the stored revision <paramref name="programId"/> when it is one.</summary>
    internal static SplitView Of(ChunkedProgram program, long? programId = null) => new(
        program.Manifest.SourcePath,
        program.Folder,
        program.Manifest.Chunks.Select(c => new ChunkView(c.Index, c.FileName, c.FirstSourceLine, c.LastSourceLine, c.BlockCount)).ToList(),
        program.Manifest.TotalBlocks)
    {
        Program = program,
        ProgramId = programId,
    };
}

/// <summary>Which rows of a chunk file carry a block's tracked line (<c>M0==line</c>), as the session reads the chunk.</summary>
/// <param name="TrackedLines">The source lines, ascending.</param>
/// <param name="FileLines">The 1-based file row of each.</param>
public sealed record ChunkRows(IReadOnlyList<int> TrackedLines, IReadOnlyList<int> FileLines);

/// <summary>A program stop the job waits at (M00, or M01 with optional stop on).</summary>
/// <param name="Line">The source line of the stop.</param>
/// <param name="Code">The code (<c>M00</c>, <c>M01</c>), null when it names none.</param>
public sealed record JobStop(int Line, string? Code);

/// <summary>Where a job stands, as the faces name it.</summary>
public enum JobState
{
    /// <summary>Created, not started.</summary>
    Idle,

    /// <summary>Executing (or waiting in single-block mode).</summary>
    Running,

    /// <summary>Feed hold.</summary>
    Held,

    /// <summary>Every block executed.</summary>
    Completed,

    /// <summary>Stopped by the operator.</summary>
    Aborted,

    /// <summary>Stopped by an error; resumable from its checkpoint.</summary>
    Faulted,

    /// <summary>At a program stop: the controller waits for the run command.</summary>
    Stopped,
}

/// <summary>A job's status for a screen, in the job service's words.</summary>
/// <param name="State">Job state.</param>
/// <param name="CurrentChunk">1-based chunk executing (0 before the first).</param>
/// <param name="CurrentLine">Source line executing (0 before the first move).</param>
/// <param name="Percent">Executed share of the program, 0..100.</param>
/// <param name="FeedOverride">The feed override in percent as the controller last reported it; null when unknown.</param>
/// <param name="ProgrammedFeed">The program's feed at the executing block; null when unknown.</param>
/// <param name="Elapsed">Time since start.</param>
/// <param name="Eta">Estimated time to the end, when known.</param>
/// <param name="Message">Why it stopped (empty when nothing to say).</param>
/// <param name="Stop">The program stop it waits at, else null.</param>
/// <param name="OptionalStop">True while the controller stops at M01.</param>
public sealed record JobView(
    JobState State, int CurrentChunk, int CurrentLine, double Percent, double? FeedOverride, double? ProgrammedFeed, TimeSpan Elapsed, TimeSpan? Eta, string Message,
    JobStop? Stop, bool OptionalStop);

/// <summary>A job recorded for a program that did not finish, for a screen.</summary>
/// <param name="JobId">Job record id.</param>
/// <param name="Program">Its split.</param>
/// <param name="ResumeLine">First source line not known to have executed.</param>
/// <param name="Chunk">Chunk holding that line.</param>
/// <param name="Strategy">Strategy the job used (lower case).</param>
/// <param name="CheckpointTime">When the checkpoint was written (the job's start without one).</param>
public sealed record InterruptedJobView(long JobId, SplitView Program, int ResumeLine, int Chunk, string Strategy, DateTimeOffset CheckpointTime)
{
    /// <summary>The job as the service opened it; null: opened again from the job store by <see cref="JobId"/>.</summary>
    internal ResumableJob? Resumable { get; init; }
}

/// <summary>A job to start on a split a screen holds (<see cref="JobService.StartJobAsync"/>).</summary>
/// <param name="Program">The split.</param>
/// <param name="Strategy">Strategy name (one of <see cref="JobService.Strategies"/>; empty: the default).</param>
public sealed record SplitJobRequest(SplitView Program, string Strategy)
{
    /// <summary>Start at the block of this source line behind its restore preamble; null: from the top.</summary>
    public int? FromLine { get; init; }

    /// <summary>Selected blocks: end after the block of this source line (<see cref="JobRequest.ToLine"/>); null: to the program's end.</summary>
    public int? ToLine { get; init; }

    /// <summary>Buffer words, window, tick period and safe Z.</summary>
    public RunSettings Settings { get; init; } = RunSettings.Default;

    /// <summary>Single-block mode.</summary>
    public bool SingleBlock { get; init; }

    /// <summary>The feed override in percent set before the start.</summary>
    public double FeedOverride { get; init; } = FeedOverrides.Default;

    /// <summary>The machine profile the program was checked and split under.</summary>
    public MachineProfile Profile { get; init; } = MachineProfile.Default;

    /// <summary>Optional stop on: the controller stops at M01.</summary>
    public bool OptionalStop { get; init; } = true;

    /// <summary>The stored revision the program was prepared from (its start from a line reads the store), or null.</summary>
    public long? ProgramId { get; init; }

    /// <summary>The station starting it (the job history records it); null: none recorded.</summary>
    public string? Station { get; init; }

    /// <summary>The machine as leased (the job history records it); null: its connection.</summary>
    public string? Machine { get; init; }
}
