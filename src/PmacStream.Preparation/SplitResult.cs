using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>What a split produced.</summary>
/// <param name="Manifest">The manifest written as <c>manifest.json</c>.</param>
/// <param name="OutputDirectory">Full path of the folder holding the chunks and the manifest.</param>
/// <param name="Warnings">Lexical warnings met while splitting (counted, not fatal).</param>
public sealed record SplitResult(ChunkManifest Manifest, string OutputDirectory, int Warnings)
{
    /// <summary>Full path of <c>manifest.json</c>.</summary>
    public string ManifestPath => Path.Combine(OutputDirectory, ChunkManifest.FileName);

    /// <summary>Full path of every chunk file, in order.</summary>
    public IEnumerable<string> ChunkPaths => Manifest.Chunks.Select(c => Path.Combine(OutputDirectory, c.FileName));

    /// <summary>Size of the largest chunk file in bytes.</summary>
    public long LargestChunkBytes => Manifest.Chunks switch
    {
        ChunkTable table => table.LargestBytes, // no record and strings per chunk for a summary line
        { Count: 0 } => 0,
        var chunks => chunks.Max(c => c.ByteSize),
    };

    /// <summary>
    /// The codes the program uses that the controller cannot run yet, with the line of their first use: the chunks
    /// carry them, no library routine runs them, and a job gate must refuse the program (null when the split had no
    /// profile).
    /// </summary>
    public IReadOnlyDictionary<string, int>? NotYetCodes { get; init; }

    /// <summary>Source lines the splitter's fast lane (<see cref="AxisLine"/>) took (tests check the lane is used).</summary>
    internal int LaneLines { get; init; }

    /// <summary>Of <see cref="LaneLines"/>, those scanned straight in the read buffer.</summary>
    internal int BufferLaneLines { get; init; }
}

/// <summary>Progress of a running split.</summary>
/// <param name="BytesRead">Source bytes consumed.</param>
/// <param name="TotalBytes">Source size.</param>
/// <param name="Chunks">Chunk files written.</param>
/// <param name="Blocks">Source blocks emitted.</param>
public readonly record struct SplitProgress(long BytesRead, long TotalBytes, int Chunks, int Blocks)
{
    /// <summary>Fraction done, 0..1.</summary>
    public double Fraction => TotalBytes <= 0 ? 1.0 : (double)BytesRead / TotalBytes;
}

/// <summary>
/// The program cannot be split: it has errors (and force was off), or a block cannot fit a chunk. Nothing was
/// written. <see cref="Diagnostics"/> lists the findings (at most the configured number); <see cref="ErrorCount"/> counts all.
/// </summary>
public sealed class SplitException : Exception
{
    /// <summary>Creates the exception.</summary>
    public SplitException(string message, IReadOnlyList<Diagnostic> diagnostics, int errorCount)
        : base(message)
    {
        Diagnostics = diagnostics;
        ErrorCount = errorCount;
    }

    /// <summary>The findings that stopped the split (capped).</summary>
    public IReadOnlyList<Diagnostic> Diagnostics { get; }

    /// <summary>Total number of errors found.</summary>
    public int ErrorCount { get; }

    /// <summary>True when the checker (<see cref="SplitOptions.CheckProfile"/>) found the errors in the same pass.</summary>
    public bool FromChecker { get; init; }
}
