namespace PmacStream.Preparation;

/// <summary>A growable ASCII byte buffer for building chunk text without allocating per block.</summary>
internal sealed class ByteLine
{
    private byte[] _buffer;

    public ByteLine(int capacity) => _buffer = new byte[Math.Max(16, capacity)];

    public int Length { get; private set; }

    public ReadOnlySpan<byte> Span => _buffer.AsSpan(0, Length);

    public void Clear() => Length = 0;

    public void Append(ReadOnlySpan<byte> bytes)
    {
        Ensure(bytes.Length);
        bytes.CopyTo(_buffer.AsSpan(Length));
        Length += bytes.Length;
    }

    /// <summary>Makes room for <paramref name="count"/> bytes and returns the free space after the content.</summary>
    public Span<byte> Reserve(int count)
    {
        Ensure(count);
        return _buffer.AsSpan(Length);
    }

    /// <summary>Takes the first <paramref name="count"/> bytes written into the span <see cref="Reserve"/> returned.</summary>
    public void Commit(int count) => Length += count;

    /// <summary>The first <paramref name="count"/> bytes written after the content but not committed yet.</summary>
    public ReadOnlySpan<byte> Pending(int count) => _buffer.AsSpan(Length, count);

    /// <summary>The underlying array (content is its first <see cref="Length"/> bytes).</summary>
    public byte[] Buffer => _buffer;

    /// <summary>Continues, empty, in <paramref name="replacement"/>; the caller took the old array with <see cref="Buffer"/>.</summary>
    public void Swap(byte[] replacement)
    {
        _buffer = replacement;
        Length = 0;
    }

    public void Insert(int at, ReadOnlySpan<byte> bytes)
    {
        Ensure(bytes.Length);
        _buffer.AsSpan(at, Length - at).CopyTo(_buffer.AsSpan(at + bytes.Length));
        bytes.CopyTo(_buffer.AsSpan(at));
        Length += bytes.Length;
    }

    private void Ensure(int extra)
    {
        if (Length + extra > _buffer.Length)
        {
            Array.Resize(ref _buffer, Math.Max(Length + extra, _buffer.Length * 2));
        }
    }
}
