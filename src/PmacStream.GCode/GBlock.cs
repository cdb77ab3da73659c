using System.Text;

namespace PmacStream.GCode;

/// <summary>
/// One source line as the reader saw it. The reader reuses a single instance per line while streaming, so
/// consumers that keep a block must copy what they need (<see cref="TextWithoutComments"/>, <see cref="Words"/> copy).
/// </summary>
public sealed class GBlock
{
    // The lexer's storage for the line, refilled for the next one: the splitter's hot path reads (and, once it has
    // taken the line, may compact) it in place instead of copying it.

    /// <summary>The line's bytes (its first <see cref="Length"/>), as read.</summary>
    public byte[] Buffer = new byte[256];

    /// <summary>The line's words in order (<see cref="Words"/> copies them).</summary>
    public readonly List<GWord> WordList = new(16);

    /// <summary>The lexer's findings on the line (the first <see cref="FindingLimits.PerLine"/>; the rest counted).</summary>
    public readonly List<Diagnostic> DiagnosticList = new(2);

    /// <summary>The comments' spans in <see cref="Buffer"/>: start and length of each one's inner text.</summary>
    public readonly List<(int Start, int Length)> CommentList = new(2);

    /// <summary>1-based source line number.</summary>
    public int LineNumber { get; internal set; }

    /// <summary>Byte offset of the line's first byte in the file.</summary>
    public long ByteOffset { get; internal set; }

    /// <summary>Length of the line in bytes, without its line end.</summary>
    public int Length { get; internal set; }

    /// <summary>Forgets the findings of the line before (a new line is read into this instance).</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    internal void ClearFindings()
    {
        DiagnosticList.Clear();
        UnlistedErrors = 0;
        UnlistedWarnings = 0;
    }

    /// <summary>True while the line has fewer than <see cref="FindingLimits.PerLine"/> findings listed (a caller can skip building a message the line will not list).</summary>
    internal bool ListsFindings => DiagnosticList.Count < FindingLimits.PerLine;

    /// <summary>Lists a finding, or counts it once the line has <see cref="FindingLimits.PerLine"/> listed.</summary>
    internal void AddFinding(Severity severity, string code, int column, params object[] args)
    {
        if (ListsFindings)
        {
            DiagnosticList.Add(new Diagnostic(severity, code, LineNumber, column, DiagnosticText.Format(code, args)));
        }
        else
        {
            CountUnlisted(severity);
        }
    }

    /// <summary>Counts a finding that is not listed.</summary>
    internal void CountUnlisted(Severity severity)
    {
        if (severity == Severity.Error)
        {
            UnlistedErrors++;
        }
        else
        {
            UnlistedWarnings++;
        }
    }

    /// <summary>The raw bytes of the line (no line end).</summary>
    public ReadOnlySpan<byte> Line => Buffer.AsSpan(0, Length);

    /// <summary>The address words in source order.</summary>
    public IReadOnlyList<GWord> Words => WordList;

    /// <summary>Findings of the lexer for this line (illegal characters, malformed numbers, unclosed comments).</summary>
    public IReadOnlyList<Diagnostic> LexicalDiagnostics => DiagnosticList;

    /// <summary>Lexical errors of this line past <see cref="FindingLimits.PerLine"/>: counted, not listed.</summary>
    public int UnlistedErrors { get; private set; }

    /// <summary>Lexical warnings of this line past <see cref="FindingLimits.PerLine"/>: counted, not listed.</summary>
    public int UnlistedWarnings { get; private set; }

    /// <summary>Comment spans (<c>( ... )</c> and <c>; ...</c>), as offsets into <see cref="Line"/>, delimiters included.</summary>
    public IReadOnlyList<(int Start, int Length)> Comments => CommentList;

    /// <summary>The line starts with <c>/</c>: skipped when block delete is on.</summary>
    public bool BlockDelete { get; internal set; }

    /// <summary>The line is a <c>%</c> tape mark.</summary>
    public bool IsTapeMark { get; internal set; }

    /// <summary>
    /// Index in <see cref="Words"/> of the first word after a <c>/</c> inside the block (FANUC's optional block skip from
    /// there to the end of the block), or -1 when the block has none.
    /// </summary>
    public int SkipFrom { get; internal set; } = -1;

    /// <summary>1-based column of the <c>/</c> inside the block (see <see cref="SkipFrom"/>), 0 when none.</summary>
    public int SkipColumn { get; internal set; }

    /// <summary>Nothing but white space and comments (or empty).</summary>
    public bool IsEmpty => WordList.Count == 0 && !IsTapeMark;

    /// <summary>The program number when the line carries <c>O</c>nnnn (or <c>:</c>nnnn), else null.</summary>
    public double? ProgramNumber
    {
        get
        {
            foreach (var w in WordList)
            {
                if (w.Letter == 'O')
                {
                    return w.Value;
                }
            }

            return null;
        }
    }

    /// <summary>The text of a word's number exactly as written (sign and points included).</summary>
    public ReadOnlySpan<byte> NumberText(in GWord word) => Buffer.AsSpan(word.NumberStart, word.NumberLength);

    /// <summary>The comments' inner text, decoded (UTF-8, falling back to GBK when the bytes are not UTF-8).</summary>
    public IEnumerable<string> CommentTexts()
    {
        foreach (var (start, length) in CommentList)
        {
            yield return TextDecoding.Decode(Buffer.AsSpan(start, length));
        }
    }

    /// <summary>The words only, upper case, one space between them: <c>G1 X1. Y-2.5</c>.</summary>
    public string TextWithoutComments()
    {
        var sb = new StringBuilder(Length);
        foreach (var w in WordList)
        {
            if (sb.Length > 0)
            {
                sb.Append(' ');
            }

            sb.Append(w.Letter);
            foreach (var b in NumberText(w))
            {
                sb.Append((char)b);
            }
        }

        return sb.ToString();
    }

    /// <summary>Finds the first word with the given letter.</summary>
    public bool TryGetWord(char letter, out GWord word)
    {
        foreach (var w in WordList)
        {
            if (w.Letter == letter)
            {
                word = w;
                return true;
            }
        }

        word = default;
        return false;
    }

    /// <summary>The decoded line text, for display.</summary>
    public override string ToString() => TextDecoding.Decode(Line);
}
