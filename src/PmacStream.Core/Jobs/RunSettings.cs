using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>
/// How a job is cut and run, the same for every face: the command line binds its options to it, the HMI its
/// controls, a JSON settings file (<see cref="RunSettingsFile"/>) overrides the defaults, and the job record keeps
/// the settings a job started with. It starts from the defaults of the layers that use each value
/// (<see cref="PreparationDefaults"/>, <see cref="StreamingDefaults"/>).
/// </summary>
public sealed record RunSettings
{
    /// <summary>Source blocks per chunk: 1000-block chunk files.</summary>
    public const int DefaultBlocksPerChunk = PreparationDefaults.BlocksPerChunk;

    /// <summary>Rotary buffer words (<c>&amp;1 DEFINE ROT</c>): room for the executing chunk's rest and the next whole chunk.</summary>
    public const int DefaultBufferWords = StreamingDefaults.BufferWords;

    /// <summary>
    /// Rotary buffer words of the <c>full</c> strategy at least (it defines the buffer at the start): a Turbo PMAC's
    /// standard user memory has about 26K words for programs and buffers (34K/42K with P or P and Q variables in
    /// battery-backed RAM, 212K with the expanded memory option), less what the PROG 1000 library and the PLCs take;
    /// see docs/turbo-pmac-timing.md. <c>--buffer-words</c> larger than this is used as given (extended memory).
    /// </summary>
    public const int FullBufferWords = 24_000;

    /// <summary>Words one chunk may take: 6400 words x 8 bytes is a ~50 KB chunk file, what one motion program buffer holds.</summary>
    public const int DefaultChunkWords = PreparationDefaults.ChunkWords;

    /// <summary>The download window opens at line 600 of a 1000-line chunk.</summary>
    public const double DefaultWindowStart = StreamingDefaults.WindowStart;

    /// <summary>The download window closes at line 700 of a 1000-line chunk.</summary>
    public const double DefaultWindowEnd = StreamingDefaults.WindowEnd;

    /// <summary>The M-variable the synchronous tracking assignment writes (<c>M0==line</c>).</summary>
    public const string DefaultTrackVariable = PreparationDefaults.TrackVariable;

    /// <summary>The live feed variable moves read (<c>F(P500)</c>).</summary>
    public const string DefaultFeedVariable = PreparationDefaults.FeedVariable;

    /// <summary>The optional-stop switch the library's <c>M01</c> routine reads (1: stop there, 0: go on).</summary>
    public const string DefaultOptionalStopVariable = PreparationDefaults.OptionalStopVariable;

    /// <summary>Words the session keeps free in the rotary buffer against the splitter's estimate.</summary>
    public const int BufferMarginWords = StreamingDefaults.BufferMarginWords;

    /// <summary>The timer period (timer1's interval).</summary>
    public static readonly TimeSpan DefaultTickPeriod = StreamingDefaults.TickPeriod;

    /// <summary>Every setting at its default.</summary>
    public static RunSettings Default { get; } = new();

    /// <summary>
    /// What shapes the chunks' bytes when a program is split (<see cref="ChunkShape"/>: validated there, kept whole in
    /// the manifest); its tail, left open, is the machine profile's. The four properties below are views on it.
    /// </summary>
    public ChunkShape Shape { get; init; } = ChunkShape.Default;

    /// <summary>Most source blocks per chunk file (<see cref="ChunkShape.BlocksPerChunk"/>).</summary>
    public int BlocksPerChunk { get => Shape.BlocksPerChunk; init => Shape = Shape with { BlocksPerChunk = value }; }

    /// <summary>Rotary buffer size in words; the built-in simulator's buffer is defined to it.</summary>
    public int BufferWords { get; init; } = DefaultBufferWords;

    /// <summary>
    /// <c>full</c> strategy over Ethernet: WRITEBUFFER packets in flight (1: each waits for its reply). Several ride out
    /// lost replies (docs/turbo-pmac-timing.md, "Links").
    /// </summary>
    public int PacketsInFlight { get; init; } = StreamingDefaults.PacketsInFlight;

    /// <summary><c>full</c> strategy: most words of a rotary buffer sized from the controller's <c>SIZE</c>; 0: no cap.</summary>
    public int BufferWordsCap { get; init; }

    /// <summary>Estimated words one chunk may take (<see cref="ChunkShape.ChunkWords"/>: the splitter's budget; bytes = words x 8).</summary>
    public int ChunkWords { get => Shape.ChunkWords; init => Shape = Shape with { ChunkWords = value }; }

    /// <summary>Start of the download window, as a fraction of the executing chunk.</summary>
    public double WindowStart { get; init; } = DefaultWindowStart;

    /// <summary>End of the download window, as a fraction of the executing chunk.</summary>
    public double WindowEnd { get; init; } = DefaultWindowEnd;

    /// <summary>Tracking variable written by each move's synchronous assignment (<see cref="ChunkShape.TrackVariable"/>).</summary>
    public string TrackVariable { get => Shape.TrackVariable; init => Shape = Shape with { TrackVariable = value }; }

    /// <summary>Feed variable of <c>F(...)</c> on moves (<see cref="ChunkShape.FeedVariable"/>).</summary>
    public string FeedVariable { get => Shape.FeedVariable; init => Shape = Shape with { FeedVariable = value }; }

    /// <summary>Timer period of the streaming tick.</summary>
    public TimeSpan TickPeriod { get; init; } = DefaultTickPeriod;

