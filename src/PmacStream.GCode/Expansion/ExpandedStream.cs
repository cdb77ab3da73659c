namespace PmacStream.GCode.Expansion;

/// <summary>
/// The expansion as a read-only stream of program text, produced as it is read (the reader, the checker and the
/// splitter take it as they take a file). A refusal ends the stream; <see cref="MacroExpander.Error"/> says why.
/// </summary>
public sealed class ExpandedStream(MacroExpander expander) : Stream
{
    private long _position;

    /// <summary>The expander producing the text.</summary>
    public MacroExpander Expander { get; } = expander;

    /// <inheritdoc/>
    public override bool CanRead => true;

    /// <inheritdoc/>
    public override bool CanSeek => false;

    /// <inheritdoc/>
    public override bool CanWrite => false;

    /// <inheritdoc/>
    public override long Length => throw new NotSupportedException();

    /// <inheritdoc/>
    public override long Position { get => _position; set => throw new NotSupportedException(); }

    /// <inheritdoc/>
    public override int Read(byte[] buffer, int offset, int count) => Read(buffer.AsSpan(offset, count));

    /// <inheritdoc/>
    public override int Read(Span<byte> buffer)
    {
        if (Expander.Output.Length == 0)
        {
            Expander.Fill(Math.Max(buffer.Length, 1));
        }

        var n = Math.Min(buffer.Length, Expander.Output.Length);
        Expander.Output[..n].CopyTo(buffer);
        Expander.Consume(n);
        _position += n;
        return n;
    }

    /// <inheritdoc/>
    public override void Flush()
    {
    }

    /// <inheritdoc/>
    public override long Seek(long offset, SeekOrigin origin) => throw new NotSupportedException();

    /// <inheritdoc/>
    public override void SetLength(long value) => throw new NotSupportedException();

    /// <inheritdoc/>
    public override void Write(byte[] buffer, int offset, int count) => throw new NotSupportedException();
}
