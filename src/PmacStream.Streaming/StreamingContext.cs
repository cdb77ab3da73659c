namespace PmacStream.Streaming;

/// <summary>What a strategy may see and do inside a tick; the session keeps order, the open-buffer rule and checkpoints.</summary>
public sealed class StreamingContext
{
    private readonly StreamingSession _session;
    private readonly ProgramSender _sender;
    private readonly RotaryBufferModel _buffer;
    private readonly ControllerChannel _channel;
    private readonly ExecutionPace _pace;
    private readonly Func<int, int, double> _leadThrough;

    internal StreamingContext(StreamingSession session, ProgramSender sender, RotaryBufferModel buffer, ControllerChannel channel, ExecutionPace pace)
    {
        _session = session;
        _sender = sender;
        _buffer = buffer;
        _channel = channel;
        _pace = pace;
        _leadThrough = (line, moves) => _pace.LeadSeconds(TrackedLine, line, moves);
    }

    /// <summary>The session's options.</summary>
    public StreamingOptions Options => _session.Options;

    /// <summary>The program.</summary>
    public ChunkedProgram Program => _session.Program;

    /// <summary>The tracking variable read this tick.</summary>
    public int TrackedLine => _session.Tracked;

    /// <summary>The chunk executing (from the tracking variable).</summary>
    public int CurrentChunk => _session.CurrentChunk;

    /// <summary>Where M0 lies in the current chunk, as a fraction of its source lines (0.65 = line 650 of 1000).</summary>
    public double ChunkFraction => Program.FractionOfChunk(CurrentChunk, TrackedLine);

    /// <summary>The next program line to send.</summary>
    public StreamPosition Next => _sender.Next;

    /// <summary>True when every line was sent.</summary>
    public bool AllSent => _sender.AllSent;

    /// <summary>Measured round trip of a query, seconds (smoothed).</summary>
    public double RoundTripSeconds => _channel.RoundTripSeconds;

    /// <summary>The longest single query or batch so far, seconds (a retransmission stall shows here).</summary>
    public double WorstRoundTripSeconds => _channel.WorstRoundTripSeconds;

    /// <summary>WRITEBUFFER packets the full strategy may keep in flight now (1: one at a time).</summary>
    public int PacketsInFlight => _session.PacketsInFlight;

    /// <summary>The rotary buffer's size in words, as defined.</summary>
    public int BufferWords => _buffer.BufferWords;

    /// <summary>Moves sent and not yet reached by the tracking variable.</summary>
    public int MovesAhead => _buffer.MovesAhead;

    /// <summary>Estimated free words in the rotary buffer.</summary>
    public int FreeWords => _buffer.FreeWords;

    /// <summary>Reads <c>PR</c> (lines ahead) and updates the occupancy estimate.</summary>
    public Task<int> ReadLinesAheadAsync(CancellationToken cancellationToken) => _session.ReadLinesAheadAsync(cancellationToken);

    /// <summary>Reads <c>PR</c>; true when the rest of the next chunk fits in the free words.</summary>
    public async Task<bool> HasRoomForRestOfChunkAsync(CancellationToken cancellationToken)
    {
        var need = _sender.WordsOfRestOfChunk();
        await ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        return need <= _buffer.FreeWords;
    }

    /// <summary>Downloads the next chunk (the whole file through <c>Download</c>, or the rest of a broken-off one).</summary>
    public Task DownloadNextChunkAsync(bool late, CancellationToken cancellationToken) => _session.DownloadNextChunkAsync(late, cancellationToken);

    /// <summary>Sends up to <paramref name="maxLines"/> lines within <paramref name="maxWords"/> words, in one batch or line by line.</summary>
    public Task SendLinesAsync(int maxLines, int maxWords, bool oneByOne, CancellationToken cancellationToken) => _sender.SendLinesAsync(maxLines, maxWords, oneByOne, cancellationToken);

    /// <summary>
    /// Sends up to <paramref name="maxLines"/> lines within <paramref name="maxWords"/> words in one batch, with up to
    /// <paramref name="packetsInFlight"/> packets in flight; the words are the buffer model's (the controller's count
    /// when the session pipelines).
    /// </summary>
    public Task SendLinesPipelinedAsync(int maxLines, int maxWords, int packetsInFlight, CancellationToken cancellationToken) =>
        _sender.SendLinesAsync(maxLines, maxWords, oneByOne: false, cancellationToken, packetsInFlight);

    /// <summary>Seconds of motion in the buffer ahead of the executing block (move times, or the measured block rate).</summary>
    public double LeadSeconds() => _pace.LeadSeconds(TrackedLine, _buffer.LastSentLine, _buffer.MovesAhead);

    /// <summary>Sends lines until the lead reaches <paramref name="targetSeconds"/>, bounded by free words and <paramref name="maxLines"/>.</summary>
    public Task SendUntilLeadAsync(double targetSeconds, int maxLines, CancellationToken cancellationToken) =>
        _sender.SendUntilLeadAsync(targetSeconds, maxLines, _leadThrough, cancellationToken);

    /// <summary>Logs a note and shows it in the status message.</summary>
    public void Note(string message) => _session.Note(message);
}
