using System.Runtime.ExceptionServices;
using System.Runtime.InteropServices;
using System.Security.Cryptography;

namespace PmacStream.Preparation;

/// <summary>
/// Writes chunk files and hashes them on a background thread, so file creation (slow on some file systems) and
/// SHA-256 overlap with reading the source. At most <see cref="Depth"/> chunks wait, so memory stays bounded.
/// A failure on the writer thread surfaces on the splitter's thread at its next hand-over or at <see cref="Complete"/>.
/// </summary>
internal sealed class ChunkFileWriter : IDisposable
{
    private const int Depth = 4;
    private const int CollectEvery = 4096;

    private readonly HandOff<(int Index, string Path, byte[] Data, int Length)> _queue;
    private readonly HandOff<byte[]> _free;
    private readonly ChunkTable _table;
    private readonly Action<int>? _afterWritten;
    private readonly CancellationToken _ct;
    private readonly Task _task;
    private volatile Exception? _failure;

    public ChunkFileWriter(ChunkTable table, Action<int>? afterWritten, CancellationToken ct, int chunkCapacity = 1 << 16)
    {
        _table = table;
        _afterWritten = afterWritten;
        _ct = ct;
        _queue = new(Depth, ct);
        // Its own few buffers, recycled: renting from the shared pool on one thread and returning on another kept
        // missing and allocated a new 64 KB array for many chunks (megabytes of garbage, all resident until a GC).
        _free = new(Depth + 2, ct);
        for (var i = 0; i < Depth + 2; i++)
        {
            _free.Add(new byte[chunkCapacity]);
        }

        _task = Task.Factory.StartNew(Run, CancellationToken.None, TaskCreationOptions.LongRunning, TaskScheduler.Default);
    }

    /// <summary>
    /// Queues the first <paramref name="length"/> bytes of <paramref name="data"/> to be written to
    /// <paramref name="path"/>; the writer owns that array from now on. Returns an empty array to build the next
    /// chunk in (waits while <see cref="Depth"/> chunks are queued).
    /// </summary>
    public byte[] Submit(int index, string path, byte[] data, int length)
    {
        if (!_free.TryTake(out var next))
        {
            // The writer failed and closed the pool.
            ExceptionDispatchInfo.Throw(_failure ?? new InvalidOperationException("chunk writer stopped"));
        }

        try
        {
            _queue.Add((index, path, data, length));
        }
        catch (InvalidOperationException) when (_failure != null)
        {
            ExceptionDispatchInfo.Throw(_failure);
        }

        return next;
    }

    /// <summary>Waits for every queued chunk (their hashes are then in the table). Rethrows a writer failure.</summary>
    public void Complete()
    {
        _queue.Complete();
        _task.GetAwaiter().GetResult();
    }

    public void Dispose()
    {
        _queue.Complete();

        try
        {
            _task.Wait();
        }
        catch (AggregateException)
        {
            // Already reported through Enqueue/Complete, or the split failed for another reason.
        }

        _queue.Dispose();
        _free.Dispose();
    }

    private void Run()
    {
        Span<byte> hash = stackalloc byte[32];
        try
        {
            while (_queue.TryTake(out var item))
            {
                var (index, path, data, length) = item;
                try
                {
                    _ct.ThrowIfCancellationRequested();
                    var span = data.AsSpan(0, length);
                    NewFile.Write(path, span);

                    SHA256.HashData(span, hash);
                    _table.SetHash(index, hash);
                }
                finally
                {
                    _free.Add(data);
                }

                _afterWritten?.Invoke(index);
                if ((index & (CollectEvery - 1)) == 0)
                {
                    // Each chunk leaves ~300 bytes of garbage (its path string and file handle) and the first gen0
                    // collection would only come after tens of megabytes (the budget follows the L3 cache size), all
                    // of it resident: a gigabyte program's 30,000 chunks would add ~9 MB. A gen0 collection of an
                    // almost empty generation costs well under a millisecond.
                    GC.Collect(0, GCCollectionMode.Forced, blocking: true, compacting: false);
                }
            }
        }
        catch (Exception e)
        {
            _failure = e;
            _queue.Complete();
            _free.Complete();
            throw;
        }
    }
}

/// <summary>
/// Creates a file that must not exist yet and writes it whole. On Linux straight through libc (open, write, close):
/// .NET's own handle adds an advisory lock and its release (flock twice) and a seek test per file, which for the
/// 30,000 chunks of a gigabyte program is tens of thousands of system calls that protect nothing here (the folder is
/// the split's own, hidden until published). Elsewhere a bare .NET handle (no FileStream objects per chunk).
/// </summary>
internal static partial class NewFile
{
    // Linux x86-64 and arm64 open(2) flags.
    private const int OWrOnly = 0x1;
    private const int OCreat = 0x40;
    private const int OExcl = 0x80;
    private const int OCloExec = 0x80000;
    private const int EIntr = 4;

    public static void Write(string path, ReadOnlySpan<byte> data)
    {
        if (!OperatingSystem.IsLinux())
        {
            using var handle = File.OpenHandle(path, FileMode.CreateNew, FileAccess.Write, FileShare.None);
            RandomAccess.Write(handle, data, 0);
            return;
        }

        int fd;
        do
        {
            fd = Open(path, OWrOnly | OCreat | OExcl | OCloExec, Convert.ToInt32("644", 8));
        }
        while (fd < 0 && Marshal.GetLastPInvokeError() == EIntr);

        if (fd < 0)
        {
            throw Failure(path, "create");
        }

        var written = false;
        try
        {
            unsafe
            {
                fixed (byte* p = data)
                {
                    for (var done = 0; done < data.Length;)
                    {
                        var n = WriteBytes(fd, p + done, (nuint)(data.Length - done));
                        if (n < 0)
                        {
                            if (Marshal.GetLastPInvokeError() == EIntr)
                            {
                                continue;
                            }

                            throw Failure(path, "write");
                        }

                        done += (int)n;
                    }
                }
            }

            written = true;
        }
        finally
        {
            // A failing close is reported (after a failed write, that failure is the one that counts).
            if (Close(fd) < 0 && Marshal.GetLastPInvokeError() != EIntr && written)
            {
                throw Failure(path, "close");
            }
        }
    }

    private static IOException Failure(string path, string what)
    {
        var errno = Marshal.GetLastPInvokeError();
        return new IOException($"{path}: cannot {what}: {Marshal.GetPInvokeErrorMessage(errno)}", errno);
    }

    [LibraryImport("libc", EntryPoint = "open", SetLastError = true, StringMarshalling = StringMarshalling.Utf8)]
    private static partial int Open(string path, int flags, int mode);

    [LibraryImport("libc", EntryPoint = "write", SetLastError = true)]
    private static unsafe partial nint WriteBytes(int fd, byte* buffer, nuint count);

    [LibraryImport("libc", EntryPoint = "close", SetLastError = true)]
    private static partial int Close(int fd);
}
