using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// How <see cref="Splitter"/> cuts a program into rotary-buffer chunks: the <see cref="Shape"/> of the chunks (defaults:
/// 1000 blocks and ~50 KB per chunk, <c>F(P500)</c> feeds, the <c>M0==line</c> synchronous assignment before each
/// move's words), where they go, and how the program is checked on the way.
/// </summary>
public sealed record SplitOptions
{
    /// <summary>What shapes the chunks' bytes; the properties below up to <see cref="BlockDelete"/> are views on it.</summary>
    public ChunkShape Shape { get; init; } = ChunkShape.Default;

    /// <summary>
    /// <see cref="Shape"/> as the chunks are written: its tail named (the shape's own, else the checking profile's,
    /// else the default profile's). The manifest keeps it and the split cache compares it.
    /// </summary>
    public ChunkShape ResolvedShape => Shape.WithTailOf(CheckProfile ?? MachineProfile.Default);

    /// <summary>At most this many source blocks per chunk (<see cref="ChunkShape.BlocksPerChunk"/>).</summary>
    public int BlocksPerChunk { get => Shape.BlocksPerChunk; init => Shape = Shape with { BlocksPerChunk = value }; }

    /// <summary>The rotary-buffer words a chunk must fit in (<see cref="ChunkShape.ChunkWords"/>; <c>--rot-words</c>).</summary>
    public int RotWords { get => Shape.ChunkWords; init => Shape = Shape with { ChunkWords = value }; }

    /// <summary>Words charged at least per emitted block (<see cref="ChunkShape.WordsPerBlock"/>).</summary>
    public int WordsPerBlock { get => Shape.WordsPerBlock; init => Shape = Shape with { WordsPerBlock = value }; }

    /// <summary>Text bytes allowed per rotary word (<see cref="ChunkShape.BytesPerWord"/>).</summary>
    public int BytesPerWord { get => Shape.BytesPerWord; init => Shape = Shape with { BytesPerWord = value }; }

    /// <summary>Byte budget of a chunk file (header, blocks, tail and <c>CLOSE</c> included).</summary>
    public long MaxChunkBytes => Shape.MaxChunkBytes;

    /// <summary>The M-variable that receives the executing source line (<c>M0==line</c>).</summary>
    public string TrackVariable { get => Shape.TrackVariable; init => Shape = Shape with { TrackVariable = value }; }

    /// <summary>Where the tracking assignment goes (exact: before the move; paper: after it).</summary>
    public TrackingPlacement Tracking { get => Shape.Tracking; init => Shape = Shape with { Tracking = value }; }

    /// <summary>Paper: <c>F(P500)</c> on moves and programmed F carried into P500; override: F words kept.</summary>
    public FeedMode Feed { get => Shape.Feed; init => Shape = Shape with { Feed = value }; }

    /// <summary>The variable the feed expression reads (<c>F(P500)</c>).</summary>
    public string FeedVariable { get => Shape.FeedVariable; init => Shape = Shape with { FeedVariable = value }; }

    /// <summary>Keep <c>N</c> numbers (a PMAC reads them as labels, so they are dropped by default).</summary>
    public bool KeepN { get => Shape.KeepN; init => Shape = Shape with { KeepN = value }; }

    /// <summary>Block delete switch on: <c>/</c> blocks are skipped. Off: they run (emitted without the slash).</summary>
    public bool BlockDelete { get => Shape.BlockDelete; init => Shape = Shape with { BlockDelete = value }; }

    /// <summary>Lines appended after the last source block of the last chunk: <see cref="ResolvedShape"/>'s tail.</summary>
    public string ProgramTail { get => ResolvedShape.ProgramTail!; init => Shape = Shape with { ProgramTail = value }; }

    /// <summary>Output folder; null means <c>&lt;source dir&gt;/&lt;name&gt;_chunks</c> beside the source.</summary>
    public string? OutDir { get; init; }

    /// <summary>Split even when the program has errors (<c>--force</c>); erroneous words are dropped, not emitted.</summary>
    public bool AllowErrors { get; init; }

    /// <summary>
    /// When set (and <see cref="AllowErrors"/> is off), the checker runs against this machine profile in the
    /// same streamed pass, on the same lexed blocks the splitter consumes; any error it finds refuses the split
    /// (<see cref="SplitException.FromChecker"/>), listing the errors, and nothing is written. When null only the
    /// lexical errors refuse.
    /// </summary>
    public MachineProfile? CheckProfile { get; init; }

    /// <summary>Folders, limits and the variable file of the expansion of programs with subprograms or macros (null: the defaults).</summary>
    public GCode.Expansion.ExpansionOptions? Expansion { get; init; }

    /// <summary>
    /// The profile the split is checked against, named for the manifest and for reusing a split: the profile's name
    /// and the start of the SHA-256 of its JSON (two profiles of one name but other codes differ); null when the split
    /// does not check (<see cref="AllowErrors"/>, or no <see cref="CheckProfile"/>).
    /// </summary>
    public string? CheckedProfile => CheckProfile is null || AllowErrors ? null : ProfileIdentity(CheckProfile);

    /// <summary>How many errors a refusal lists (the total is always counted).</summary>
    public int MaxReportedErrors { get; init; } = 50;

    /// <summary>Test hook: called after each chunk file is written (index), so a failure can be injected mid-way.</summary>
    internal Action<int>? AfterChunkWritten { get; init; }

    /// <summary>
    /// Simple axis lines (<see cref="AxisLine"/>) skip the general lexer and interpreter. Off only in tests, which
    /// compare both paths: the results must be byte for byte the same.
    /// </summary>
    internal bool AxisLane { get; init; } = true;

    /// <summary>Throws <see cref="ArgumentException"/> naming the first bad setting (the shape's rules are <see cref="ChunkShape.Validate"/>).</summary>
    public void Validate() => Shape.Validate();

    /// <summary>A machine profile's name and digest (see <see cref="CheckedProfile"/>).</summary>
    public static string ProfileIdentity(MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return profile.Identity;
    }
}
