namespace PmacStream.Preparation;

/// <summary>
/// The defaults of what preparation writes into a chunk: its size and the controller variables its lines name. They
/// live with the layer that writes them; the job service's <c>RunSettings</c> starts from them.
/// </summary>
public static class PreparationDefaults
{
    /// <summary>Source blocks per chunk: 1000-line chunk files.</summary>
    public const int BlocksPerChunk = 1000;

    /// <summary>Words one chunk may take: 6400 words x 8 bytes is a ~50 KB chunk file, what one motion program buffer holds.</summary>
    public const int ChunkWords = 6400;

    /// <summary>The M-variable the synchronous tracking assignment writes (<c>M0==line</c>).</summary>
    public const string TrackVariable = SyncAssignment.DefaultVariable;

    /// <summary>The live feed variable moves read (<c>F(P500)</c>).</summary>
    public const string FeedVariable = "P500";

    /// <summary>The optional-stop switch the library's <c>M01</c> routine reads (1: stop there, 0: go on).</summary>
    public const string OptionalStopVariable = "P502";
}
