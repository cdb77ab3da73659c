using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// A job's start on the controller, made atomic. It refuses while the coordinate system runs a program, prepares it
/// (the rotary buffer defined, M0 and the line probe reset, <c>&amp;n B0</c> before the first <c>OPEN ROT</c>), and
/// loads what must be in the buffer before the run command: the buffer cleared, the preamble, the first chunk.
/// Nothing runs before the run command, so until the load completed (<see cref="Loaded"/>) a recovery simply loads
/// it again.
/// </summary>
/// <param name="program">The program started.</param>
/// <param name="options">The session's settings (buffer definition, resets).</param>
/// <param name="cs">The coordinate system's commands.</param>
/// <param name="channel">The line to the controller.</param>
/// <param name="queries">The controller's status.</param>
/// <param name="sender">Sends the preamble and positions the program at the start.</param>
/// <param name="buffer">The buffer model, emptied by the load.</param>
/// <param name="checkpoint">Writes a durable checkpoint.</param>
/// <param name="downloadFirstChunk">Sends the chunk at the start position.</param>
internal sealed class StartSequence(ChunkedProgram program, StreamingOptions options, CoordinateSystemCommands cs, ControllerChannel channel,
    ControllerQueries queries, ProgramSender sender, RotaryBufferModel buffer, Action checkpoint, Func<CancellationToken, Task> downloadFirstChunk)
{
    private static readonly ILogger Logger = Log.ForContext<StartSequence>();
    private StreamPosition _startAt = new(1, 0);
    private List<ProgramLine>? _preamble;

    /// <summary>True once the buffer holds the whole start (or a resumed job's lines): a recovery need not load it again.</summary>
    public bool Loaded { get; set; }

    /// <summary>
    /// Throws <see cref="InvalidOperationException"/> when the coordinate system is running a program; sends only
    /// <c>CLOSE</c> and a status query.
    /// </summary>
    public async Task EnsureNotRunningAsync(CancellationToken cancellationToken)
    {
        await channel.OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        if (await queries.ProgramRunningAsync(cancellationToken).ConfigureAwait(false) == true
            && !await EndedCompletedJobAsync(cancellationToken).ConfigureAwait(false))
        {
            // Redefining the rotary buffer or sending B0 under a running program would break it off (a real PMAC
            // answers ERR001). Refuse before anything reaches a buffer.
            throw new InvalidOperationException($"{cs.Prefix} is running a program: stop it or let it finish, then start again");
        }
    }

    /// <summary>
    /// Ends the rotary program of the previous job on this controller when it only waits for lines after its end
    /// (<see cref="StreamingOptions.CompletedJobLine"/>): nothing ahead, no move, the tracking variable at that job's last
    /// line. True when it was ended; false (nothing sent) for any other running program.
    /// </summary>
    private async Task<bool> EndedCompletedJobAsync(CancellationToken cancellationToken)
    {
        if (options.CompletedJobLine is not { } line
            || await queries.LinesAheadAsync(cancellationToken).ConfigureAwait(false) != 0
            || !await queries.MotionStoppedAsync(cancellationToken).ConfigureAwait(false)
            || queries.StatusUnknown
            || await queries.TrackedLineAsync(cancellationToken).ConfigureAwait(false) != line)
        {
            return false;
        }

        Logger.Information("{Cs}: the previous job's rotary program waits for lines after its last line {Line}, with nothing ahead and no move: ended ({Abort})",
            cs.Prefix, line, cs.Abort);
        await channel.OnlineAsync(cs.Abort, cancellationToken).ConfigureAwait(false);
        return await queries.ProgramRunningAsync(cancellationToken).ConfigureAwait(false) != true;
    }

    /// <summary>Prepares the coordinate system: defines the rotary buffer (when asked), resets M0 and the line probe, points it at the rotary buffer.</summary>
    public async Task PrepareAsync(CancellationToken cancellationToken)
    {
        if (options.DefineBuffer)
        {
            await channel.OnlineAsync("DELETE GATHER", cancellationToken).ConfigureAwait(false);
            await channel.OnlineIgnoringErrorAsync(cs.DeleteRotary, cancellationToken).ConfigureAwait(false);
            var words = options.SizeBufferFromController ? await WordsFromControllerAsync(cancellationToken).ConfigureAwait(false) : options.BufferWords;
            await channel.OnlineAsync(cs.DefineRotary(words), cancellationToken).ConfigureAwait(false);
            buffer.Resize(words);
        }

        if (options.ResetTrackVariable)
        {
            await channel.OnlineAsync(program.Sync.ResetCommand, cancellationToken).ConfigureAwait(false);
        }

        if (program.LineProbeVariable is { } probe)
        {
            // A probe value left by an earlier job would read as lines of this one.
            await channel.OnlineAsync($"{probe}=0", cancellationToken).ConfigureAwait(false);
        }

        // B0 must precede the first OPEN ROT: inside an open buffer it would be a B-axis move.
        await channel.OnlineAsync(cs.PointAtRotary, cancellationToken).ConfigureAwait(false);
    }

    /// <summary>
    /// The rotary buffer's size from the controller's free memory: <c>SIZE</c> ("the amount of unused long words of
    /// memory available for buffers", PMAC Software Reference p. 286) less <see cref="StreamingOptions.MemoryReserveWords"/>
    /// (PLCs and programs loaded later), capped by <see cref="StreamingOptions.BufferWordsCap"/>. A controller that does
    /// not answer it (or answers a buffer open, a negative number) gets <see cref="StreamingOptions.BufferWords"/>.
    /// </summary>
    private async Task<int> WordsFromControllerAsync(CancellationToken cancellationToken)
    {
        string reply;
        try
        {
            reply = await channel.OnlineAsync("SIZE", cancellationToken).ConfigureAwait(false);
        }
        catch (PmacErrorException e)
        {
            Logger.Information("SIZE refused (ERR{Number:000}): the rotary buffer gets the setting's {Words} words", e.Number, options.BufferWords);
            return options.BufferWords;
        }

        if (!long.TryParse(reply.Trim(), System.Globalization.NumberStyles.Integer, System.Globalization.CultureInfo.InvariantCulture, out var free) || free <= 0)
        {
            Logger.Information("SIZE answered '{Reply}': the rotary buffer gets the setting's {Words} words", reply, options.BufferWords);
            return options.BufferWords;
        }

        var words = free - options.MemoryReserveWords;
        if (options.BufferWordsCap > 0)
        {
            words = Math.Min(words, options.BufferWordsCap);
        }

        var chosen = (int)Math.Clamp(words, 1, int.MaxValue);
        Logger.Information("SIZE: {Free} words of user memory free; the rotary buffer gets {Words} (reserve {Reserve}, cap {Cap})", free, chosen, options.MemoryReserveWords, options.BufferWordsCap > 0 ? options.BufferWordsCap : (object)"none");
        return chosen;
    }

    /// <summary>What <see cref="LoadAsync"/> loads: the program from <paramref name="start"/>, after <paramref name="preamble"/> (none when null or empty).</summary>
    public void Plan(StreamPosition start, IReadOnlyList<string>? preamble)
    {
        _startAt = start;
        _preamble = preamble is { Count: > 0 } ? preamble.Select(p => program.Classify(p) with { TrackedLine = 0 }).ToList() : null;
    }

    /// <summary>
    /// Loads what must be in the buffer before the run command: clears the rotary buffer (leftovers of an earlier job
    /// or of a start that broke off would run first), then the preamble and the first chunk (from the start block).
    /// </summary>
    public async Task LoadAsync(CancellationToken cancellationToken)
    {
        Loaded = false;
        sender.Restart(_startAt);
        buffer.Reset();

        // Durable before the buffer is touched: whatever the last checkpoint said about the buffer (a broken first
        // load) stops being true with the CLEAR; a resume from here loads the recorded start again.
        checkpoint();
        channel.BufferOpen = true;
        await channel.SendAsync("OPEN ROT", cancellationToken).ConfigureAwait(false);
        await channel.SendAsync("CLEAR", cancellationToken).ConfigureAwait(false);
        await channel.OnlineAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        if (_preamble is not null)
        {
            await sender.SendBatchAsync(_preamble, advance: false, oneByOne: false, cancellationToken).ConfigureAwait(false);
        }

        await downloadFirstChunk(cancellationToken).ConfigureAwait(false);
        Loaded = true;
    }
}
