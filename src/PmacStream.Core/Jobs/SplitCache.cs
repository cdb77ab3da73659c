using System.Text.Json;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>
/// Reuses an earlier split only when it is the split these options would write now: the same source bytes
/// (SHA-256), the same <see cref="ChunkShape"/> (every option that changes chunk bytes, compared as one record), the same check (profile name and digest; a forced split
/// only when forcing again), and every chunk file still there. Anything else splits again.
/// </summary>
public static class SplitCache
{
    /// <summary>The split in <paramref name="outDir"/> when it matches, else null.</summary>
    public static ChunkedProgram? TryOpen(string sourcePath, string outDir, SplitOptions options, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(options);
        var manifestPath = Path.Combine(outDir, ChunkManifest.FileName);
        if (!File.Exists(manifestPath))
        {
            return null;
        }

        ChunkManifest manifest;
        try
        {
            manifest = ChunkManifest.Load(manifestPath);
        }
        catch (Exception e) when (e is JsonException or InvalidDataException)
        {
            return null; // a damaged manifest: split again
        }

        if (!SameOptions(manifest, options)
            || manifest.Chunks.Count == 0
            || !manifest.Chunks.All(c => File.Exists(Path.Combine(outDir, c.FileName)))
            || !FileHash.SameDigest(manifest.SourceSha256, FileHash.Sha256Hex(sourcePath, cancellationToken)))
        {
            return null;
        }

        return ChunkedProgram.FromManifest(manifest, Path.GetFullPath(outDir));
    }

    /// <summary>
    /// True when <paramref name="manifest"/> was written with the chunk shape of <paramref name="options"/> (the whole
    /// record, <c>==</c>) and checked as they ask. A manifest of an older version has no shape: never the same.
    /// </summary>
    public static bool SameOptions(ChunkManifest manifest, SplitOptions options)
    {
        ArgumentNullException.ThrowIfNull(manifest);
        ArgumentNullException.ThrowIfNull(options);
        // Forcing takes a checked split of the same bytes too: it is the same split.
        var checkedAsAsked = options.CheckedProfile is not { } profile || manifest.CheckedProfile == profile;
        return checkedAsAsked && manifest.Shape == options.ResolvedShape;
    }
}
