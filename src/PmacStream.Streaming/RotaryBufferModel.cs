using PmacStream.Preparation;

namespace PmacStream.Streaming;

/// <summary>
/// The host's model of one coordinate system's rotary buffer: the program lines sent and not yet calculated, in
/// order, with their words, so the strategies know the occupancy and the free room without asking the controller
/// for every line. The controller frees a line once it has calculated it; the host learns that from the tracking
/// variable (a move M0 has reached frees everything before it) and from <c>PR</c> (lines ahead).
/// </summary>
internal sealed class RotaryBufferModel
{
    private readonly Queue<Entry> _lines = new();
    private readonly Func<ProgramLine, int>? _wordsOf;

    /// <summary>
    /// Creates the model of a buffer of <paramref name="bufferWords"/> words, <paramref name="safetyWords"/> of them
    /// kept free; a line is charged <paramref name="wordsOf"/> (the splitter's estimate when null).
    /// </summary>
    public RotaryBufferModel(int bufferWords, int safetyWords, Func<ProgramLine, int>? wordsOf = null)
    {
        BufferWords = bufferWords;
        SafetyWords = safetyWords;
        _wordsOf = wordsOf;
    }

    /// <summary>The words this model charges <paramref name="line"/>.</summary>
    public int WordsOf(ProgramLine line) => _wordsOf is null ? line.Words : _wordsOf(line);

    /// <summary>The buffer's size (<c>DEFINE ROT</c>), words.</summary>
    public int BufferWords { get; private set; }

    /// <summary>The buffer was defined with <paramref name="words"/> words (sized from the controller's free memory).</summary>
    public void Resize(int words) => BufferWords = words;

    /// <summary>Words never filled, a margin for the estimate.</summary>
    public int SafetyWords { get; }

    /// <summary>Lines believed in the buffer, not yet calculated.</summary>
    public int Lines => _lines.Count;

    /// <summary>Words those lines take (the splitter's estimate per line).</summary>
    public int Words { get; private set; }

    /// <summary>Words that can still be sent: size less margin less occupancy, never below 0.</summary>
    public int FreeWords => Math.Max(0, BufferWords - SafetyWords - Words);

    /// <summary>Moves (lines with a tracking assignment) in the buffer.</summary>
    public int MovesAhead { get; private set; }

    /// <summary>Moves sent since the last <see cref="Reset"/>.</summary>
    public long MovesSent { get; private set; }

    /// <summary>Moves sent that the controller has reached: what the measured block rate counts.</summary>
    public long MovesReached => MovesSent - MovesAhead;

    /// <summary>Program lines sent since the last <see cref="Reset"/>.</summary>
    public long LinesSent { get; private set; }

    /// <summary>The source line of the last move sent (0 before the first).</summary>
    public int LastSentLine { get; private set; }

    /// <summary>Forgets everything: a new load of the buffer (it was cleared).</summary>
    public void Reset()
    {
        _lines.Clear();
        Words = 0;
        MovesAhead = 0;
        MovesSent = 0;
        LinesSent = 0;
        LastSentLine = 0;
    }

    /// <summary>A line the controller accepted into the buffer.</summary>
    public void Accept(ProgramLine line)
    {
        LinesSent++;
        if (line.TrackedLine > 0)
        {
            LastSentLine = line.TrackedLine;
            MovesAhead++;
            MovesSent++;
        }

        // A non-motion line belongs to the move before it: it is freed when a later move is reached.
        var words = WordsOf(line);
        _lines.Enqueue(new Entry(LastSentLine, words, line.TrackedLine > 0));
        Words += words;
    }

    /// <summary>The tracking variable reads <paramref name="trackedLine"/>: every line before that move has been calculated.</summary>
    public void Reached(int trackedLine)
    {
        while (_lines.Count > 0 && _lines.Peek().Line < trackedLine)
        {
            Free();
        }
    }

    /// <summary><c>PR</c> says <paramref name="linesAhead"/> lines remain: the oldest ones beyond that are gone.</summary>
    public void LinesAhead(int linesAhead)
    {
        while (_lines.Count > linesAhead)
        {
            Free();
        }
    }

    /// <summary>
    /// The buffer drained (everything sent was calculated): empty, and sending continues after the move the
    /// tracking variable names.
    /// </summary>
    public void Drained(int trackedLine)
    {
        LinesAhead(0);
        LastSentLine = trackedLine;
    }

    /// <summary>
    /// A resumed job: <paramref name="linesAhead"/> lines (<c>PR</c>) of unknown text are in the buffer after the move
    /// <paramref name="trackedLine"/>; each is charged the chunk's average words a line, and counted as a move.
    /// Sending continues after <paramref name="lastSentLine"/>.
    /// </summary>
    public void Resumed(int linesAhead, ChunkInfo chunk, int trackedLine, int lastSentLine)
    {
        ArgumentNullException.ThrowIfNull(chunk);
        LastSentLine = lastSentLine;
        var perLine = chunk.BlockCount > 0 ? Math.Max(1, (int)Math.Ceiling((double)chunk.EstimatedWords / chunk.BlockCount)) : 6;
        for (var i = 0; i < linesAhead; i++)
        {
            _lines.Enqueue(new Entry(trackedLine + 1, perLine, true));
            Words += perLine;
            MovesAhead++;
        }
    }

    /// <summary>
    /// Throws <see cref="InvalidOperationException"/> when a chunk of <paramref name="program"/> (with the line probe's
    /// words) would not fit the buffer less its margin: it could never be downloaded whole.
    /// </summary>
    public void EnsureChunksFit(ChunkedProgram program)
    {
        ArgumentNullException.ThrowIfNull(program);
        var room = BufferWords - SafetyWords;
        foreach (var c in program.Manifest.Chunks)
        {
            // The line probe adds a word to each non-motion line (feed-variable lines included: at most one line per
            // source block), or to every line with paper placement (at most two lines per block).
            var probeWords = program.LineProbeVariable is null ? 0 : program.ProbesEveryLine ? 2 * c.BlockCount : c.BlockCount;
            if (c.EstimatedWords + probeWords > room)
            {
                throw new InvalidOperationException(
                    $"chunk {c.Index} ({c.FileName}) needs about {c.EstimatedWords + probeWords} words (line probe included) but the rotary buffer holds {BufferWords} (less {SafetyWords} margin): split into smaller chunks or define a larger buffer");
            }
        }
    }

    private void Free()
    {
        var e = _lines.Dequeue();
        Words -= e.Words;
        if (e.Move)
        {
            MovesAhead--;
        }
    }

    /// <summary>One line in the buffer: the move it belongs to, its words, whether it is that move.</summary>
    private readonly record struct Entry(int Line, int Words, bool Move);
}
