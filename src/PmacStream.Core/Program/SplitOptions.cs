using PmacStream.GCode;

namespace PmacStream.Program;

/// <summary>
/// How <see cref="Splitter"/> cuts a program into rotary-buffer chunks. Defaults: 1000 blocks and ~50 KB per chunk,
/// <c>F(P500)</c> feeds, the <c>M0==line</c> synchronous assignment before each move's words (M0 names the move
/// that executes).
/// </summary>
public sealed record SplitOptions
{
    /// <summary>At most this many source blocks per chunk.</summary>
    public int LinesPerChunk { get; init; } = Jobs.RunSettings.DefaultLinesPerChunk;

    /// <summary>The <c>DEFINE ROT</c> size in controller words a chunk must fit in (6400 x 8 bytes = ~50 KB).</summary>
    public int RotWords { get; init; } = Jobs.RunSettings.DefaultChunkWords;

    /// <summary>
    /// Explicit words-per-block estimate: every emitted block is charged at least this many rotary-buffer words
    /// (more when it carries more values: each letter value, assignment or <c>F(...)</c> counts one word).
    /// pmac-facts: a 4-axis move line takes about 4-6 words.
    /// </summary>
    public int WordsPerBlock { get; init; } = 6;

    /// <summary>Text bytes allowed per rotary word; the chunk file byte budget is <see cref="RotWords"/> x this.</summary>
    public int BytesPerWord { get; init; } = 8;

    /// <summary>Byte budget of a chunk file (header, blocks, tail and <c>CLOSE</c> included).</summary>
    public long MaxChunkBytes => (long)RotWords * BytesPerWord;

    /// <summary>The M-variable that receives the executing source line (<c>M0==line</c>).</summary>
    public string TrackVariable { get; init; } = Jobs.RunSettings.DefaultTrackVariable;

    /// <summary>Where the tracking assignment goes (exact: before the move; paper: after it).</summary>
    public TrackingPlacement Tracking { get; init; } = TrackingPlacement.Exact;

    /// <summary>Paper: <c>F(P500)</c> on moves and programmed F carried into P500; override: F words kept.</summary>
    public FeedMode Feed { get; init; } = FeedMode.Paper;

    /// <summary>The variable the feed expression reads (<c>F(P500)</c>).</summary>
    public string FeedVariable { get; init; } = Jobs.RunSettings.DefaultFeedVariable;

    /// <summary>Keep <c>N</c> numbers (a PMAC reads them as labels, so they are dropped by default).</summary>
    public bool KeepN { get; init; }

    /// <summary>Block delete switch on: <c>/</c> blocks are skipped. Off: they run (emitted without the slash).</summary>
    public bool BlockDelete { get; init; } = true;

    /// <summary>
    /// Lines appended after the last source block of the last chunk (one line per <c>\n</c>). Default <c>M05</c>;
    /// some machines want <c>M03 M05</c> (a machine profile setting, not a constant).
    /// </summary>
    public string ProgramTail { get; init; } = "M05";

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

    /// <summary>Throws <see cref="ArgumentException"/> naming the first bad setting.</summary>
    public void Validate()
    {
        if (LinesPerChunk < 1)
        {
            throw new ArgumentException($"lines per chunk must be at least 1 (got {LinesPerChunk})");
        }

        if (RotWords < 1 || WordsPerBlock < 1 || BytesPerWord < 1)
        {
            throw new ArgumentException($"rot words, words per block and bytes per word must be positive (got {RotWords}, {WordsPerBlock}, {BytesPerWord})");
        }

        if (!IsVariable(TrackVariable) || !TrackVariable.StartsWith('M'))
        {
            throw new ArgumentException($"track variable must be an M-variable such as M0 (got '{TrackVariable}')");
        }

        if (!IsVariable(FeedVariable))
        {
            throw new ArgumentException($"feed variable must be a P, Q or M variable such as P500 (got '{FeedVariable}')");
        }

        foreach (var c in ProgramTail)
        {
            if (c > 127 || (c < 32 && c != '\n' && c != '\r' && c != '\t'))
            {
                throw new ArgumentException($"program tail must be plain ASCII (got '{ProgramTail}')");
            }
        }
    }

    /// <summary>A machine profile's name and digest (see <see cref="CheckedProfile"/>).</summary>
    public static string ProfileIdentity(MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return profile.Identity;
    }

    /// <summary>P, Q or M followed by 1-4 digits (no Regex: it would load an assembly for one check).</summary>
    private static bool IsVariable(string name) =>
        name.Length is >= 2 and <= 5 && name[0] is 'P' or 'Q' or 'M' && name.AsSpan(1).IndexOfAnyExceptInRange('0', '9') < 0;
}
