using System.Diagnostics;
using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>What one download of a chunk sent.</summary>
/// <param name="Chunk">The chunk (1-based).</param>
/// <param name="Lines">Program lines sent.</param>
/// <param name="Whole">True for the whole chunk file through <c>Download</c>; false for the rest of a broken-off chunk.</param>
internal readonly record struct ChunkSent(int Chunk, int Lines, bool Whole);

/// <summary>
/// The sending primitives the strategies use: a whole chunk file through <c>Download</c>, a batch of lines in one
/// write, lines one by one. It keeps the position of the next line to send and whether that position is exact. Before
/// anything goes out the position is marked not exact (and a checkpoint says so); once the controller accepted the
/// lines it moves past them; when a line is refused it stops exactly before it, so nothing is skipped or repeated.
/// </summary>
/// <param name="program">The program sent.</param>
/// <param name="channel">The line to the controller.</param>
/// <param name="devices">The device facade whose <c>Download</c> sends chunk files.</param>
/// <param name="pmacNumber">The device number for <c>Download</c>.</param>
/// <param name="buffer">Records what the controller accepted.</param>
/// <param name="positionUncertain">Runs when the position stops being exact (the session writes a checkpoint).</param>
internal sealed class ProgramSender(ChunkedProgram program, ControllerChannel channel, IPmacDevices devices, int pmacNumber, RotaryBufferModel buffer, Action positionUncertain)
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    /// <summary>The next program line to send.</summary>
    public StreamPosition Next { get; set; } = new(1, 0);

    /// <summary>False while a send is under way or after one broke off: how much of it arrived is not known.</summary>
    public bool NextExact { get; set; } = true;

    /// <summary>Chunks completely sent.</summary>
    public int ChunksDownloaded { get; set; }

    /// <summary>True when every line was sent.</summary>
    public bool AllSent => program.IsEnd(Next);

    /// <summary>A new load of the buffer: sending starts at <paramref name="start"/>, nothing counted yet.</summary>
    public void Restart(StreamPosition start)
    {
        Next = start;
        NextExact = true;
        ChunksDownloaded = 0;
    }

    /// <summary>Words of the lines from <see cref="Next"/> to the end of its chunk.</summary>
    public int WordsOfRestOfChunk()
    {
        var p = program.Normalize(Next);
        if (p.Chunk > program.TotalChunks)
        {
            return 0;
        }

        var body = program.Body(p.Chunk);
        var words = 0;
        for (var i = p.Line; i < body.Count; i++)
        {
            words += body[i].Words;
        }

        return words;
    }

    /// <summary>
    /// Sends the next chunk: the whole file through <c>Download</c> (with PComm's macro, map, log and dnld flags all set), or the rest
    /// of a chunk that broke off as one batch. Returns null when everything was sent. A refused line leaves the
    /// position exactly before it and throws <see cref="PmacErrorException"/>.
    /// </summary>
    public async Task<ChunkSent?> DownloadNextChunkAsync(CancellationToken cancellationToken)
    {
        var p = program.Normalize(Next);
        Next = p;
        if (p.Chunk > program.TotalChunks)
        {
            return null;
        }

        if (p.Line > 0)
        {
            var rest = program.Body(p.Chunk).Skip(p.Line).ToList();
            await SendBatchAsync(rest, advance: true, oneByOne: false, cancellationToken).ConfigureAwait(false);
            return new ChunkSent(p.Chunk, rest.Count, Whole: false);
        }

        var body = program.Body(p.Chunk);
        var path = program.SendPath(p.Chunk, out var temporary);
        NextExact = false;
        positionUncertain();
        channel.BufferOpen = true;
        var sw = Stopwatch.StartNew();
        DownloadReport report;
        try
        {
            report = await devices.DownloadAsync(pmacNumber, path, new DownloadOptions(true, true, true, true), cancellationToken).ConfigureAwait(false);
        }
        finally
        {
            if (temporary)
            {
                DeleteQuietly(Path.GetDirectoryName(path)!);
            }
        }

        Log.Debug("download {File} -> {Success} {Lines} lines in {Ms:0.0} ms", path, report.Success, report.LinesSent, sw.Elapsed.TotalMilliseconds);
        if (report.Success)
        {
            channel.BufferOpen = false;
            foreach (var l in body)
            {
                buffer.Accept(l);
            }

            Next = new StreamPosition(p.Chunk + 1, 0);
            NextExact = true;
            ChunksDownloaded++;
            return new ChunkSent(p.Chunk, body.Count, Whole: true);
        }

        if (report.Error is { } err)
        {
            // Lines before the refused one are in the buffer; continue exactly there later.
            var accepted = 0;
            foreach (var l in body)
            {
                if (l.FileLine >= err.Line)
                {
                    break;
                }

                buffer.Accept(l);
                accepted++;
            }

            Next = new StreamPosition(p.Chunk, accepted);
            NextExact = true;
            await channel.TryCloseAsync(cancellationToken).ConfigureAwait(false);
            throw new PmacErrorException(err.Number, err.Text);
        }

        throw new PmacLinkException($"download of {path} failed without a reason");
    }

    /// <summary>
    /// Sends up to <paramref name="maxLines"/> lines within <paramref name="maxWords"/> words (as the buffer model
    /// counts them), in one batch or line by line; a batch with up to <paramref name="packetsInFlight"/> packets in flight.
    /// </summary>
    public Task SendLinesAsync(int maxLines, int maxWords, bool oneByOne, CancellationToken cancellationToken, int packetsInFlight = 1)
    {
        var lines = new List<ProgramLine>();
        var words = 0;
        foreach (var l in Ahead())
        {
            var w = buffer.WordsOf(l);
            if (lines.Count >= maxLines || words + w > maxWords)
            {
                break;
            }

            lines.Add(l);
            words += w;
        }

        return lines.Count == 0 ? Task.CompletedTask : SendBatchAsync(lines, advance: true, oneByOne, cancellationToken, packetsInFlight);
    }

    /// <summary>
    /// Sends lines in one batch until <paramref name="leadThrough"/> (seconds of motion through a move, given the moves
    /// ahead) reaches <paramref name="targetSeconds"/>, bounded by the free words and <paramref name="maxLines"/>; the
    /// non-motion lines right after the last move go with it (up to 16 more), so a batch ends at a block boundary.
    /// </summary>
    public Task SendUntilLeadAsync(double targetSeconds, int maxLines, Func<int, int, double> leadThrough, CancellationToken cancellationToken)
    {
        var lines = new List<ProgramLine>();
        var words = 0;
        var free = buffer.FreeWords;
        var moves = buffer.MovesAhead;
        var trailing = false; // the lead or the line limit is reached: only the last move's non-motion lines follow
        foreach (var l in Ahead())
        {
            trailing |= lines.Count >= maxLines;
            if (words + l.Words > free || (trailing && (l.TrackedLine > 0 || lines.Count >= maxLines + 16)))
            {
                break;
            }

            lines.Add(l);
            words += l.Words;
            trailing |= l.TrackedLine > 0 && leadThrough(l.TrackedLine, ++moves) >= targetSeconds;
        }

        return lines.Count == 0 ? Task.CompletedTask : SendBatchAsync(lines, advance: true, oneByOne: false, cancellationToken);
    }

    /// <summary>
    /// Sends <paramref name="lines"/> into the rotary buffer (<c>OPEN ROT</c> ... <c>CLOSE</c>). With
    /// <paramref name="advance"/> they are program lines at <see cref="Next"/> and the position moves past each one
    /// accepted; without, they are extra lines (a preamble) that take room but are not program positions.
    /// </summary>
    public async Task SendBatchAsync(List<ProgramLine> lines, bool advance, bool oneByOne, CancellationToken cancellationToken, int packetsInFlight = 1)
    {
        if (advance)
        {
            NextExact = false;
            positionUncertain();
        }

        channel.BufferOpen = true;
        try
        {
            if (oneByOne)
            {
                await channel.SendAsync("OPEN ROT", cancellationToken).ConfigureAwait(false);
                foreach (var l in lines)
                {
                    await channel.SendAsync(l.Text, cancellationToken).ConfigureAwait(false);
                    if (advance)
                    {
                        Accept(l);
                    }
                }

                await channel.SendAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            }
            else
            {
                var batch = new List<string>(lines.Count + 2) { "OPEN ROT" };
                batch.AddRange(lines.Select(l => l.Text));
                batch.Add("CLOSE");
                await channel.DownloadAsync(batch, lines.Count, packetsInFlight, cancellationToken).ConfigureAwait(false);
                if (advance)
                {
                    foreach (var l in lines)
                    {
                        Accept(l);
                    }
                }
            }

            channel.BufferOpen = false;
            if (advance)
            {
                NextExact = true;
            }
        }
        catch (PmacErrorException e)
        {
            if (!oneByOne && advance && e.LineInBatch is { } i)
            {
                // Index 0 was OPEN ROT: lines 1..i-1 of the batch were accepted. Lines stored behind a gap (several
                // packets in flight) are not positions to continue from: the session stops the motion before them.
                for (var k = 0; k < Math.Min(i - 1, lines.Count); k++)
                {
                    Accept(lines[k]);
                }

                NextExact = true;
            }
            else if (oneByOne && advance)
            {
                NextExact = true;
            }

            await channel.TryCloseAsync(cancellationToken).ConfigureAwait(false);
            throw;
        }
    }

    /// <summary>The program lines from <see cref="Next"/> to the end, in order (chunk bodies read as they are reached).</summary>
    private LinesAhead Ahead() => new(program, Next);

    /// <summary>A <c>foreach</c> over the program's lines from a position on, without an enumerator object per batch.</summary>
    private struct LinesAhead(ChunkedProgram program, StreamPosition from)
    {
        private StreamPosition _at = new(from.Chunk, from.Line - 1);

        public readonly ProgramLine Current => program.Body(_at.Chunk)[_at.Line];

        public readonly LinesAhead GetEnumerator() => this;

        public bool MoveNext()
        {
            _at = program.Normalize(new StreamPosition(_at.Chunk, _at.Line + 1));
            return _at.Chunk <= program.TotalChunks;
        }
    }

    private void Accept(ProgramLine line)
    {
        buffer.Accept(line);
        Next = program.Normalize(new StreamPosition(Next.Chunk, Next.Line + 1));
    }

    private static void DeleteQuietly(string folder)
    {
        try
        {
            Directory.Delete(folder, recursive: true);
        }
        catch (IOException e)
        {
            Log.Warning("could not delete {Folder}: {Error}", folder, e.Message);
        }
        catch (UnauthorizedAccessException e)
        {
            Log.Warning("could not delete {Folder}: {Error}", folder, e.Message);
        }
    }
}
