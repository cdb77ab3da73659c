using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// Recovery from a download that broke off mid-way (how much of it arrived is unknown): sending waits until the
/// rotary buffer has drained, then resumes after what the controller got. Drained means every line calculated
/// (<c>PR</c> 0) and every calculated move done, with the tracking variable standing still; then M0 names the last move
/// that arrived and the line probe the last line of any kind, and sending continues after the later of the two.
/// </summary>
internal sealed class BufferDrain
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    private int _stableReads;
    private int _lastTracked = -1;

    /// <summary>True while sending waits for the buffer to drain.</summary>
    public bool Draining { get; private set; }

    /// <summary>Starts waiting when the position is not exact (a download broke off); otherwise sending goes on at once.</summary>
    public void Begin(bool positionExact)
    {
        Draining = !positionExact;
        _stableReads = 0;
        _lastTracked = -1;
    }

    /// <summary>
    /// One tick while draining, after <c>PR</c> read <paramref name="linesAhead"/>: asks for the motion status and,
    /// once drained, the line probe. Returns where sending resumes (and stops waiting), or null while the buffer drains.
    /// </summary>
    public async Task<StreamPosition?> StepAsync(ControllerQueries queries, ChunkedProgram program, int linesAhead, int trackedLine, StreamPosition next, CancellationToken cancellationToken)
    {
        // With lookahead M0 lags the calculated lines until motion stops, so "not moving" must hold as well as PR 0.
        var still = linesAhead == 0 && await queries.MotionStoppedAsync(cancellationToken).ConfigureAwait(false);
        if (!Observe(still, trackedLine, queries.StatusUnknown))
        {
            return null;
        }

        long? probe = program.LineProbeVariable is { } variable ? await queries.ProbeAsync(variable, cancellationToken).ConfigureAwait(false) : null;
        Draining = false;
        return ResumePosition(program, trackedLine, next, probe);
    }

    /// <summary>
    /// One reading: <paramref name="still"/> when <c>PR</c> is 0 and motion stopped. True for a still reading with M0
    /// where the reading before left it; when the controller's status word could not be read ("still" then rests on
    /// <c>PR</c> alone), only for the fifth such reading in a row.
    /// </summary>
    public bool Observe(bool still, int trackedLine, bool statusUnknown)
    {
        _stableReads = still && trackedLine == _lastTracked ? _stableReads + 1 : 0;
        _lastTracked = trackedLine;
        return _stableReads >= (statusUnknown ? 5 : 1);
    }

    /// <summary>
    /// Where sending resumes once drained: after the block of <paramref name="trackedLine"/> and, with a line probe,
    /// after the line whose probe value the controller holds, whichever is later; never before <paramref name="next"/>.
    /// A probe value that points past moves M0 did not reach is not this job's (a program or PLC wrote the variable)
    /// and is ignored, so nothing is skipped on its word.
    /// </summary>
    public static StreamPosition ResumePosition(ChunkedProgram program, int trackedLine, StreamPosition next, long? probeValue)
    {
        ArgumentNullException.ThrowIfNull(program);
        var after = program.PositionAfterBlock(trackedLine) ?? next;
        if (Compare(after, next) > 0)
        {
            next = after;
        }

        if (probeValue is not { } value || program.PositionAfterProbe(value) is not { } afterProbe || Compare(afterProbe, next) <= 0)
        {
            return next;
        }

        // Only lines without a move can lie between M0's block and the probe's line (a move that arrived would have
        // moved M0; when M0 lags one move, one move may).
        var allowed = program.ProbesEveryLine ? 1 : 0;
        if (MovesBetween(program, after, afterProbe, allowed) <= allowed)
        {
            Log.Information("line probe {Probe}={Value}: the controller got lines up to {Position}", program.LineProbeVariable, value, afterProbe);
            return afterProbe;
        }

        Log.Warning("line probe {Probe}={Value} points past moves M0={Tracked} did not reach: ignored (is {Probe} used elsewhere?)", program.LineProbeVariable, value, trackedLine, program.LineProbeVariable);
        return next;
    }

    /// <summary>Orders positions: chunk, then line.</summary>
    public static int Compare(StreamPosition a, StreamPosition b) =>
        a.Chunk != b.Chunk ? a.Chunk.CompareTo(b.Chunk) : a.Line.CompareTo(b.Line);

    /// <summary>Tracked (move) lines from <paramref name="from"/> up to, not including, <paramref name="to"/>; stops counting past <paramref name="limit"/>.</summary>
    private static int MovesBetween(ChunkedProgram program, StreamPosition from, StreamPosition to, int limit)
    {
        var n = 0;
        for (var p = program.Normalize(from); Compare(p, to) < 0 && p.Chunk <= program.TotalChunks; p = program.Normalize(new StreamPosition(p.Chunk, p.Line + 1)))
        {
            if (program.Body(p.Chunk)[p.Line].TrackedLine > 0 && ++n > limit)
            {
                break;
            }
        }

        return n;
    }
}
