using PmacStream.Pmac;

namespace PmacStream.Sim.Servers;

/// <summary>
/// One Ethernet client's reply text not yet fetched (SENDLINE replies waiting for GETLINE, the rest of a long
/// GETRESPONSE waiting for GETBUFFER), bounded like a controller's response buffer: when a SENDLINE reply would
/// overflow <see cref="Capacity"/>, the oldest whole replies are dropped (and counted). The bytes are given back
/// once fetched, so a client that never reads cannot grow the server.
/// </summary>
internal sealed class PendingReplies
{
    private const int InitialSize = 256;

    // Kept after a burst only up to this size; a larger buffer is given back once it empties.
    private const int KeepSize = 4096;

    private byte[] _buffer = new byte[InitialSize];
    private int _start;
    private int _count;

    /// <summary>Creates an empty buffer that holds at most <paramref name="capacity"/> bytes of queued replies.</summary>
    public PendingReplies(int capacity)
    {
        ArgumentOutOfRangeException.ThrowIfLessThan(capacity, 1);
        Capacity = capacity;
    }

    /// <summary>Most bytes of queued replies kept (one reply larger than this is still kept whole, alone).</summary>
    public int Capacity { get; }

    /// <summary>Bytes waiting to be fetched.</summary>
    public int Count => _count;

    /// <summary>Replies dropped because the buffer was full.</summary>
    public long DroppedReplies { get; private set; }

    /// <summary>Bytes of those replies.</summary>
    public long DroppedBytes { get; private set; }

    /// <summary>Size of the storage held now (for tests: it shrinks back once emptied).</summary>
    internal int StorageBytes => _buffer.Length;

    /// <summary>The waiting bytes.</summary>
    public ReadOnlySpan<byte> Span => _buffer.AsSpan(_start, _count);

    /// <summary>Queues a SENDLINE reply behind the others, dropping the oldest whole replies while it would not fit.</summary>
    /// <returns>The number of replies dropped to make room.</returns>
    public int Add(ReadOnlySpan<byte> reply)
    {
        var dropped = 0;
        while (_count > 0 && _count + reply.Length > Capacity)
        {
            var n = VrPmac.ReplyLength(Span);
            n = n < 0 ? _count : n;
            Consume(n);
            dropped++;
            DroppedBytes += n;
        }

        DroppedReplies += dropped;
        Append(reply);
        return dropped;
    }

    /// <summary>Replaces everything waiting with one command's reply (GETRESPONSE answers only its own command).</summary>
    public void Replace(ReadOnlySpan<byte> reply)
    {
        Clear();
        Append(reply);
    }

    /// <summary>
    /// Moves the first reply (by the controller's termination rules, or everything when no terminator is there) into
    /// <paramref name="destination"/>, at most its length; the rest stays for the next fetch. Returns the bytes moved.
    /// </summary>
    public int Take(Span<byte> destination)
    {
        var n = VrPmac.ReplyLength(Span);
        n = Math.Min(n < 0 ? _count : n, destination.Length);
        Span[..n].CopyTo(destination);
        Consume(n);
        return n;
    }

    /// <summary>Discards everything waiting (FLUSH, Ctrl-X).</summary>
    public void Clear()
    {
        _start = 0;
        _count = 0;
        GiveBack();
    }

    private void Consume(int n)
    {
        _start += n;
        _count -= n;
        if (_count == 0)
        {
            _start = 0;
            GiveBack();
        }
    }

    private void GiveBack()
    {
        if (_buffer.Length > KeepSize)
        {
            _buffer = new byte[InitialSize];
        }
    }

    private void Append(ReadOnlySpan<byte> bytes)
    {
        if (_start + _count + bytes.Length > _buffer.Length)
        {
            var needed = _count + bytes.Length;
            var target = needed <= _buffer.Length ? _buffer : new byte[Math.Max(needed, Math.Min(_buffer.Length * 2, Math.Max(needed, Capacity)))];
            Span.CopyTo(target);
            _buffer = target;
            _start = 0;
        }

        bytes.CopyTo(_buffer.AsSpan(_start + _count));
        _count += bytes.Length;
    }
}
