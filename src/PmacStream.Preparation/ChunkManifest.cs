using System.Text.Json;
using System.Text.Json.Serialization;

namespace PmacStream.Preparation;

/// <summary>Where the tracking marker goes relative to the move it tracks.</summary>
public enum TrackingPlacement
{
    /// <summary><c>M0==i</c> before the move of line i: M0 equals the line whose move is executing.</summary>
    Exact,

    /// <summary>After the words, <c>M0==i</c> at the end of line i: M0 reports i while line i+1 moves.</summary>
    Paper,
}

/// <summary>How the programmed feed reaches the controller.</summary>
public enum FeedMode
{
    /// <summary><c>F(P500)</c> on every move (a live feed); programmed F values are carried into P500.</summary>
    Paper,

    /// <summary>Programmed F words kept; speed changes through the <c>%</c> feed override.</summary>
    Override,
}

/// <summary>One chunk file of a split program: a rotary-buffer download unit.</summary>
/// <param name="Index">1-based chunk number.</param>
/// <param name="FileName">File name relative to the manifest's folder (<c>name_0001.pmc</c>).</param>
/// <param name="FirstSourceLine">First source line carried by the chunk.</param>
/// <param name="LastSourceLine">Last source line carried by the chunk.</param>
/// <param name="BlockCount">Source blocks in the chunk (non-empty blocks that produce a PMAC line).</param>
/// <param name="MotionBlockCount">Blocks in the chunk that execute a move or dwell (what the executed-move log counts).</param>
/// <param name="ByteSize">File size in bytes.</param>
/// <param name="EstimatedWords">Rotary-buffer words the chunk's program lines take (the splitter's estimate).</param>
/// <param name="Sha256">Hex SHA-256 of the file.</param>
public sealed record ChunkInfo(
    int Index,
    string FileName,
    int FirstSourceLine,
    int LastSourceLine,
    int BlockCount,
    int MotionBlockCount,
    long ByteSize,
    int EstimatedWords,
    string Sha256);

