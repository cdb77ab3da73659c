using System.Buffers.Binary;
using System.Globalization;

namespace PmacStream.Streaming;

/// <summary>
/// The job database's files as they lie on disk, read before SQLite opens them: SQLite quietly ignores a write-ahead
/// log whose frames fail their checksums (and with it the last checkpoints and jobs), so the damage is found here,
/// and a damaged set is moved aside rather than replaced.
/// </summary>
internal static class JobStoreFiles
{
    private const int WalHeaderSize = 32;
    private const int FrameHeaderSize = 24;
    private static readonly byte[] SqliteMagic = "SQLite format 3\0"u8.ToArray();

    /// <summary>The write-ahead log beside <paramref name="path"/>.</summary>
    public static string Wal(string path) => path + "-wal";

    /// <summary>What is wrong with the main file's header, or null (also when the file is absent or empty: SQLite starts a new one).</summary>
    public static string? HeaderProblem(string path)
    {
        var info = new FileInfo(path);
        if (!info.Exists || info.Length == 0)
        {
            return null;
        }

        if (info.Length < 100)
        {
            return $"it is {info.Length} bytes long, shorter than an SQLite header";
        }

        var head = new byte[SqliteMagic.Length];
        using (var f = new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.ReadWrite | FileShare.Delete))
        {
            f.ReadExactly(head);
        }

        return head.AsSpan().SequenceEqual(SqliteMagic) ? null : "it is not an SQLite database (its first bytes are not the SQLite header)";
    }

    /// <summary>
    /// What is wrong with the write-ahead log, or null when it is absent, empty or sound. Sound means: a valid header,
    /// and no committed transaction of the current generation (the header's salts) behind a frame that fails its
    /// checksum. A bad frame with no commit after it is the torn tail of a transaction a killed writer never
    /// committed, which SQLite rightly rolls back.
    /// </summary>
    public static string? WalProblem(string walPath)
    {
        var info = new FileInfo(walPath);
        if (!info.Exists || info.Length == 0)
        {
            return null;
        }

        using var f = new FileStream(walPath, FileMode.Open, FileAccess.Read, FileShare.ReadWrite | FileShare.Delete);
        if (f.Length < WalHeaderSize)
        {
            return $"its write-ahead log {walPath} is cut short ({f.Length} bytes)";
        }

        var header = new byte[WalHeaderSize];
        f.ReadExactly(header);
        var magic = BinaryPrimitives.ReadUInt32BigEndian(header);
        if ((magic & 0xFFFFFFFE) != 0x377F0682 || BinaryPrimitives.ReadUInt32BigEndian(header.AsSpan(4)) != 3007000)
        {
            return $"its write-ahead log {walPath} does not start with a write-ahead log header";
        }

        var bigEndian = (magic & 1) != 0;
        var pageSize = (int)BinaryPrimitives.ReadUInt32BigEndian(header.AsSpan(8));
        pageSize = pageSize == 1 ? 65536 : pageSize;
        if (pageSize < 512 || pageSize > 65536 || (pageSize & (pageSize - 1)) != 0)
        {
            return $"its write-ahead log {walPath} names a page size of {pageSize}";
        }

        var (s0, s1) = Checksum(header.AsSpan(0, 24), 0, 0, bigEndian);
        if (s0 != BinaryPrimitives.ReadUInt32BigEndian(header.AsSpan(24)) || s1 != BinaryPrimitives.ReadUInt32BigEndian(header.AsSpan(28)))
        {
            return $"the header of its write-ahead log {walPath} fails its checksum (SQLite would ignore the whole log)";
        }

        var salt1 = BinaryPrimitives.ReadUInt32BigEndian(header.AsSpan(16));
        var salt2 = BinaryPrimitives.ReadUInt32BigEndian(header.AsSpan(20));
        var frame = new byte[FrameHeaderSize + pageSize];
        long broken = 0;
        for (long index = 1; ; index++)
        {
            if (f.ReadAtLeast(frame, frame.Length, throwOnEndOfStream: false) < frame.Length)
            {
                return null;
            }

            var current = BinaryPrimitives.ReadUInt32BigEndian(frame.AsSpan(8)) == salt1 && BinaryPrimitives.ReadUInt32BigEndian(frame.AsSpan(12)) == salt2;
            if (broken == 0)
            {
                // SQLite reads the log up to the first frame of another generation or with a bad checksum.
                if (!current)
                {
                    broken = index;
                    continue;
                }

                (s0, s1) = Checksum(frame.AsSpan(0, 8), s0, s1, bigEndian);
                (s0, s1) = Checksum(frame.AsSpan(FrameHeaderSize), s0, s1, bigEndian);
                if (s0 != BinaryPrimitives.ReadUInt32BigEndian(frame.AsSpan(16)) || s1 != BinaryPrimitives.ReadUInt32BigEndian(frame.AsSpan(20)))
                {
                    broken = index;
                }

                continue;
            }

            // Past that point, a committed transaction of this generation is one SQLite would silently drop. Without
            // one, the break is the log's end or the torn tail of a transaction a killed writer never committed.
            if (current && BinaryPrimitives.ReadUInt32BigEndian(frame.AsSpan(4)) != 0)
            {
                return $"frame {broken} of its write-ahead log {walPath} is damaged: SQLite would silently drop it and the committed writes after it";
            }
        }
    }

    /// <summary>
    /// Moves the database and its write-ahead log and shared-memory files aside as <c>PATH.damaged-STAMP</c> (+
    /// <c>-wal</c>, <c>-shm</c>), never deleting anything; returns the new database path.
    /// </summary>
    public static string KeepAside(string path)
    {
        var stamp = DateTime.UtcNow.ToString("yyyyMMdd'T'HHmmss'Z'", CultureInfo.InvariantCulture);
        var aside = $"{path}.damaged-{stamp}";
        for (var n = 2; File.Exists(aside) || File.Exists(aside + "-wal"); n++)
        {
            aside = $"{path}.damaged-{stamp}-{n}";
        }

        foreach (var suffix in new[] { "-wal", "-shm", string.Empty })
        {
            if (File.Exists(path + suffix))
            {
                File.Move(path + suffix, aside + suffix);
            }
        }

        return aside;
    }

    /// <summary>SQLite's WAL checksum: over 32-bit words in pairs, in the byte order the log's magic names.</summary>
    private static (uint S0, uint S1) Checksum(ReadOnlySpan<byte> data, uint s0, uint s1, bool bigEndian)
    {
        for (var i = 0; i + 8 <= data.Length; i += 8)
        {
            var x0 = bigEndian ? BinaryPrimitives.ReadUInt32BigEndian(data[i..]) : BinaryPrimitives.ReadUInt32LittleEndian(data[i..]);
            var x1 = bigEndian ? BinaryPrimitives.ReadUInt32BigEndian(data[(i + 4)..]) : BinaryPrimitives.ReadUInt32LittleEndian(data[(i + 4)..]);
            s0 += x0 + s1;
            s1 += x1 + s0;
        }

        return (s0, s1);
    }
}
