using System.IO.Ports;

namespace PmacStream.Pmac;

/// <summary>
/// A serial port through System.IO.Ports (the same class PComm-era .NET HMIs use): raw 8 data bits, no handshake,
/// with the baud rate, parity and stop bits asked. Reads wait for the first byte up to the timeout given per call.
/// </summary>
internal sealed class SystemIoSerialPort : ISerialPort
{
    private readonly SerialPort _port;
    private static readonly TimeSpan SpinFor = TimeSpan.FromMilliseconds(0.2);
    private readonly byte[] _readBuffer = new byte[4096];

    public SystemIoSerialPort(string portName, SerialSettings settings)
    {
        PortName = portName;
        _port = new SerialPort(portName, settings.BaudRate, ToParity(settings.Parity), 8, settings.TwoStopBits ? StopBits.Two : StopBits.One)
        {
            Handshake = Handshake.None,
            ReadBufferSize = 64 * 1024,
            WriteBufferSize = 64 * 1024,
            WriteTimeout = 10_000,
        };
        try
        {
            _port.Open();
        }
        catch (Exception ex) when (ex is UnauthorizedAccessException or ArgumentException or InvalidOperationException or IOException)
        {
            _port.Dispose();
            throw new IOException($"cannot open serial port {portName}: {ex.Message}", ex);
        }
    }

    public string PortName { get; }

    public void Write(ReadOnlySpan<byte> data)
    {
        try
        {
            // SerialPort.Write takes arrays only; lines to a PMAC are short, so the copy is cheap.
            var copy = data.ToArray();
            _port.Write(copy, 0, copy.Length);
        }
        catch (Exception ex) when (ex is TimeoutException or InvalidOperationException)
        {
            throw new IOException($"write to {PortName} failed: {ex.Message}", ex);
        }
    }

    public int Read(Span<byte> buffer, TimeSpan timeout)
    {
        var ms = (int)Math.Clamp(timeout.TotalMilliseconds, 0, int.MaxValue);
        try
        {
            if (!OperatingSystem.IsWindows())
            {
                // On Unix SerialPort ends a timed-out read from a pool-thread timer: with the pool busy a 300 ms
                // timeout fired when the late reply came, seconds on. Waiting for the first byte here keeps the
                // deadline ours; the read below then finds data waiting.
                if (!WaitForData(timeout))
                {
                    return 0;
                }

                ms = Math.Max(ms, 1);
            }

            // ReadTimeout 0 means "return what is there or time out at once"; SerialPort rejects negative values.
            _port.ReadTimeout = ms;
            var n = _port.Read(_readBuffer, 0, Math.Min(buffer.Length, _readBuffer.Length));
            _readBuffer.AsSpan(0, n).CopyTo(buffer);
            return n;
        }
        catch (TimeoutException)
        {
            return 0;
        }
        catch (InvalidOperationException ex)
        {
            throw new IOException($"read from {PortName} failed: {ex.Message}", ex);
        }
    }

    /// <summary>Polls the driver's receive count (FIONREAD) until a byte is there or the timeout passes.</summary>
    private bool WaitForData(TimeSpan timeout)
    {
        if (_port.BytesToRead > 0)
        {
            return true;
        }

        var clock = System.Diagnostics.Stopwatch.StartNew();
        var spin = new SpinWait();

        // Spin briefly first: a controller's reply usually follows within a character time or two.
        while (clock.Elapsed < SpinFor)
        {
            spin.SpinOnce(sleep1Threshold: -1);
            if (_port.BytesToRead > 0)
            {
                return true;
            }
        }

        while (clock.Elapsed < timeout)
        {
            Thread.Sleep(1);
            if (_port.BytesToRead > 0)
            {
                return true;
            }
        }

        return false;
    }

    public void DiscardInput()
    {
        try
        {
            _port.DiscardInBuffer();
        }
        catch (InvalidOperationException ex)
        {
            throw new IOException($"{PortName} is closed: {ex.Message}", ex);
        }
    }

    public void Dispose() => _port.Dispose();

    private static Parity ToParity(SerialParity parity) => parity switch
    {
        SerialParity.Even => Parity.Even,
        SerialParity.Odd => Parity.Odd,
        _ => Parity.None,
    };
}
