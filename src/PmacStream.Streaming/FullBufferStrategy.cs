using System.Globalization;
using PmacStream.Pmac;

namespace PmacStream.Streaming;

/// <summary>
/// Keeps the rotary buffer full, so that the motion never starves on a real network (issue 28). Over Ethernet every
/// request waits for its reply, so a lost packet gets no duplicate ACKs and waits for TCP's retransmission timeout
/// (200 ms or more on Linux, doubled on a second loss): the chunk method's window leaves ~80 ms of motion ahead when
/// the next chunk goes, and such a stall starves it. This strategy instead tops the buffer up on every tick on which
/// a slice of it is free (as soon as there is room, never waiting for a window), in batches of whole lines, so the lead
/// is always what the buffer holds; the job service defines the buffer as large as the controller's memory allows
/// (<c>RunSettings.FullBufferWords</c>, docs/turbo-pmac-timing.md). It measures the link (the longest
/// single request, a retransmission stall) and the lead, and says once when the buffer at full is less than twice
/// that stall: then only a larger buffer (<c>--buffer-words</c>, extended memory) helps.
/// </summary>
public sealed class FullBufferStrategy : IStreamingStrategy
{
    /// <summary>ERR006, "no room in buffer for command": the controller's rotary buffer is full.</summary>
    private const int NoRoomError = 6;

    private double _warnedStall;

    // Controller words per estimated word. The per-line estimate counts a value a word; the controller's own count
    // can be higher (an M0==n assignment, F(P500)), and this strategy is the only one that fills the buffer to the
    // brim, so the first "no room" teaches it the real capacity in estimated words.
    private double _scale = 1;

    /// <inheritdoc />
    public string Name => "full";

    /// <summary>The lead (seconds of motion ahead) after the last tick's send.</summary>
    public double LeadSeconds { get; private set; }

    /// <summary>The smallest lead seen once the buffer was first filled (seconds); infinity before.</summary>
    public double WorstLeadSeconds { get; private set; } = double.PositiveInfinity;

    /// <summary>
    /// One batch within <paramref name="free"/> words. With several packets in flight the words are the controller's
    /// count (the session's buffer model charges <see cref="ControllerWords"/>) and a batch carries at most
    /// <see cref="StreamingOptions.WordsInFlight"/>: the credit is what the controller last reported free, less the
    /// words in flight, so <c>ERR006</c> cannot leave later packets stored behind a gap.
    /// </summary>
    private static Task SendAsync(StreamingContext context, int free, CancellationToken cancellationToken)
    {
        var o = context.Options;
        return context.PacketsInFlight > 1
            ? context.SendLinesPipelinedAsync(o.FullMaxBatchLines, Math.Min(free, o.WordsInFlight), context.PacketsInFlight, cancellationToken)
            : context.SendLinesAsync(o.FullMaxBatchLines, free, oneByOne: false, cancellationToken);
    }

    /// <inheritdoc />
    public void Reset()
    {
        // Nothing per window: every tick decides from the buffer's occupancy alone.
    }

    /// <inheritdoc />
    public async Task TickAsync(StreamingContext context, CancellationToken cancellationToken)
    {
        ArgumentNullException.ThrowIfNull(context);
        if (context.AllSent)
        {
            return;
        }

        // A slice of the buffer (1/32) free is worth a batch: smaller top-ups would cost a round trip per few lines.
        // The words kept free beyond the session's margin (1/64) absorb the per-line estimate's error, since this
        // strategy runs the buffer near full where the others never go.
        var room = context.BufferWords - context.Options.SafetyWords;
        var used = room - context.FreeWords;
        var free = (int)(room / _scale) - (context.BufferWords / 64) - used;
        if (free >= Math.Max(64, context.BufferWords / 32))
        {
            try
            {
                await SendAsync(context, free, cancellationToken).ConfigureAwait(false);
            }
            catch (PmacErrorException e) when (e.Number == NoRoomError && e.LineInBatch is not null && e.LinesStoredAfterGap == 0 && room - context.FreeWords > context.BufferWords / 4)
            {
                // The lines before the refused one are stored and the position stands exactly before it (the
                // sender's rule). The model still counts the lines executed while the batch went out (M0 was not
                // read meanwhile): PR, the lines ahead, frees those, so what is left is what the full buffer holds.
                await context.ReadLinesAheadAsync(cancellationToken).ConfigureAwait(false);
                var full = Math.Max(1, room - context.FreeWords);
                _scale = Math.Max(_scale, 1.03 * room / full);
                context.Note(string.Create(CultureInfo.InvariantCulture,
                    $"the rotary buffer was full at {full} estimated words of {room}: filling it to {room / _scale:0} from now on"));
            }
        }

        LeadSeconds = context.LeadSeconds();
        if (context.TrackedLine > 0 && context.MovesAhead > 0)
        {
            WorstLeadSeconds = Math.Min(WorstLeadSeconds, LeadSeconds);
        }

        var stall = context.WorstRoundTripSeconds;
        if (context.FreeWords <= context.BufferWords / 16 && LeadSeconds > 0 && LeadSeconds < 2 * stall && stall > 1.5 * _warnedStall)
        {
            _warnedStall = stall;
            context.Note(string.Create(CultureInfo.InvariantCulture,
                $"the full rotary buffer holds {LeadSeconds:0.00} s of motion, less than twice the worst link stall measured ({stall:0.000} s): define a larger buffer (--buffer-words) or slow the feed"));
        }
    }
}
