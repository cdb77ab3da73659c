using System.Collections;
using System.Runtime.CompilerServices;

namespace PmacStream.Preparation;

/// <summary>
/// The manifest's chunk list kept compact (about 60 bytes a chunk, hash as bytes, file name derived), so splitting a
/// gigabyte program (tens of thousands of chunks) stays within the memory goal. <see cref="ChunkInfo"/> records are
/// made on demand. Add and SetHash may run on different threads (splitter and background writer).
/// </summary>
internal sealed class ChunkTable(string name) : IReadOnlyList<ChunkInfo>
{
    private readonly object _gate = new();
    // Fixed-size segments instead of one doubling array: growing never copies, so no garbage accumulates.
    private const int SegmentShift = 10;
    private readonly List<Entry[]> _segments = [];
    private int _count;
    private long _largest;

    public int Count
    {
        get
        {
            lock (_gate)
            {
                return _count;
            }
        }
    }

    public ChunkInfo this[int index]
    {
        get
        {
            Entry e;
            lock (_gate)
            {
                ArgumentOutOfRangeException.ThrowIfGreaterThanOrEqual((uint)index, (uint)_count, nameof(index));
                e = At(index);
            }

            return new ChunkInfo(index + 1, FileName(index + 1), e.First, e.Last, e.Blocks, e.Motion, e.Bytes, e.Words,
                Convert.ToHexStringLower(e.Sha));
        }
    }

    /// <summary>Size of the largest chunk so far.</summary>
    public long LargestBytes
    {
        get
        {
            lock (_gate)
            {
                return _largest;
            }
        }
    }

    public string FileName(int chunkIndex) => $"{name}_{chunkIndex:D4}{Splitter.ChunkExtension}";

    /// <summary>The chunk file's full path in <paramref name="folder"/>, built as one string (one allocation per chunk).</summary>
    public string FilePath(string folder, int chunkIndex) =>
        string.Create(System.Globalization.CultureInfo.InvariantCulture, $"{folder}{Path.DirectorySeparatorChar}{name}_{chunkIndex:D4}{Splitter.ChunkExtension}");

    /// <summary>Adds the next chunk; returns its 1-based index. The hash comes later through <see cref="SetHash"/>.</summary>
    public int Add(int first, int last, int blocks, int motion, long bytes, int words)
    {
        lock (_gate)
        {
            if ((_count >> SegmentShift) == _segments.Count)
            {
                _segments.Add(new Entry[1 << SegmentShift]);
            }

            _largest = Math.Max(_largest, bytes);
            At(_count) = new Entry { First = first, Last = last, Blocks = blocks, Motion = motion, Bytes = bytes, Words = words };
            return ++_count;
        }
    }

    public void SetHash(int chunkIndex, ReadOnlySpan<byte> sha256)
    {
        lock (_gate)
        {
            sha256.CopyTo(At(chunkIndex - 1).Sha);
        }
    }

    /// <summary>Writes every chunk as a manifest JSON object without allocating per chunk.</summary>
    public void WriteTo(System.Text.Json.Utf8JsonWriter w)
    {
        Span<char> file = stackalloc char[name.Length + 32];
        Span<char> sha = stackalloc char[64];
        name.CopyTo(file);
        file[name.Length] = '_';
        var n = Count;
        for (var i = 0; i < n; i++)
        {
            Entry e;
            lock (_gate)
            {
                e = At(i);
            }

            (i + 1).TryFormat(file[(name.Length + 1)..], out var digits, "D4", System.Globalization.CultureInfo.InvariantCulture);
            var length = name.Length + 1 + digits;
            Splitter.ChunkExtension.CopyTo(file[length..]);
            length += Splitter.ChunkExtension.Length;
            Convert.TryToHexStringLower(e.Sha, sha, out _);
            ChunkManifest.WriteChunk(w, i + 1, file[..length], e.First, e.Last, e.Blocks, e.Motion, e.Bytes, e.Words, sha);
            if (w.BytesPending > 1 << 14)
            {
                // The writer buffers everything until flushed: a gigabyte program's manifest is megabytes.
                w.Flush();
            }
        }
    }

    public IEnumerator<ChunkInfo> GetEnumerator()
    {
        var n = Count;
        for (var i = 0; i < n; i++)
        {
            yield return this[i];
        }
    }

    IEnumerator IEnumerable.GetEnumerator() => GetEnumerator();

    private ref Entry At(int index) => ref _segments[index >> SegmentShift][index & ((1 << SegmentShift) - 1)];

    private struct Entry
    {
        public int First;
        public int Last;
        public int Blocks;
        public int Motion;
        public int Words;
        public long Bytes;
        public Sha256Bytes Sha;
    }

    [InlineArray(32)]
    private struct Sha256Bytes
    {
        private byte _b;
    }
}
