namespace PmacStream.Pmac;

/// <summary>Parity of a serial line.</summary>
public enum SerialParity
{
    /// <summary>No parity bit.</summary>
    None,

    /// <summary>Even parity.</summary>
    Even,

    /// <summary>Odd parity.</summary>
    Odd,
}

/// <summary>Line settings of a serial port (8 data bits, 1 stop bit unless told).</summary>
/// <param name="BaudRate">Bits per second (9600, 19200, 38400, 57600, 115200, 230400).</param>
/// <param name="Parity">Parity.</param>
/// <param name="TwoStopBits">Two stop bits instead of one.</param>
public sealed record SerialSettings(int BaudRate = 38400, SerialParity Parity = SerialParity.None, bool TwoStopBits = false);

/// <summary>
/// A raw serial port: the seam between the serial transport (and the simulator's serial server) and the device, so
/// tests can put a socat pty pair or an in-memory fake behind it. <see cref="SerialPorts.Open"/> opens a real one.
/// </summary>
public interface ISerialPort : IDisposable
{
    /// <summary>The device path or COM name.</summary>
    string PortName { get; }

    /// <summary>Writes all bytes (blocking until the driver took them).</summary>
    void Write(ReadOnlySpan<byte> data);

    /// <summary>Reads what is available, waiting at most <paramref name="timeout"/> for the first byte. 0 = timed out.</summary>
    int Read(Span<byte> buffer, TimeSpan timeout);

    /// <summary>Discards received bytes not yet read.</summary>
    void DiscardInput();
}

/// <summary>Opens serial ports through System.IO.Ports (Windows COM ports, Linux/macOS tty and pty devices).</summary>
public static class SerialPorts
{
    /// <summary>Opens <paramref name="portName"/> (<c>/dev/ttyS0</c>, a pty path, or <c>COM3</c>) raw, with the given settings.</summary>
    /// <exception cref="IOException">The port cannot be opened or configured.</exception>
    public static ISerialPort Open(string portName, SerialSettings settings)
    {
        ArgumentNullException.ThrowIfNull(portName);
        ArgumentNullException.ThrowIfNull(settings);
        return new SystemIoSerialPort(portName, settings);
    }
}

/// <summary>A <see cref="Stream"/> over an <see cref="ISerialPort"/>, for code that speaks streams (the simulator's serial server).</summary>
public sealed class SerialPortStream : Stream
{
    private readonly ISerialPort _port;
    private readonly TimeSpan _poll;

    /// <summary>Wraps a port; reads poll it every <paramref name="poll"/> so cancellation is noticed.</summary>
    public SerialPortStream(ISerialPort port, TimeSpan? poll = null)
    {
        _port = port ?? throw new ArgumentNullException(nameof(port));
        _poll = poll ?? TimeSpan.FromMilliseconds(100);
    }

    /// <inheritdoc />
    public override bool CanRead => true;

    /// <inheritdoc />
    public override bool CanSeek => false;

    /// <inheritdoc />
    public override bool CanWrite => true;

    /// <inheritdoc />
    public override long Length => throw new NotSupportedException();

    /// <inheritdoc />
    public override long Position { get => throw new NotSupportedException(); set => throw new NotSupportedException(); }

    /// <inheritdoc />
    public override void Flush()
    {
    }

    /// <inheritdoc />
    public override int Read(byte[] buffer, int offset, int count) => Read(buffer.AsSpan(offset, count));

    /// <inheritdoc />
    public override int Read(Span<byte> buffer)
    {
        while (true)
        {
            var n = _port.Read(buffer, _poll);
            if (n > 0)
            {
                return n;
            }
        }
    }

    /// <inheritdoc />
    public override ValueTask<int> ReadAsync(Memory<byte> buffer, CancellationToken cancellationToken = default) =>
        new(Task.Factory.StartNew(
            () =>
            {
                while (true)
                {
                    cancellationToken.ThrowIfCancellationRequested();
                    var n = _port.Read(buffer.Span, _poll);
                    if (n > 0)
                    {
                        return n;
                    }
                }
            },
            cancellationToken,
            TaskCreationOptions.LongRunning,
            TaskScheduler.Default));

    /// <inheritdoc />
    public override Task<int> ReadAsync(byte[] buffer, int offset, int count, CancellationToken cancellationToken) =>
        ReadAsync(buffer.AsMemory(offset, count), cancellationToken).AsTask();

    /// <inheritdoc />
    public override void Write(byte[] buffer, int offset, int count) => _port.Write(buffer.AsSpan(offset, count));

    /// <inheritdoc />
    public override void Write(ReadOnlySpan<byte> buffer) => _port.Write(buffer);

    /// <inheritdoc />
    public override ValueTask WriteAsync(ReadOnlyMemory<byte> buffer, CancellationToken cancellationToken = default)
    {
        _port.Write(buffer.Span);
        return ValueTask.CompletedTask;
    }

    /// <inheritdoc />
    public override Task WriteAsync(byte[] buffer, int offset, int count, CancellationToken cancellationToken)
    {
        _port.Write(buffer.AsSpan(offset, count));
        return Task.CompletedTask;
    }

    /// <inheritdoc />
    public override long Seek(long offset, SeekOrigin origin) => throw new NotSupportedException();

    /// <inheritdoc />
    public override void SetLength(long value) => throw new NotSupportedException();

    /// <inheritdoc />
    protected override void Dispose(bool disposing)
    {
        if (disposing)
        {
            _port.Dispose();
        }

        base.Dispose(disposing);
    }
}
