using System.Buffers;

namespace PmacStream.GCode;

/// <summary>
/// Streams a G-code program line by line from bytes, never holding more than one line. Accepts what CAM posts and
/// people write: no spaces (<c>G0X1.Y-2.5</c>), spaces between letter and number (<c>G0Z  0.1</c>), lower case,
/// <c>.5</c>/<c>5.</c>/<c>+5</c>, tabs, CR/LF/CRLF, <c>( )</c> and <c>;</c> comments holding UTF-8 or GBK text,
/// <c>%</c> tape marks, <c>/</c> block delete, <c>O</c>/<c>:</c> program numbers and <c>N</c> numbers.
/// Lexical problems become diagnostics on the block; the reader itself never throws on content.
/// </summary>
public sealed class GCodeReader : IDisposable
{
    /// <summary>Longest line accepted; longer lines are cut there and reported (E114), so memory stays bounded.</summary>
    public const int MaxLineLength = 1 << 20;

    /// <summary>Bytes readable after the line end of a line <see cref="ReadRaw"/> returns (wide loads need no bounds checks).</summary>
    public const int RawSlack = 16;

    private readonly Stream _stream;
    private readonly bool _leaveOpen;
    private readonly byte[] _chunk;
    private readonly GBlock _block = new();
    private int _chunkPos;
    private int _chunkLen;
    private long _chunkFileOffset;
    private int _lineNumber;
    private bool _pendingCrLf;
    private bool _eof;
    private bool _rawInChunk;   // the line ReadRaw returned lies in the read buffer, not (yet) in the block
    private long _rawOffset;
    private int _rawStart;
    private int _rawLength;
    private bool _sawBlock;     // a line with words came before: a '%' line now ends the tape
    private bool _sawBlockBeforeRaw; // _sawBlock before NoteRaw guessed from the raw line: LexRaw judges by the words
    private bool _ended;        // the closing '%' was read: nothing after it is program text

    /// <summary>Reads from a stream (which the reader disposes unless <paramref name="leaveOpen"/>).</summary>
    public GCodeReader(Stream stream, bool leaveOpen = false, int bufferSize = 1 << 16)
    {
        _stream = stream;
        _leaveOpen = leaveOpen;
        _chunk = ArrayPool<byte>.Shared.Rent(bufferSize + RawSlack + 1);
    }

