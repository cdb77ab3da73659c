using System.Runtime.InteropServices;
using PmacStream.GCode;

namespace PmacStream.Program;

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
    private readonly LineRecord[] _lines = new LineRecord[MaxLines];

    /// <summary>Lines in the batch.</summary>
    public int Count { get; private set; }

    /// <summary>Source bytes consumed up to the end of the batch's last line (for progress).</summary>
    public long EndPosition { get; set; }

    public bool IsFull => Count == MaxLines || TextLength >= TextBudget;

    private int TextLength { get; set; }

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

    /// <summary>Copies a line (the reader's shared block is overwritten by the next line).</summary>
    public void Add(GBlock block)
    {
        var words = CollectionsMarshal.AsSpan(block.WordList);
        var length = block.Length;
        if (TextLength + length > _text.Length)
        {
            Array.Resize(ref _text, Math.Max(TextLength + length, _text.Length * 2));
        }

        if (WordCount + words.Length > _words.Length)
        {
            Array.Resize(ref _words, Math.Max(WordCount + words.Length, _words.Length * 2));
        }

        block.Buffer.AsSpan(0, length).CopyTo(_text.AsSpan(TextLength));
        words.CopyTo(_words.AsSpan(WordCount));
        _lines[Count++] = new LineRecord(block.LineNumber, TextLength, length, WordCount, words.Length);
        TextLength += length;
        WordCount += words.Length;
    }
}

/// <summary>Where one line of a <see cref="LineBatch"/> lies; word number offsets are relative to the line's text.</summary>
internal readonly record struct LineRecord(int LineNumber, int TextStart, int TextLength, int WordStart, int WordCount);
