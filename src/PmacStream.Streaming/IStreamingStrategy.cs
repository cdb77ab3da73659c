namespace PmacStream.Streaming;

/// <summary>
/// How the rotary buffer is fed. A strategy runs inside <see cref="StreamingSession.TickAsync"/> after the session
/// has read the tracking variable; it decides whether and what to send through the <see cref="StreamingContext"/>,
/// which keeps the order, the buffer-open rule and the checkpoint.
/// </summary>
public interface IStreamingStrategy
{
    /// <summary>The strategy's name (<c>full</c>, <c>chunk</c>, <c>pr</c>, <c>adaptive</c>).</summary>
    string Name { get; }

    /// <summary>One timer tick: send what the strategy wants sent now.</summary>
    Task TickAsync(StreamingContext context, CancellationToken cancellationToken);

    /// <summary>Forget per-window state after a fault or resume (the session repositions).</summary>
    void Reset();
}

/// <summary>Creates strategies by kind.</summary>
public static class StreamingStrategies
{
    /// <summary>The strategy for a kind.</summary>
    public static IStreamingStrategy Create(StrategyKind kind) => kind switch
    {
        StrategyKind.Chunk => new ChunkStrategy(),
        StrategyKind.Pr => new PrStrategy(),
        StrategyKind.Adaptive => new AdaptiveStrategy(),
        StrategyKind.Full => new FullBufferStrategy(),
        _ => throw new ArgumentOutOfRangeException(nameof(kind)),
    };

    /// <summary>Parses <c>full</c>, <c>chunk</c>, <c>pr</c> or <c>adaptive</c>.</summary>
    public static StrategyKind Parse(string text) => text.Trim().ToLowerInvariant() switch
    {
        "chunk" => StrategyKind.Chunk,
        "pr" => StrategyKind.Pr,
        "adaptive" => StrategyKind.Adaptive,
        "full" => StrategyKind.Full,
        _ => throw new ArgumentException($"unknown strategy '{text}': expected full, chunk, pr or adaptive", nameof(text)),
    };
}

/// <summary>
/// The chunk method: every tick read M0; when M0 lies in the download window of the current chunk (a fraction of
/// it, 0.6-0.7 by default) download the next chunk file exactly once, guarded by a bool flag that is reset when
/// execution enters the next chunk. Never early; never without room; once late (with a log) when the window was missed.
/// A job that starts (or resumes) inside a chunk past its window did not miss it: execution joined the chunk there,
/// and the next chunk goes at once, not late.
/// </summary>
public sealed class ChunkStrategy : IStreamingStrategy
{
    private bool _downloaded;
    private int _flagChunk;
    private bool _waitLogged;
    private bool _joined;
    private bool _joinedPastWindow;

    /// <inheritdoc />
    public string Name => "chunk";

    /// <summary>The download-once flag (true once the next chunk was sent in this chunk's window).</summary>
    public bool DownloadFlag => _downloaded;

    /// <inheritdoc />
    public void Reset()
    {
        _downloaded = false;
        _flagChunk = 0;
        _waitLogged = false;
        _joined = false;
        _joinedPastWindow = false;
    }

    /// <inheritdoc />
    public async Task TickAsync(StreamingContext context, CancellationToken cancellationToken)
    {
        if (context.AllSent)
        {
            return;
        }

        var current = context.CurrentChunk;
        if (current != _flagChunk)
        {
            // Execution entered another chunk: the next chunk may be downloaded once again.
            _joinedPastWindow = false;
            _flagChunk = current;
            _downloaded = false;
            _waitLogged = false;
        }

        var f = context.ChunkFraction;
        if (!_joined && context.TrackedLine > 0)
        {
            // The first block the job executes (a preamble before it tracks as 0): where it joined its chunk.
            _joined = true;
            _joinedPastWindow = f > context.Options.WindowEnd;
        }

        var next = context.Next;
        if (next.Line > 0 || next.Chunk <= current)
        {
            // The rest of a chunk that broke off, or a chunk execution already needs: send as soon as it fits.
            if (await context.HasRoomForRestOfChunkAsync(cancellationToken).ConfigureAwait(false))
            {
                await context.DownloadNextChunkAsync(late: true, cancellationToken).ConfigureAwait(false);
            }

            return;
        }

        if (next.Chunk > current + 1 || _downloaded)
        {
            return;
        }

        if (f < context.Options.WindowStart)
        {
            return;
        }

        var late = f > context.Options.WindowEnd && !_joinedPastWindow;
        if (!await context.HasRoomForRestOfChunkAsync(cancellationToken).ConfigureAwait(false))
        {
            if (!_waitLogged)
            {
                _waitLogged = true;
                context.Note($"chunk {next.Chunk} waits for room in the rotary buffer");
            }

            return;
        }

        if (_joinedPastWindow)
        {
            context.Note($"execution joined chunk {current} at line {context.TrackedLine}, past its download window: chunk {next.Chunk} goes at once");
        }

        await context.DownloadNextChunkAsync(late, cancellationToken).ConfigureAwait(false);
        _downloaded = true;
    }
}

/// <summary>The traditional method: poll <c>PR</c> every tick and top the buffer up line by line.</summary>
public sealed class PrStrategy : IStreamingStrategy
{
    /// <inheritdoc />
    public string Name => "pr";

    /// <inheritdoc />
    public void Reset()
    {
    }

    /// <inheritdoc />
    public async Task TickAsync(StreamingContext context, CancellationToken cancellationToken)
    {
        if (context.AllSent)
        {
            return;
        }

        var ahead = await context.ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
        var want = context.Options.PrTargetLines - ahead;
        if (want <= 0)
        {
            return;
        }

        await context.SendLinesAsync(want, context.FreeWords, oneByOne: true, cancellationToken).ConfigureAwait(false);
    }
}

/// <summary>
/// Keeps a lead in seconds of motion: the target is the larger of a floor and four times (tick period + measured
/// round trip), so a slow link or slow timer is covered; the seconds come from the interpreter's move times (or the
/// measured block rate) scaled by the feed override, and the buffer's words bound it. It tracks occupancy from M0
/// alone, so a tick costs one query.
/// </summary>
public sealed class AdaptiveStrategy : IStreamingStrategy
{
    /// <inheritdoc />
    public string Name => "adaptive";

    /// <summary>The lead (seconds) aimed at on the last tick.</summary>
    public double TargetLeadSeconds { get; private set; }

    /// <inheritdoc />
    public void Reset()
    {
    }

    /// <inheritdoc />
    public async Task TickAsync(StreamingContext context, CancellationToken cancellationToken)
    {
        if (context.AllSent)
        {
            return;
        }

        var floor = context.Options.AdaptiveMinLeadSeconds;
        var cover = 4 * (context.Options.TickPeriod.TotalSeconds + context.RoundTripSeconds);
        TargetLeadSeconds = Math.Max(floor, cover);
        var lead = context.LeadSeconds();
        if (lead >= TargetLeadSeconds)
        {
            return;
        }

        // Fill to twice the target so a batch covers several ticks (fewer, larger writes).
        await context.SendUntilLeadAsync(2 * TargetLeadSeconds, context.Options.AdaptiveMaxBatchLines, cancellationToken).ConfigureAwait(false);
    }
}
