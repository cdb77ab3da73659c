using System.Data.Common;
using System.Security.Cryptography;
using System.Text;
using System.Text.Json;
using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>A preparation stored with a revision: its chunk files and manifest, made from the inputs its key names.</summary>
/// <param name="Id">Row id.</param>
/// <param name="ProgramId">The revision.</param>
/// <param name="InputsKey">SHA-256 (hex) of <paramref name="Inputs"/>.</param>
/// <param name="Inputs">Every input the split read, as text (the source, chunk shape, profile identity, force, splitter version).</param>
/// <param name="Manifest">The manifest as the preparing station wrote it (its source path is that station's).</param>
public sealed record StoredPreparation(long Id, long ProgramId, string InputsKey, string Inputs, string Manifest)
{
    /// <summary>The key of a preparation's inputs: SHA-256 of their text, lower-case hex.</summary>
    public static string KeyOf(string inputs) => Convert.ToHexStringLower(SHA256.HashData(Encoding.UTF8.GetBytes(inputs)));

    /// <summary>The stored manifest, read.</summary>
    public ChunkManifest ReadManifest() =>
        JsonSerializer.Deserialize(Manifest, ChunkManifestJsonContext.Default.ChunkManifest) ?? throw new InvalidDataException($"preparation {Id}: empty manifest");
}

/// <summary>
/// The chunk files of preparations on either engine: written into a folder from the store (another station, or a
/// folder that was removed), and read from a split folder into the store, a file per row so memory stays one chunk.
/// </summary>
public static class PreparationFiles
{
    /// <summary>The statement that lists a preparation's files in order.</summary>
    internal const string SelectFiles = "SELECT name, data FROM preparation_files WHERE preparation_id = {0} ORDER BY seq";

    /// <summary>
    /// True when <paramref name="folder"/> already holds <paramref name="prepared"/>'s chunks: its manifest names the
    /// same chunks (by SHA-256) and every chunk file is there with exactly the stored bytes (its SHA-256: a file edited
    /// in place, even to the same size, is not held, and is written again from the store). Its source path may be another's.
    /// </summary>
    public static bool Holds(string folder, StoredPreparation prepared)
    {
        ArgumentNullException.ThrowIfNull(prepared);
        var path = Path.Combine(folder, ChunkManifest.FileName);
        if (!File.Exists(path))
        {
            return false;
        }

        ChunkManifest local;
        try
        {
            local = ChunkManifest.Load(path);
        }
        catch (Exception e) when (e is JsonException or InvalidDataException or IOException)
        {
            return false;
        }

        var stored = prepared.ReadManifest();
        return local.SourceSha256 == stored.SourceSha256 && local.Shape == stored.Shape && local.Chunks.Count == stored.Chunks.Count
            && local.Chunks.Zip(stored.Chunks).All(p => p.First.Sha256 == p.Second.Sha256 && p.First.FileName == p.Second.FileName)
            && stored.Chunks.All(c => SameBytes(Path.Combine(folder, c.FileName), c));
    }

    private static bool SameBytes(string path, ChunkInfo chunk)
    {
        if (new FileInfo(path) is not { Exists: true } f || f.Length != chunk.ByteSize)
        {
            return false;
        }

        using var stream = File.OpenRead(path);
        return string.Equals(Convert.ToHexStringLower(SHA256.HashData(stream)), chunk.Sha256, StringComparison.OrdinalIgnoreCase);
    }

    /// <summary>
    /// Writes the preparation's chunk files from <paramref name="files"/> (name, bytes, in order) into
    /// <paramref name="folder"/>, checking each against the manifest's SHA-256, then its manifest with
    /// <paramref name="sourcePath"/> as the source (this station's copy of the revision). The manifest goes last, so a
    /// folder left half-written is never taken for a split.
    /// </summary>
    public static ChunkManifest Write(StoredPreparation prepared, IEnumerable<(string Name, byte[] Data)> files, string folder, string sourcePath)
    {
        ArgumentNullException.ThrowIfNull(prepared);
        ArgumentNullException.ThrowIfNull(files);
        Directory.CreateDirectory(folder);
        var manifestPath = Path.Combine(folder, ChunkManifest.FileName);
        File.Delete(manifestPath);
        var manifest = prepared.ReadManifest() with { SourcePath = sourcePath };
        var expected = manifest.Chunks.ToDictionary(c => c.FileName, c => c.Sha256, StringComparer.Ordinal);
        var written = 0;
        foreach (var (name, data) in files)
        {
            if (!expected.TryGetValue(name, out var sha) || !string.Equals(sha, Convert.ToHexStringLower(SHA256.HashData(data)), StringComparison.OrdinalIgnoreCase))
            {
                throw new InvalidDataException($"preparation {prepared.Id}: stored chunk {name} is not the manifest's; the store is damaged");
            }

            File.WriteAllBytes(Path.Combine(folder, name), data);
            written++;
        }

        if (written != expected.Count)
        {
            throw new InvalidDataException($"preparation {prepared.Id}: {written} chunk files stored of the manifest's {expected.Count}; the store is damaged");
        }

        manifest.Save(manifestPath);
        return manifest;
    }

    /// <summary>The chunk files of a split, in the manifest's order, one at a time.</summary>
    public static IEnumerable<(string Name, byte[] Data)> Read(string folder, ChunkManifest manifest)
    {
        ArgumentNullException.ThrowIfNull(manifest);
        foreach (var c in manifest.Chunks)
        {
            yield return (c.FileName, File.ReadAllBytes(Path.Combine(folder, c.FileName)));
        }
    }

    /// <summary>Reads a preparation row (<c>id, program_id, inputs_key, inputs, manifest</c>).</summary>
    internal static StoredPreparation ReadRow(DbDataReader r) => new(r.GetInt64(0), r.GetInt64(1), r.GetString(2), r.GetString(3), r.GetString(4));
}

/// <summary>What a preparation read, named for its key.</summary>
public static class PreparationInputs
{
    /// <summary>
    /// Every input the split reads besides the source: the chunk shape (blocks and words per chunk, tracking, feed mode,
    /// tail ...), the machine profile it is checked and converted under (its identity: codes, tool lengths and radii, work
    /// offsets, as the machine's tool table left them), whether errors were forced past, and the splitter's version (a
    /// newer splitter may write other bytes). The rotary buffer's size is not among them: the chunk shape's words are.
    /// </summary>
    public static string Of(string sourceSha256, SplitOptions options)
    {
        ArgumentNullException.ThrowIfNull(options);
        var version = typeof(Splitter).Assembly.GetCustomAttributes(typeof(System.Reflection.AssemblyInformationalVersionAttribute), false)
            .OfType<System.Reflection.AssemblyInformationalVersionAttribute>().FirstOrDefault()?.InformationalVersion ?? "unknown";
        return string.Join('\n',
            "source " + sourceSha256.ToLowerInvariant(),
            "shape " + JsonSerializer.Serialize(options.ResolvedShape, ChunkManifestJsonContext.Default.ChunkShape).ReplaceLineEndings(" "),
            "profile " + (options.CheckProfile?.Identity ?? MachineProfile.Default.Identity),
            "force " + (options.AllowErrors ? "yes" : "no"),
            "splitter " + version);
    }
}
