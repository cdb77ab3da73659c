using System.Text.Json;
using System.Text.Json.Serialization;
using PmacStream.Streaming;

namespace PmacStream.Hmi;

/// <summary>What the HMI records about a job beside its chunk files, so it can resume after the host stopped.</summary>
/// <param name="JobId">Job id (start time in Unix milliseconds).</param>
/// <param name="SourcePath">The program.</param>
/// <param name="SourceSha256">The program's SHA-256 when it was split (a changed file is refused).</param>
/// <param name="ChunkFolder">Folder of the manifest and chunk files.</param>
/// <param name="Strategy">Strategy name.</param>
/// <param name="Checkpoint">The session's last checkpoint.</param>
public sealed record HmiJobRecord(long JobId, string SourcePath, string SourceSha256, string ChunkFolder, string Strategy, Checkpoint Checkpoint);

/// <summary>
/// The session's checkpoint sink for the HMI: <c>NAME.hmi-job.json</c> beside the program (not in the chunk folder,
/// which the splitter replaces only when it holds nothing but a split), replaced atomically on
/// every checkpoint (written to a temporary file, flushed to disk for durable ones, then renamed), so a crash at
/// any moment leaves either the previous or the new checkpoint, never a torn one.
/// </summary>
public sealed class HmiJobJournal : ICheckpointSink
{
    /// <summary>Suffix of the journal's file name (after the program's name without extension).</summary>
    public const string Suffix = ".hmi-job.json";

    private static readonly JsonSerializerOptions Json = new()
    {
        WriteIndented = true,
        PropertyNamingPolicy = JsonNamingPolicy.CamelCase,
        Converters = { new JsonStringEnumConverter(JsonNamingPolicy.CamelCase) },
    };

    private readonly string _path;
    private readonly HmiJobRecord _template;

    /// <summary>Starts a journal for a new job of <paramref name="sourcePath"/>.</summary>
    public HmiJobJournal(long jobId, string sourcePath, string sourceSha256, string chunkFolder, string strategy)
    {
        _path = PathFor(sourcePath);
        _template = new HmiJobRecord(jobId, sourcePath, sourceSha256, chunkFolder, strategy,
            new Checkpoint(0, 1, new StreamPosition(1, 0), true, 0, SessionState.Idle, DateTimeOffset.UtcNow));
    }

    /// <summary>The last record written (or the empty one).</summary>
    public HmiJobRecord Current { get; private set; } = null!;

    /// <inheritdoc />
    public void Save(Checkpoint checkpoint, bool durable)
    {
        Current = _template with { Checkpoint = checkpoint };
        var temp = _path + ".tmp";
        using (var s = new FileStream(temp, FileMode.Create, FileAccess.Write, FileShare.None, 4096))
        {
            JsonSerializer.Serialize(s, Current, Json);
            s.Flush(flushToDisk: durable);
        }

        File.Move(temp, _path, overwrite: true);
    }

    /// <summary>Where the journal of a program lives.</summary>
    public static string PathFor(string sourcePath)
    {
        var full = Path.GetFullPath(sourcePath);
        return Path.Combine(Path.GetDirectoryName(full)!, Path.GetFileNameWithoutExtension(full) + Suffix);
    }

    /// <summary>Reads the journal of a program, or null when there is none (or it cannot be read).</summary>
    public static HmiJobRecord? Read(string sourcePath)
    {
        var path = PathFor(sourcePath);
        if (!File.Exists(path))
        {
            return null;
        }

        try
        {
            using var s = File.OpenRead(path);
            return JsonSerializer.Deserialize<HmiJobRecord>(s, Json);
        }
        catch (JsonException)
        {
            return null;
        }
    }
}