    /// <summary>Opens a file for sequential reading.</summary>
    public static GCodeReader Open(string path) =>
        new(new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan));

    /// <summary>True when the input starts with a UTF-16 byte-order mark (the lines will not be G-code; the checker says so).</summary>
    public bool StartsWithUtf16Bom { get; private set; }

    /// <summary>Bytes consumed so far (for progress).</summary>
    public long Position => _chunkFileOffset + _chunkPos;

    /// <summary>The current block after <see cref="Read"/> returned true. The same instance every time.</summary>
    public GBlock Current => _block;

    /// <summary>
    /// Line of the <c>%</c> that ended the tape (a <c>%</c> line after the first block), 0 while none did. FANUC reads a
    /// program between the first <c>%</c> and the next; RS274/NGC ignores what follows the second percent line. The
    /// reader ends its input there.
    /// </summary>
    public int TapeEndLine { get; private set; }

    /// <summary>Something other than blanks follows the <c>%</c> that ended the tape (it is ignored; the checker says so).</summary>
    public bool TextAfterTapeEnd { get; private set; }

    /// <summary>Reads the next line. Returns false at the end of the input (or after the <c>%</c> that ends the tape).</summary>
    public bool Read()
    {
        if (_ended || !ReadLine())
        {
            return false;
        }

        LineLexer.Lex(_block);
        Note(_block);
        return true;
    }

    /// <summary>Lines read so far: the number of the line <see cref="ReadRaw"/> returned last.</summary>
    public int LineNumber => _lineNumber;

    /// <summary>
    /// Reads the next line without lexing it (the splitter's fast lane looks at the bytes first): it is
    /// <paramref name="length"/> bytes of <paramref name="data"/> from <paramref name="start"/>, followed by a line
    /// end (CR or LF) and at least <see cref="RawSlack"/> more bytes of the array; valid until the next read.
    /// <see cref="LexRaw"/> turns it into <see cref="Current"/>, exactly as <see cref="Read"/> would have. A line
    /// that lies whole in the read buffer is not copied.
    /// </summary>
    public bool ReadRaw(out byte[] data, out int start, out int length)
    {
        if (_ended)
        {
            data = _block.Buffer;
            start = length = 0;
            return false;
        }

        SkipLfAfterCr();

        if (!_pendingCrLf && _chunkPos < _chunkLen)
        {
            var span = _chunk.AsSpan(_chunkPos, _chunkLen - _chunkPos);
            var end = span.IndexOfAny((byte)'\n', (byte)'\r');
            if ((uint)end <= MaxLineLength)
            {
                _rawInChunk = true;
                _rawOffset = _chunkFileOffset + _chunkPos;
                data = _chunk;
                start = _rawStart = _chunkPos;
                length = _rawLength = end;
                _pendingCrLf = span[end] == (byte)'\r';
                _chunkPos += end + 1;
                _lineNumber++;
                NoteRaw(span[..end]);
                return true;
            }
        }

        // The line runs past the buffer (or is the first one, or too long): assemble it in the block as Read does.
        _rawInChunk = false;
        if (!ReadLine())
        {
            data = _block.Buffer;
            start = length = 0;
            return false;
        }

        var b = _block;
        if (b.Buffer.Length < b.Length + 1 + RawSlack)
        {
            Array.Resize(ref b.Buffer, b.Length + 1 + RawSlack);
        }

        b.Buffer[b.Length] = (byte)'\n'; // what every line returned is followed by
        data = b.Buffer;
        start = 0;
        length = b.Length;
        NoteRaw(b.Buffer.AsSpan(0, b.Length));
        return true;
    }

    /// <summary>
    /// The unread part of the read buffer, <paramref name="data"/>[<paramref name="position"/>..<paramref name="end"/>),
    /// followed by a 0 and at least <see cref="RawSlack"/> more bytes: for a scanner that finds the next line's end
    /// itself and then takes the line with <see cref="TakeLine"/>. False when the next line must come from
    /// <see cref="ReadRaw"/> (the buffer is used up, or a CR at its end may still be followed by an LF).
    /// </summary>
    public bool PeekBuffer(out byte[] data, out int position, out int end)
    {
        SkipLfAfterCr();

        data = _chunk;
        position = _chunkPos;
        end = _chunkLen;
        return !_ended && !_pendingCrLf && _chunkPos < _chunkLen;
    }

    /// <summary>
    /// Takes the next line, found by the caller in <see cref="PeekBuffer"/>'s bytes: <paramref name="length"/> bytes
    /// and the line end after them (CR or LF). It is then read, as if through <see cref="ReadRaw"/>; it is not lexed.
    /// </summary>
    public void TakeLine(int length)
    {
        var terminator = _chunk[_chunkPos + length];
        if ((uint)length > MaxLineLength || _chunkPos + length >= _chunkLen || terminator is not ((byte)'\n' or (byte)'\r'))
        {
            throw new ArgumentOutOfRangeException(nameof(length), "not a whole line of the read buffer");
        }

        _rawInChunk = false;
        _pendingCrLf = terminator == (byte)'\r';
        _chunkPos += length + 1;
        _lineNumber++;
        _sawBlock = true; // the caller's scan found words on it
    }

    /// <summary>A CR ended the last line: an LF right after it belongs to that line end, when the buffer shows it yet.</summary>
    private void SkipLfAfterCr()
    {
        if (_pendingCrLf && _chunkPos < _chunkLen)
        {
            _pendingCrLf = false;
            if (_chunk[_chunkPos] == (byte)'\n')
            {
                _chunkPos++;
            }
        }
    }

    /// <summary>The line <see cref="ReadRaw"/> returned last lay whole in the read buffer (and was not copied).</summary>
    public bool LineWasInBuffer => _rawInChunk;

    /// <summary>Lexes the line <see cref="ReadRaw"/> returned last into <see cref="Current"/> and returns it.</summary>
    public GBlock LexRaw()
    {
        var b = _block;
        if (_rawInChunk)
        {
            _rawInChunk = false;
            b.Length = 0;
            b.ClearFindings();
            var truncated = false;
            Append(b, _chunk.AsSpan(_rawStart, _rawLength), ref truncated);
            b.ByteOffset = _rawOffset;
            b.LineNumber = _lineNumber;
        }

        // A lexed line is a block by its words, as Read judges it, not by the letter NoteRaw saw at its start (a junk
        // line such as "ray" would otherwise let the next '%' end the tape here and not in Read).
        _sawBlock = _sawBlockBeforeRaw;
        LineLexer.Lex(b);
        Note(b);
        return b;
    }

    /// <summary>
    /// A raw line that a caller may take without lexing: until the first block, one that starts with a letter is
    /// taken as a block, so that a later <c>%</c> ends the tape (a line that is then lexed, <see cref="LexRaw"/>, is
    /// judged by its words instead).
    /// </summary>
    private void NoteRaw(ReadOnlySpan<byte> line)
    {
        _sawBlockBeforeRaw = _sawBlock;
        if (_sawBlock)
        {
            return;
        }

        var i = LineLexer.SkipBlanks(line, 0);
        _sawBlock = i < line.Length && (uint)((line[i] | 0x20) - 'a') <= 'z' - 'a';
    }

    /// <summary>A lexed line: a block with words, or the <c>%</c> that ends the tape (the rest of the input is then only counted).</summary>
    private void Note(GBlock b)
    {
        _sawBlock |= b.WordList.Count > 0;
        if (b.IsTapeMark && _sawBlock)
        {
            _ended = true;
            TapeEndLine = b.LineNumber;
            SkipToEnd();
        }
    }

    /// <summary>Reads the rest of the input after the tape's end: its lines are counted, and whether it holds text.</summary>
    private void SkipToEnd()
    {
        var lineOpen = false;
        while (_chunkPos < _chunkLen || Fill())
        {
            var c = _chunk[_chunkPos++];
            if (_pendingCrLf)
            {
                _pendingCrLf = false;
                if (c == (byte)'\n')
                {
                    continue;
                }
            }

            if (c is (byte)'\n' or (byte)'\r')
            {
                _lineNumber++;
                _pendingCrLf = c == (byte)'\r';
                lineOpen = false;
                continue;
            }

            lineOpen = true;
            // Blanks and a DOS end-of-file mark are not text.
            TextAfterTapeEnd |= c is not ((byte)' ' or (byte)'\t' or 0x1A);
        }

        if (lineOpen)
        {
            _lineNumber++; // a last line without a line end
        }
    }

    /// <summary>Reads every block of a file, yielding the shared instance (copy what you keep).</summary>
    public static IEnumerable<GBlock> ReadAll(string path)
    {
        using var reader = Open(path);
        while (reader.Read())
        {
            yield return reader.Current;
        }
    }

    /// <summary>Lexes a single line of text (tests, the HMI, the store's formatter).</summary>
    public static GBlock LexLine(string text, int lineNumber = 1)
    {
        var block = new GBlock();
        var bytes = System.Text.Encoding.UTF8.GetBytes(text);
        block.Buffer = bytes.Length == 0 ? new byte[1] : bytes;
        block.Length = bytes.Length;
        block.LineNumber = lineNumber;
        LineLexer.Lex(block);
        return block;
    }

    /// <summary>Lexes a single line of text into <paramref name="into"/>, reusing its buffer and lists (a caller that copies what it keeps).</summary>
    public static GBlock LexLine(string text, int lineNumber, GBlock into)
    {
        var length = System.Text.Encoding.UTF8.GetByteCount(text);
        if (into.Buffer.Length < length)
        {
            into.Buffer = new byte[Math.Max(length, into.Buffer.Length * 2)];
        }

        System.Text.Encoding.UTF8.GetBytes(text, into.Buffer);
        into.Length = length;
        into.LineNumber = lineNumber;
        into.ClearFindings();
        LineLexer.Lex(into);
        return into;
    }

    /// <inheritdoc />
    public void Dispose()
    {
        ArrayPool<byte>.Shared.Return(_chunk);
        if (!_leaveOpen)
        {
            _stream.Dispose();
        }
    }

    private bool Fill()
    {
        if (_eof)
        {
            return false;
        }

        _chunkFileOffset += _chunkLen;
        _chunkPos = 0;
        _chunkLen = _stream.Read(_chunk, 0, _chunk.Length - RawSlack - 1); // room for the 0 and the slack after it
        if (_chunkLen <= 0)
        {
            _chunkLen = 0;
            _eof = true;
            return false;
        }

        _chunk[_chunkLen] = 0; // the end of the data, for scans that find line ends themselves (PeekBuffer)

        if (_chunkFileOffset == 0)
        {
            // Editors on Windows like to prepend byte-order marks: skip UTF-8's, flag UTF-16's.
            var head = _chunk.AsSpan(0, _chunkLen);
            if (head.StartsWith((ReadOnlySpan<byte>)[0xEF, 0xBB, 0xBF]))
            {
                _chunkPos = 3;
            }
            else if (head.StartsWith((ReadOnlySpan<byte>)[0xFF, 0xFE]) || head.StartsWith((ReadOnlySpan<byte>)[0xFE, 0xFF]))
            {
                StartsWithUtf16Bom = true;
            }
        }

        return true;
    }

    // Hot loop of a million-line program: compile optimized at once instead of spending the first
    // hundreds of milliseconds in unoptimized tier-0 code waiting for tiering.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveOptimization)]
    private bool ReadLine()
    {
        var b = _block;
        b.Length = 0;
        b.ClearFindings();
        var truncated = false;
        var started = false;

        while (true)
        {
            if (_chunkPos >= _chunkLen && !Fill())
            {
                if (!started)
                {
                    return false;
                }

                break;
            }

            if (_pendingCrLf)
            {
                _pendingCrLf = false;
                if (_chunk[_chunkPos] == (byte)'\n')
                {
                    _chunkPos++;
                    continue;
                }
            }

            if (!started)
            {
                started = true;
                b.ByteOffset = _chunkFileOffset + _chunkPos;
            }

            var span = _chunk.AsSpan(_chunkPos, _chunkLen - _chunkPos);
            var end = span.IndexOfAny((byte)'\n', (byte)'\r');
            var take = end < 0 ? span.Length : end;
            Append(b, span[..take], ref truncated);
            _chunkPos += take;
            if (end >= 0)
            {
                if (span[end] == (byte)'\r')
                {
                    _pendingCrLf = true;
                }

                _chunkPos++;
                break;
            }
        }

        b.LineNumber = ++_lineNumber;
        if (truncated)
        {
            b.DiagnosticList.Add(new Diagnostic(Severity.Error, DiagnosticCodes.LineTooLong, b.LineNumber, MaxLineLength,
                DiagnosticText.Format(DiagnosticCodes.LineTooLong, MaxLineLength)));
        }

        return true;
    }

    private static void Append(GBlock b, ReadOnlySpan<byte> data, ref bool truncated)
    {
        if (b.Length + data.Length > MaxLineLength)
        {
            truncated = true;
            data = data[..Math.Max(0, MaxLineLength - b.Length)];
        }

        if (b.Length + data.Length > b.Buffer.Length)
        {
            var bigger = new byte[Math.Max(b.Length + data.Length, b.Buffer.Length * 2)];
            b.Buffer.AsSpan(0, b.Length).CopyTo(bigger);
            b.Buffer = bigger;
        }

        data.CopyTo(b.Buffer.AsSpan(b.Length));
        b.Length += data.Length;
    }
}
