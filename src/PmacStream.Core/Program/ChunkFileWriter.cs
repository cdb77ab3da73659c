using System.Runtime.ExceptionServices;
using System.Security.Cryptography;

namespace PmacStream.Program;

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
                    // A bare handle: no FileStream and buffering strategy objects per chunk.
                    using (var handle = File.OpenHandle(path, FileMode.CreateNew, FileAccess.Write, FileShare.None))
                    {
                        RandomAccess.Write(handle, span, 0);
                    }

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
