using System.Collections.Concurrent;

namespace PmacStream.Preparation.Store;

/// <summary>
/// A program's source bytes cut into pieces as the check reads them (on its thread) and handed to the thread that
/// stores them, so a revision keeps its exact source without a second read of the file. The reader runs at most a
/// few batches ahead of the store, so few pieces wait at a time whatever the program's size.
/// </summary>
internal sealed class SourcePieces
{
    /// <summary>Bytes per stored piece (one row of <c>program_source</c>).</summary>
    internal const int PieceSize = 1 << 20;

    private readonly ConcurrentQueue<byte[]> _ready = new();
    private byte[] _current = new byte[PieceSize];
    private int _filled;

    /// <summary>Appends what the reader read.</summary>
    public void Append(ReadOnlySpan<byte> data)
    {
        while (data.Length > 0)
        {
            var n = Math.Min(data.Length, PieceSize - _filled);
            data[..n].CopyTo(_current.AsSpan(_filled));
            _filled += n;
            data = data[n..];
            if (_filled == PieceSize)
            {
                _ready.Enqueue(_current);
                _current = new byte[PieceSize];
                _filled = 0;
            }
        }
    }

    /// <summary>Ends the source: the last, partial piece becomes ready (call after the reader finished).</summary>
    public void Finish()
    {
        if (_filled > 0)
        {
            _ready.Enqueue(_current[.._filled]);
            _filled = 0;
        }
    }

    /// <summary>Takes the pieces ready so far, in order.</summary>
    public IEnumerable<byte[]> Drain()
    {
        while (_ready.TryDequeue(out var piece))
        {
            yield return piece;
        }
    }
}