/// <summary>
/// <c>manifest.json</c>: what a split produced, so streaming, resume and the HMI know the chunks without re-splitting,
/// and can refuse a source that changed since (its SHA-256).
/// </summary>
public sealed record ChunkManifest(
    string SourcePath,
    long SourceSize,
    string SourceSha256,
    int TotalBlocks,
    int TotalMotionBlocks,
    string TrackVariable,
    TrackingPlacement Tracking,
    FeedMode Feed,
    string FeedVariable,
    IReadOnlyList<ChunkInfo> Chunks)
{
    /// <summary>The file name the splitter writes beside the chunks.</summary>
    public const string FileName = "manifest.json";

    /// <summary>
    /// What shaped the chunks' bytes, whole (its tail named); the split cache reuses the split only for an equal shape.
    /// Null in a manifest of an older version, which kept the shape in the flat fields below: such a split is read and
    /// streamed, but split again rather than reused.
    /// </summary>
    public ChunkShape? Shape { get; init; }

    /// <summary>Most source blocks per chunk (0 when unknown); written as <c>linesPerChunk</c> for readers of older manifests.</summary>
    [JsonPropertyName("linesPerChunk")]
    public int BlocksPerChunk => Shape?.BlocksPerChunk ?? 0;

    /// <summary>The words a chunk was allowed (<see cref="ChunkShape.ChunkWords"/>; 0 when unknown), for readers of older manifests.</summary>
    public int RotWords => Shape?.ChunkWords ?? 0;

    /// <summary>The explicit words-per-block estimate used (0 when unknown), for readers of older manifests.</summary>
    public int WordsPerBlock => Shape?.WordsPerBlock ?? 0;

    /// <summary>Byte budget of one chunk file (0 when unknown), for readers of older manifests.</summary>
    public long MaxChunkBytes => Shape?.MaxChunkBytes ?? 0;

    /// <summary>Lines appended to the last chunk after the last source block (null when unknown), for readers of older manifests.</summary>
    public string? ProgramTail => Shape?.ProgramTail;

    /// <summary>True when N numbers were kept in the chunks, for readers of older manifests.</summary>
    public bool KeepN => Shape?.KeepN ?? false;

    /// <summary>True when block delete was on (<c>/</c> blocks left out; true when unknown), for readers of older manifests.</summary>
    public bool BlockDelete => Shape?.BlockDelete ?? true;

    /// <summary>
    /// The machine profile the program was checked against while it was split, as <see cref="SplitOptions.CheckedProfile"/>
    /// names it (profile name and digest); null when it was not checked (forced, or no profile given).
    /// </summary>
    public string? CheckedProfile { get; init; }
    /// <summary>
    /// The codes the chunks carry that the controller cannot run yet, with the source line of their first use: a job
    /// gate refuses to stream such a split (null when the split had no profile).
    /// </summary>
    public IReadOnlyDictionary<string, int>? NotYetCodes { get; init; }

    /// <summary>
    /// The codes in the chunks whose routine stops the program (<c>M00</c>, <c>M01</c>: the profile's <c>"stop"</c>
    /// codes), with the source line of their first use; each such block is tracked (<c>M0==line DWELL0 M00</c>), so a
    /// job names the stop's line and code. Empty or null (manifests of older versions) when the program never stops.
    /// </summary>
    public IReadOnlyDictionary<string, int>? StopCodes { get; init; }

    /// <summary>Reads a manifest.</summary>
    public static ChunkManifest Load(string path)
    {
        using var s = File.OpenRead(path);
        return JsonSerializer.Deserialize(s, ChunkManifestJsonContext.Default.ChunkManifest) ?? throw new InvalidDataException($"{path}: empty manifest");
    }

    /// <summary>Writes the manifest as indented JSON.</summary>
    public void Save(string path)
    {
        using var s = new FileStream(path, FileMode.Create, FileAccess.Write, FileShare.None, 1 << 16);
        WriteTo(s);
    }

    /// <summary>
    /// The same JSON the serializer writes (same names, order and layout; <see cref="Load"/> reads it back), written
    /// field by field so that tens of thousands of chunks are not turned into records and strings first: a
    /// gigabyte program's manifest then costs no memory beyond the writer's buffer.
    /// </summary>
    internal void WriteTo(Stream stream)
    {
        using var w = new Utf8JsonWriter(stream, new JsonWriterOptions { Indented = true });
        w.WriteStartObject();
        w.WriteString("sourcePath", SourcePath);
        w.WriteNumber("sourceSize", SourceSize);
        w.WriteString("sourceSha256", SourceSha256);
        w.WriteNumber("totalBlocks", TotalBlocks);
        w.WriteNumber("totalMotionBlocks", TotalMotionBlocks);
        w.WriteString("trackVariable", TrackVariable);
        w.WriteString("tracking", Tracking == TrackingPlacement.Exact ? "exact" : "paper");
        w.WriteString("feed", Feed == FeedMode.Paper ? "paper" : "override");
        w.WriteString("feedVariable", FeedVariable);
        WriteChunks(w);
        WriteShape(w);
        WriteCodes(w);
        w.WriteEndObject();
    }

    /// <summary>The chunk table, row by row (a split's own table straight from its arrays).</summary>
    private void WriteChunks(Utf8JsonWriter w)
    {
        w.WriteStartArray("chunks");
        if (Chunks is ChunkTable table)
        {
            table.WriteTo(w);
        }
        else
        {
            foreach (var c in Chunks)
            {
                WriteChunk(w, c.Index, c.FileName, c.FirstSourceLine, c.LastSourceLine, c.BlockCount, c.MotionBlockCount,
                    c.ByteSize, c.EstimatedWords, c.Sha256);
            }
        }

        w.WriteEndArray();
    }

    /// <summary>The chunk shape whole, then its fields as older manifests name them.</summary>
    private void WriteShape(Utf8JsonWriter w)
    {
        if (Shape == null)
        {
            w.WriteNull("shape");
        }
        else
        {
            // The shape's own (generated) serializer, so that its fields are written and read by one definition.
            w.WritePropertyName("shape");
            JsonSerializer.Serialize(w, Shape, ChunkManifestJsonContext.Default.ChunkShape);
        }

        w.WriteNumber("linesPerChunk", BlocksPerChunk);
        w.WriteNumber("rotWords", RotWords);
        w.WriteNumber("wordsPerBlock", WordsPerBlock);
        w.WriteNumber("maxChunkBytes", MaxChunkBytes);
        WriteStringOrNull(w, "programTail", ProgramTail);
        w.WriteBoolean("keepN", KeepN);
        w.WriteBoolean("blockDelete", BlockDelete);
    }

    /// <summary>The checked profile and the codes the job gate and the stops read.</summary>
    private void WriteCodes(Utf8JsonWriter w)
    {
        WriteStringOrNull(w, "checkedProfile", CheckedProfile);
        if (NotYetCodes == null)
        {
            w.WriteNull("notYetCodes");
        }
        else
        {
            // In the order of first use (the splitter adds them as it reads).
            WriteCodeLines(w, "notYetCodes", NotYetCodes);
        }

        WriteCodeLines(w, "stopCodes", StopCodes ?? new Dictionary<string, int>());
    }

    private static void WriteCodeLines(Utf8JsonWriter w, string name, IReadOnlyDictionary<string, int> codes)
    {
        w.WriteStartObject(name);
        foreach (var (code, line) in codes)
        {
            w.WriteNumber(code, line);
        }

        w.WriteEndObject();
    }

    private static void WriteStringOrNull(Utf8JsonWriter w, string name, string? value)
    {
        if (value == null)
        {
            w.WriteNull(name);
        }
        else
        {
            w.WriteString(name, value);
        }
    }

    internal static void WriteChunk(Utf8JsonWriter w, int index, ReadOnlySpan<char> fileName, int first, int last, int blocks,
        int motion, long bytes, int words, ReadOnlySpan<char> sha256)
    {
        w.WriteStartObject();
        w.WriteNumber("index", index);
        w.WriteString("fileName", fileName);
        w.WriteNumber("firstSourceLine", first);
        w.WriteNumber("lastSourceLine", last);
        w.WriteNumber("blockCount", blocks);
        w.WriteNumber("motionBlockCount", motion);
        w.WriteNumber("byteSize", bytes);
        w.WriteNumber("estimatedWords", words);
        w.WriteString("sha256", sha256);
        w.WriteEndObject();
    }

    /// <summary>The chunk that carries a source line, or null when the line lies outside every chunk.</summary>
    public ChunkInfo? ChunkOfLine(int sourceLine)
    {
        // Chunks are in source order, so a binary search on the first line finds it.
        int lo = 0, hi = Chunks.Count - 1;
        while (lo <= hi)
        {
            var mid = (lo + hi) / 2;
            var c = Chunks[mid];
            if (sourceLine < c.FirstSourceLine)
            {
                hi = mid - 1;
            }
            else if (sourceLine > c.LastSourceLine)
            {
                lo = mid + 1;
            }
            else
            {
                return c;
            }
        }

        return null;
    }
}

/// <summary>
/// Source-generated serializer for <c>manifest.json</c>: no reflection, so the CLI can be published with Native AOT.
/// Camel-case names and camel-case enum strings, as the reflection serializer wrote them before.
/// </summary>
[JsonSourceGenerationOptions(
    WriteIndented = true,
    PropertyNamingPolicy = JsonKnownNamingPolicy.CamelCase,
    Converters = [typeof(CamelCaseEnumConverter<TrackingPlacement>), typeof(CamelCaseEnumConverter<FeedMode>)])]
[JsonSerializable(typeof(ChunkManifest))]
[JsonSerializable(typeof(ChunkShape))]
internal sealed partial class ChunkManifestJsonContext : JsonSerializerContext;

/// <summary>An enum written as its camel-case name (the generic converter is the AOT-safe one).</summary>
internal sealed class CamelCaseEnumConverter<TEnum> : JsonStringEnumConverter<TEnum>
    where TEnum : struct, Enum
{
    public CamelCaseEnumConverter()
        : base(JsonNamingPolicy.CamelCase)
    {
    }
}
