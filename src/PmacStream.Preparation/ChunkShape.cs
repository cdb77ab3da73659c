using System.Text.Json;
using System.Text.Json.Nodes;
using System.Text.Json.Serialization;
using System.Text.Json.Serialization.Metadata;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// Everything that shapes a chunk file's bytes, in one record: how many blocks and words a chunk may take, the
/// tracking and feed variables and their placement, the program tail, N numbers and block delete. Validated here
/// only (<see cref="Validate"/>); the splitter writes it whole into <c>manifest.json</c> (<see cref="ChunkManifest.Shape"/>),
/// the split cache reuses a split only when the manifest's shape <c>==</c> the asked one, the job service's
/// <c>RunSettings</c> holds it and the settings file reads its properties by their JSON names. A new chunk-shaping
/// option is a property here (and its check in <see cref="Validate"/>), its use in the splitter, and its command-line
/// option: the manifest, the cache, the settings file and the job record follow by themselves.
/// </summary>
public sealed record ChunkShape
{
    private readonly string _trackVariable = PreparationDefaults.TrackVariable;
    private readonly string _feedVariable = PreparationDefaults.FeedVariable;

    /// <summary>Every property at its default (the tail left to the machine profile).</summary>
    public static ChunkShape Default { get; } = new();

    /// <summary>At most this many source blocks per chunk (blocks, not text lines: comments and blank lines do not count).</summary>
    public int BlocksPerChunk { get; init; } = PreparationDefaults.BlocksPerChunk;

    /// <summary>
    /// Rotary-buffer words one chunk may take (6400 x 8 bytes = a ~50 KB chunk file); the job's <c>DEFINE ROT</c>
    /// must hold the executing chunk's rest and the next whole chunk. Manifests call it <c>rotWords</c> too.
    /// </summary>
    public int ChunkWords { get; init; } = PreparationDefaults.ChunkWords;

    /// <summary>
    /// Explicit words-per-block estimate: every emitted block is charged at least this many rotary-buffer words
    /// (more when it carries more values: each letter value, assignment or <c>F(...)</c> counts one word).
    /// pmac-facts: a 4-axis move line takes about 4-6 words.
    /// </summary>
    public int WordsPerBlock { get; init; } = 6;

    /// <summary>Text bytes allowed per rotary word; the chunk file byte budget is <see cref="ChunkWords"/> x this.</summary>
    public int BytesPerWord { get; init; } = 8;

    /// <summary>Byte budget of a chunk file (header, blocks, tail and <c>CLOSE</c> included).</summary>
    [JsonIgnore]
    public long MaxChunkBytes => (long)ChunkWords * BytesPerWord;

    /// <summary>The M-variable that receives the executing source line (<c>M0==line</c>); kept upper-case, so <c>==</c> ignores case.</summary>
    public string TrackVariable
    {
        get => _trackVariable;
        init => _trackVariable = Normalize(value);
    }

    /// <summary>Where the tracking assignment goes (exact: before the move; paper: after it).</summary>
    public TrackingPlacement Tracking { get; init; } = TrackingPlacement.Exact;

    /// <summary>Paper: <c>F(P500)</c> on moves and programmed F carried into P500; override: F words kept.</summary>
    public FeedMode Feed { get; init; } = FeedMode.Paper;

    /// <summary>The variable the feed expression reads (<c>F(P500)</c>); kept upper-case.</summary>
    public string FeedVariable
    {
        get => _feedVariable;
        init => _feedVariable = Normalize(value);
    }

    /// <summary>
    /// Lines appended after the last source block of the last chunk (one line per <c>\n</c>); null: the machine
    /// profile's (<c>M05</c> by default; some machines want <c>M03 M05</c>). A manifest's shape always names it.
    /// </summary>
    public string? ProgramTail { get; init; }

    /// <summary>Keep <c>N</c> numbers (a PMAC reads them as labels, so they are dropped by default).</summary>
    public bool KeepN { get; init; }

    /// <summary>Block delete switch on: <c>/</c> blocks are skipped. Off: they run (emitted without the slash).</summary>
    public bool BlockDelete { get; init; } = true;