    /// <summary>Safe Z rule of a start from a line.</summary>
    public SafeZMode SafeZMode { get; init; } = SafeZMode.Fixed;

    /// <summary>Safe Z in work coordinates (fixed mode, and the fallback of highest).</summary>
    public double SafeZ { get; init; } = 10;

    /// <summary>Added to the highest Z so far in highest mode.</summary>
    public double Clearance { get; init; } = 5;

    /// <summary>The window as <c>0.6-0.7</c>.</summary>
    public string Window => string.Create(CultureInfo.InvariantCulture, $"{WindowStart:0.###}-{WindowEnd:0.###}");

    /// <summary>
    /// Parses a download window: <c>START-END</c> as fractions of a chunk (<c>0.6-0.7</c>) or percentages
    /// (<c>60-70%</c>). Throws <see cref="FormatException"/> naming the forms.
    /// </summary>
    public static (double Start, double End) ParseWindow(string text)
    {
        ArgumentNullException.ThrowIfNull(text);
        var t = text.Trim();
        var percent = t.EndsWith('%');
        var parts = t.TrimEnd('%').Split('-', StringSplitOptions.TrimEntries);
        if (parts.Length != 2
            || !double.TryParse(parts[0].TrimEnd('%'), NumberStyles.Float, CultureInfo.InvariantCulture, out var start)
            || !double.TryParse(parts[1], NumberStyles.Float, CultureInfo.InvariantCulture, out var end))
        {
            throw new FormatException($"window '{text}': expected START-END as fractions of a chunk (0.6-0.7) or percent (60-70%)");
        }

        return percent ? (start / 100, end / 100) : (start, end);
    }

    /// <summary>Throws <see cref="ArgumentException"/> naming the first setting that cannot work.</summary>
    public void Validate()
    {
        // The shape's own rules first: chunk words positive, the variables' forms.
        Shape.Validate();
        if (BufferWords < 1)
        {
            throw new ArgumentException($"buffer words must be positive (got {BufferWords})");
        }

        if (ChunkWords > BufferWords - BufferMarginWords)
        {
            throw new ArgumentException($"a chunk of {ChunkWords} words does not fit a rotary buffer of {BufferWords} words (less the {BufferMarginWords}-word margin)");
        }

        if (PacketsInFlight is < 1 or > 64 || BufferWordsCap < 0)
        {
            throw new ArgumentException($"packets in flight must be 1 to 64 and the buffer cap 0 or more (got {PacketsInFlight}, {BufferWordsCap})");
        }

        if (!(WindowStart >= 0 && WindowStart < WindowEnd && WindowEnd <= 1))
        {
            throw new ArgumentException($"download window {Window}: expected 0 <= start < end <= 1");
        }

        if (TickPeriod < TimeSpan.FromMilliseconds(5) || TickPeriod > TimeSpan.FromSeconds(10))
        {
            throw new ArgumentException($"tick period must be between 5 ms and 10 s (got {TickPeriod.TotalMilliseconds:0.###} ms)");
        }

        if (double.IsNaN(SafeZ) || double.IsInfinity(SafeZ) || !(Clearance >= 0) || double.IsInfinity(Clearance))
        {
            throw new ArgumentException($"safe Z must be a number and clearance 0 or more (got {SafeZ}, {Clearance})");
        }
    }

    /// <summary>
    /// The split these settings make: their <see cref="Shape"/> (the tail, when it leaves it open, the machine
    /// profile's), checked against that profile in the same pass unless <paramref name="force"/>.
    /// </summary>
    public SplitOptions ToSplitOptions(MachineProfile profile, string? outDir, bool force)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return new SplitOptions
        {
            Shape = Shape.WithTailOf(profile),
            OutDir = outDir,
            CheckProfile = profile,
            AllowErrors = force,
        };
    }

    /// <summary>
    /// The streaming session's options. <paramref name="clockFactor"/> is virtual seconds per real second when the
    /// host steps a simulator's clock (the session reasons in machine time); <paramref name="defineBuffer"/> defines
    /// the rotary buffer to <see cref="BufferWords"/> before the start. The operator's feed control is the coordinate
    /// system's feed override (<c>&amp;n %</c>) whatever the split's feed mode: the program's own feeds (carried in
    /// P500 in paper mode) stay the program's.
    /// </summary>
    public StreamingOptions ToStreamingOptions(StrategyKind strategy, bool singleBlock, bool defineBuffer, double clockFactor = 1) => new()
    {
        Strategy = strategy,
        // The full strategy's lead is the buffer: it defines one as large as the controller allows, on any controller.
        BufferWords = strategy == StrategyKind.Full ? Math.Max(BufferWords, FullBufferWords) : BufferWords,
        SafetyWords = BufferMarginWords,
        DefineBuffer = defineBuffer || strategy == StrategyKind.Full,
        SizeBufferFromController = strategy == StrategyKind.Full,
        BufferWordsCap = BufferWordsCap,
        PacketsInFlight = PacketsInFlight,
        WindowStart = WindowStart,
        WindowEnd = WindowEnd,
        TickPeriod = TickPeriod * clockFactor,
        SingleBlock = singleBlock,
        Feed = FeedMode.Override,
    };

    /// <summary>How a start from a line is planned for a split program (its feed mode and variable, this safe Z).</summary>
    public StartPlanOptions ToStartPlanOptions(ChunkManifest manifest, MachineProfile profile) =>
        StartPlanOptions.For(manifest, new StartPlanOptions { SafeZMode = SafeZMode, SafeZ = SafeZ, Clearance = Clearance, Profile = profile });
}
