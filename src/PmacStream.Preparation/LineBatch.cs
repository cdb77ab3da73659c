using System.Runtime.InteropServices;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// A run of lexed source lines handed from the reading thread (reader, and the checker when it runs in the same
/// pass) to the splitting thread. Only what the splitter emits is carried: each line's bytes and words. Batches
/// are recycled through a small pool, so the hand-over allocates nothing per line and memory stays bounded.
/// </summary>
internal sealed class LineBatch
{
    /// <summary>A batch is handed over once it holds this many lines ...</summary>
    public const int MaxLines = 4096;

    /// <summary>... or this many text bytes.</summary>
    public const int TextBudget = 1 << 18;

    private byte[] _text = new byte[TextBudget + 1024];
    private GWord[] _words = new GWord[MaxLines * 4];
    private LineRecord[] _lines = new LineRecord[MaxLines];

    /// <summary>Lines in the batch.</summary>
    public int Count { get; private set; }

    /// <summary>Source bytes consumed up to the end of the batch's last line (for progress).</summary>
    public long EndPosition { get; set; }

    public bool IsFull => Count >= MaxLines || TextLength >= TextBudget;

    /// <summary>Text bytes used: where the next line's text goes.</summary>
    public int TextLength { get; private set; }

    private int WordCount { get; set; }

    public ReadOnlySpan<LineRecord> Lines => _lines.AsSpan(0, Count);

    public byte[] Text => _text;

    public ReadOnlySpan<GWord> WordsOf(in LineRecord line) => _words.AsSpan(line.WordStart, line.WordCount);

    public void Clear()
    {
        Count = 0;
        TextLength = 0;
        WordCount = 0;
        EndPosition = 0;
    }

    /// <summary>
    /// Makes room in <see cref="Text"/> for an <see cref="AxisLine"/> of a <paramref name="lineLength"/>-byte line and
    /// returns where it goes (read <see cref="Text"/> after this call: it may have grown).
    /// </summary>
    public int AxisTextRoom(int lineLength)
    {
        var room = AxisLine.TextRoom(lineLength);
        if (TextLength + room > _text.Length)
        {
            Array.Resize(ref _text, Math.Max(TextLength + room, _text.Length * 2));
        }

        return TextLength;
    }

    /// <summary>Takes the <see cref="AxisLine"/> text just written into <see cref="AxisTextRoom"/>: a line of <paramref name="words"/> words, N dropped.</summary>
    public void AddAxisLine(int lineNumber, int textLength, int words)
    {
        Room();
        _lines[Count++] = new LineRecord(lineNumber, TextLength, textLength, -1, words);
        TextLength += textLength;
    }

    /// <summary>A host block's lines stay in one batch, so a batch may grow past <see cref="MaxLines"/> while one is added.</summary>
    private void Room()
    {
        if (Count == _lines.Length)
        {
            Array.Resize(ref _lines, _lines.Length * 2);
        }
    }

    /// <summary>
    /// Copies a line (the reader's shared block is overwritten by the next line), its first <paramref name="wordCount"/>
    /// words (all by default: fewer when block delete skips the part of the block after a <c>/</c> inside it), less the
    /// words at <paramref name="dropColumns"/> (words the check found unused: the controller must not get them).
    /// </summary>
    public void Add(GBlock block, int wordCount = int.MaxValue, IReadOnlyList<int>? dropColumns = null, bool continues = false)
    {
        var words = CollectionsMarshal.AsSpan(block.WordList);
        words = words[..Math.Min(wordCount, words.Length)];
        if (dropColumns is { Count: > 0 })
        {
            // Rare (a warned line): compacted in place, the reader's block is not read again after this.
            var kept = 0;
            for (var i = 0; i < words.Length; i++)
            {
                if (!Contains(dropColumns, words[i].Column))
                {
                    words[kept++] = words[i];
                }
            }

            words = words[..kept];
        }

        Reserve(block.Length, words.Length);
        block.Buffer.AsSpan(0, block.Length).CopyTo(_text.AsSpan(TextLength));
        Take(block.LineNumber, block.Length, words, continues);
    }

    /// <summary>
    /// Adds a line the host's conversion wrote with its words (<paramref name="words"/> as the lexer reads
    /// <paramref name="text"/>): the line is not lexed again.
    /// </summary>
    public void Add(string text, ReadOnlySpan<GWord> words, int lineNumber, bool continues)
    {
        var length = System.Text.Encoding.UTF8.GetByteCount(text);
        Reserve(length, words.Length);
        System.Text.Encoding.UTF8.GetBytes(text, _text.AsSpan(TextLength));
        Take(lineNumber, length, words, continues);
    }

    /// <summary>The text of line <paramref name="index"/> (a held host line, to be rewritten).</summary>
    public string TextAt(int index) =>
        System.Text.Encoding.UTF8.GetString(_text, _lines[index].TextStart, _lines[index].TextLength);

    /// <summary>
    /// Line <paramref name="index"/> becomes <paramref name="block"/>'s text and words (its line number and place
    /// stay): a compensated move whose end an inside corner moved back. The old text stays unused in the batch.
    /// </summary>
    public void Replace(int index, GBlock block)
    {
        var words = CollectionsMarshal.AsSpan(block.WordList);
        Reserve(block.Length, words.Length);
        block.Buffer.AsSpan(0, block.Length).CopyTo(_text.AsSpan(TextLength));
        words.CopyTo(_words.AsSpan(WordCount));
        _lines[index] = _lines[index] with { TextStart = TextLength, TextLength = block.Length, WordStart = WordCount, WordCount = words.Length };
        TextLength += block.Length;
        WordCount += words.Length;
    }

    private void Reserve(int textLength, int words)
    {
        if (TextLength + textLength > _text.Length)
        {
            Array.Resize(ref _text, Math.Max(TextLength + textLength, _text.Length * 2));
        }

        if (WordCount + words > _words.Length)
        {
            Array.Resize(ref _words, Math.Max(WordCount + words, _words.Length * 2));
        }

        Room();
    }

    /// <summary>Records the line whose text was just copied to the end of <see cref="Text"/>, and copies its words.</summary>
    private void Take(int lineNumber, int length, ReadOnlySpan<GWord> words, bool continues)
    {
        words.CopyTo(_words.AsSpan(WordCount));
        _lines[Count++] = new LineRecord(lineNumber, TextLength, length, WordCount, words.Length) { Continues = continues };
        TextLength += length;
        WordCount += words.Length;
    }

    private static bool Contains(IReadOnlyList<int> columns, int column)
    {
        for (var i = 0; i < columns.Count; i++)
        {
            if (columns[i] == column)
            {
                return true;
            }
        }

        return false;
    }
}

/// <summary>
/// Where one line of a <see cref="LineBatch"/> lies; word number offsets are relative to the line's text. An
/// <see cref="AxisLine"/> has no words stored (<see cref="WordStart"/> -1): its text is already the block as emitted.
/// </summary>
internal readonly record struct LineRecord(int LineNumber, int TextStart, int TextLength, int WordStart, int WordCount)
{
    public bool IsAxisLine => WordStart < 0;

    /// <summary>One more line of the same source block (the host's conversion made several): it stays in its first line's chunk.</summary>
    public bool Continues { get; init; }
}