    /// <summary>The JSON names of the properties (<c>blocksPerChunk</c>, <c>chunkWords</c>, ...), as the manifest and settings files spell them.</summary>
    public static IReadOnlyList<string> JsonNames { get; } = [.. JsonSerializer.SerializeToNode(Default, JsonInfo)!.AsObject().Select(p => p.Key)];

    private static JsonTypeInfo<ChunkShape> JsonInfo => ChunkManifestJsonContext.Default.ChunkShape;

    /// <summary>This shape with the tail named: its own, else <paramref name="profile"/>'s.</summary>
    public ChunkShape WithTailOf(MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return ProgramTail is null ? this with { ProgramTail = profile.ProgramTail } : this;
    }

    /// <summary>Throws <see cref="ArgumentException"/> naming the first property that cannot make a chunk.</summary>
    public void Validate()
    {
        if (BlocksPerChunk < 1)
        {
            throw new ArgumentException($"blocks per chunk must be at least 1 (got {BlocksPerChunk})");
        }

        if (ChunkWords < 1 || WordsPerBlock < 1 || BytesPerWord < 1)
        {
            throw new ArgumentException($"chunk words, words per block and bytes per word must be positive (got {ChunkWords}, {WordsPerBlock}, {BytesPerWord})");
        }

        if (!IsVariable(TrackVariable) || !TrackVariable.StartsWith('M'))
        {
            throw new ArgumentException($"track variable must be an M-variable such as M0 (got '{TrackVariable}')");
        }

        if (!IsVariable(FeedVariable))
        {
            throw new ArgumentException($"feed variable must be a P, Q or M variable such as P500 (got '{FeedVariable}')");
        }

        if (!Enum.IsDefined(Tracking) || !Enum.IsDefined(Feed))
        {
            throw new ArgumentException($"tracking must be exact or paper and feed paper or override (got {(int)Tracking}, {(int)Feed})");
        }

        foreach (var c in ProgramTail ?? string.Empty)
        {
            if (c > 127 || (c < 32 && c != '\n' && c != '\r' && c != '\t'))
            {
                throw new ArgumentException($"program tail must be plain ASCII (got '{ProgramTail}')");
            }
        }
    }

    /// <summary>
    /// This shape with the property of JSON name <paramref name="name"/> read from <paramref name="value"/> (as the
    /// manifest writes it), or null when the shape has no such property. Not validated.
    /// </summary>
    /// <exception cref="JsonException">The value is not of the property's type.</exception>
    public ChunkShape? WithJson(string name, JsonElement value)
    {
        if (!JsonNames.Contains(name))
        {
            return null;
        }

        var node = JsonSerializer.SerializeToNode(this, JsonInfo)!.AsObject();
        node[name] = JsonNode.Parse(value.GetRawText());
        return node.Deserialize(JsonInfo) ?? throw new JsonException("expected a value");
    }

    /// <summary>What a JSON value of property <paramref name="name"/> looks like, for a message (<c>a number</c>).</summary>
    public static string ExpectedJson(string name)
    {
        var type = JsonInfo.Properties.FirstOrDefault(p => p.Name == name)?.PropertyType;
        return type == typeof(int) ? "a whole number"
            : type == typeof(bool) ? "true or false"
            : type == typeof(TrackingPlacement) ? "\"exact\" or \"paper\""
            : type == typeof(FeedMode) ? "\"paper\" or \"override\""
            : "a string";
    }

    /// <summary>Writes every property, by its JSON name, into the open object of <paramref name="writer"/>.</summary>
    public void WriteProperties(Utf8JsonWriter writer)
    {
        ArgumentNullException.ThrowIfNull(writer);
        foreach (var (name, value) in JsonSerializer.SerializeToNode(this, JsonInfo)!.AsObject())
        {
            writer.WritePropertyName(name);
            if (value is null)
            {
                writer.WriteNullValue();
            }
            else
            {
                value.WriteTo(writer);
            }
        }
    }

    private static string Normalize(string? variable) => variable?.Trim().ToUpperInvariant() ?? string.Empty;

    /// <summary>P, Q or M followed by 1-4 digits (no Regex: it would load an assembly for one check).</summary>
    private static bool IsVariable(string name) =>
        name.Length is >= 2 and <= 5 && name[0] is 'P' or 'Q' or 'M' && name.AsSpan(1).IndexOfAnyExceptInRange('0', '9') < 0;
}
