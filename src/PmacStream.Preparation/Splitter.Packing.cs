using System.Text;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <content>The chunk packer of a split: blocks into chunks under the budgets, each chunk closed and handed to the file writer.</content>
public static partial class Splitter
{
    /// <summary>
    /// Packs the blocks the writing side emits into chunks: a chunk takes blocks until one more would break a budget
    /// (blocks per chunk, bytes, the rotary buffer's words with the tail kept free), then it is closed (the program tail
    /// on the last one, <c>CLOSE</c>) and handed to the <see cref="ChunkFileWriter"/>; it counts what the manifest
    /// lists. All of it is the splitting thread's.
    /// </summary>
    private sealed class ChunkPacker
    {
        private static readonly byte[] HeaderBytes = Encoding.ASCII.GetBytes(Header);
        private static readonly byte[] FooterBytes = Encoding.ASCII.GetBytes(Footer);

        private readonly string _source;
        private readonly string _folder;
        private readonly IProgress<SplitProgress>? _progress;
        private readonly CancellationToken _ct;
        private readonly byte[] _tail;
        private readonly int _tailWords;
        private readonly ByteLine _block = new(256); // the block set aside while its chunk is closed (once per chunk)
        private readonly ByteLine _chunk;
        private readonly int _blocksPerChunk;
        private readonly long _maxChunkBytes;
        private readonly int _rotWords;
        private readonly int _limitReserve;   // tail and footer bytes every chunk keeps room for
        private ChunkFileWriter? _writer;

        // The chunk being built.
        private int _chunkBlocks;
        private int _chunkMotion;
        private int _chunkWords;
        private int _chunkFirst;
        private int _chunkLast;
        private int _lastBlockStart;
        private bool _lastBlockEndsProgram;

        public ChunkPacker(string source, string folder, SplitOptions options, IProgress<SplitProgress>? progress, CancellationToken ct)
        {
            _source = source;
            _folder = folder;
            _progress = progress;
            _ct = ct;
            Chunks = new ChunkTable(Path.GetFileNameWithoutExtension(source));
            (_tail, _tailWords) = Tail(options.ProgramTail);
            _blocksPerChunk = options.BlocksPerChunk;
            _maxChunkBytes = options.MaxChunkBytes;
            _rotWords = options.RotWords;
            _limitReserve = _tail.Length + FooterBytes.Length;
            _chunk = new ByteLine((int)Math.Min(options.MaxChunkBytes + 256, 1 << 20));
            _chunk.Append(HeaderBytes);
        }

        /// <summary>The chunks closed so far (the manifest's table).</summary>
        public ChunkTable Chunks { get; }

        /// <summary>Blocks in all chunks, and of them those that move.</summary>
        public int TotalBlocks { get; private set; }

        /// <summary>Blocks that move (tracked), in all chunks.</summary>
        public int TotalMotion { get; private set; }

        /// <summary>The source's size and how far the splitting got, for the progress reports.</summary>
        public long TotalBytes { get; set; }

        /// <summary>How far into the source the blocks packed so far reach.</summary>
        public long Position { get; set; }

        /// <summary>No block taken since the last chunk closed (none at all before the first).</summary>
        public bool Empty => _chunkBlocks == 0;

        /// <summary>The writer closed chunks go to, while the split runs.</summary>
        public void WriteTo(ChunkFileWriter writer) => _writer = writer;

        /// <summary>Room for a block at the end of the chunk: write it there, then <see cref="Add"/> it.</summary>
        public Span<byte> Reserve(int room) => _chunk.Reserve(room);

        /// <summary>
        /// Takes the block just written after the chunk's content (<paramref name="bytes"/> long), starting a new
        /// chunk first when it would break a limit.
        /// </summary>
        public void Add(int bytes, int sourceLine, int motions, bool endsProgram, int words)
        {
            var reserve = _limitReserve;
            if (_chunkBlocks > 0 &&
                (_chunkBlocks >= _blocksPerChunk ||
                 _chunk.Length + bytes + reserve > _maxChunkBytes ||
                 _chunkWords + words + _tailWords > _rotWords))
            {
                // Once per chunk: the block waits aside while the full chunk is closed and handed to the writer.
                _block.Clear();
                _block.Append(_chunk.Pending(bytes));
                Flush(last: false);
                _chunk.Append(_block.Span);
            }
            else
            {
                _chunk.Commit(bytes);
            }

            if (_chunkBlocks == 0)
            {
                FirstOfChunk(bytes, sourceLine, words);
            }

            _lastBlockStart = _chunk.Length - bytes;
            _lastBlockEndsProgram = endsProgram;
            _chunkBlocks++;
            _chunkWords += words;
            _chunkLast = sourceLine;
            TotalBlocks++;
            _chunkMotion += motions;
            TotalMotion += motions;
        }

        /// <summary>Closes the last chunk, the program tail in it.</summary>
        public void Close() => Flush(last: true);

        /// <summary>A chunk's first block: it must fit a chunk on its own (S001), and it names the chunk's first line.</summary>
        private void FirstOfChunk(int bytes, int sourceLine, int words)
        {
            if (HeaderBytes.Length + bytes + _limitReserve > _maxChunkBytes || words + _tailWords > _rotWords)
            {
                var message = $"block of {bytes} bytes, ~{words} words does not fit one chunk " +
                              $"({_maxChunkBytes} bytes, {_rotWords} words, {HeaderBytes.Length + _limitReserve} bytes and {_tailWords} words taken by header and tail); raise --rot-words";
                var d = new Diagnostic(Severity.Error, SplitDiagnosticCodes.BlockTooBig, sourceLine, 1, message);
                throw new SplitException($"{_source}:{sourceLine}: {message}", [d], 1);
            }

            _chunkFirst = sourceLine;
        }

        private void Flush(bool last)
        {
            _ct.ThrowIfCancellationRequested();
            var words = _chunkWords;
            if (last)
            {
                // The tail goes before the program's own end code (M02/M30) when that is the last block, so the
                // end code still ends the program; otherwise after the last block.
                if (_lastBlockEndsProgram)
                {
                    _chunk.Insert(_lastBlockStart, _tail);
                }
                else
                {
                    _chunk.Append(_tail);
                }

                words += _tailWords;
            }

            _chunk.Append(FooterBytes);
            var length = _chunk.Length;
            var index = Chunks.Add(_chunkFirst, _chunkLast, _chunkBlocks, _chunkMotion, length, words);
            // The full buffer goes to the writer as it is; an empty one comes back for the next chunk.
            _chunk.Swap(_writer!.Submit(index, Chunks.FilePath(_folder, index), _chunk.Buffer, length));
            _chunk.Append(HeaderBytes);
            _chunkBlocks = 0;
            _chunkMotion = 0;
            _chunkWords = 0;
            _progress?.Report(new SplitProgress(Position, TotalBytes, Chunks.Count, TotalBlocks));
        }

        /// <summary>The program tail's lines as chunk text (trimmed, CR LF each) and the words they take.</summary>
        private static (byte[] Bytes, int Words) Tail(string programTail)
        {
            var tail = new StringBuilder();
            var words = 0;
            foreach (var line in programTail.Split('\n'))
            {
                var t = line.Trim();
                if (t.Length > 0)
                {
                    tail.Append(t).Append("\r\n");
                    words += Math.Max(1, t.Split(' ', StringSplitOptions.RemoveEmptyEntries).Length);
                }
            }

            return (Encoding.ASCII.GetBytes(tail.ToString()), words);
        }
    }
}
