using System.Runtime.InteropServices;

namespace PmacStream.Pmac;

/// <summary>
/// A serial port through libc termios (Linux and macOS): opened non-blocking without becoming the controlling tty,
/// set raw (cfmakeraw) with the baud rate, parity and stop bits asked; reads wait with poll().
/// </summary>
internal sealed unsafe class PosixSerialPort : ISerialPort
{
    private const short PollIn = 0x1;
    private const short PollOut = 0x4;
    private const int Eintr = 4;
    private static readonly bool IsMac = OperatingSystem.IsMacOS() || OperatingSystem.IsFreeBSD();
    private int _fd;

    public PosixSerialPort(string portName, SerialSettings settings)
    {
        PortName = portName;
        var flags = 2 /* O_RDWR */ | (IsMac ? 0x20000 | 0x4 : 0x100 | 0x800); // O_NOCTTY | O_NONBLOCK
        _fd = open(portName, flags);
        if (_fd < 0)
        {
            throw new IOException($"cannot open serial port {portName}: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
        }

        try
        {
            Configure(settings);
        }
        catch
        {
            close(_fd);
            _fd = -1;
            throw;
        }
    }

    public string PortName { get; }

    public void Write(ReadOnlySpan<byte> data)
    {
        ObjectDisposedException.ThrowIf(_fd < 0, this);
        fixed (byte* p = data)
        {
            var done = 0;
            while (done < data.Length)
            {
                var n = write(_fd, p + done, (nint)(data.Length - done));
                if (n > 0)
                {
                    done += (int)n;
                    continue;
                }

                var errno = Marshal.GetLastPInvokeError();
                if (n < 0 && errno != Eintr && errno != 11 && errno != 35)
                {
                    throw new IOException($"write to {PortName} failed: {Marshal.GetPInvokeErrorMessage(errno)}");
                }

                Wait(PollOut, 1000);
            }
        }
    }

    public int Read(Span<byte> buffer, TimeSpan timeout)
    {
        ObjectDisposedException.ThrowIf(_fd < 0, this);
        var ms = (int)Math.Clamp(timeout.TotalMilliseconds, 0, int.MaxValue);
        var ready = Wait(PollIn, ms);
        if (!ready)
        {
            return 0;
        }

        fixed (byte* p = buffer)
        {
            var n = read(_fd, p, (nint)buffer.Length);
            if (n < 0)
            {
                var errno = Marshal.GetLastPInvokeError();
                if (errno is Eintr or 11 or 35)
                {
                    return 0;
                }

                throw new IOException($"read from {PortName} failed: {Marshal.GetPInvokeErrorMessage(errno)}");
            }

            if (n == 0)
            {
                // poll said readable and read gives nothing: the other end of a pty closed (hang-up).
                throw new IOException($"{PortName}: the line was hung up");
            }

            return (int)n;
        }
    }

    public void DiscardInput()
    {
        if (_fd >= 0)
        {
            _ = tcflush(_fd, IsMac ? 1 : 0); // TCIFLUSH
        }
    }

    public void Dispose()
    {
        if (_fd >= 0)
        {
            close(_fd);
            _fd = -1;
        }
    }

    private bool Wait(short events, int ms)
    {
        var fds = new PollFd { Fd = _fd, Events = events };
        while (true)
        {
            var r = poll(&fds, 1, ms);
            if (r > 0)
            {
                if ((fds.Revents & 0x10) != 0 && (fds.Revents & PollIn) == 0)
                {
                    // POLLHUP with nothing to read: the other side of a pty pair is closed.
                    throw new IOException($"{PortName}: the line was hung up");
                }

                return true;
            }

            if (r == 0)
            {
                return false;
            }

            if (Marshal.GetLastPInvokeError() != Eintr)
            {
                throw new IOException($"poll on {PortName} failed: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
            }
        }
    }

    private void Configure(SerialSettings settings)
    {
        // struct termios is opaque here except c_cflag: Linux has 4-byte flag fields (c_cflag at offset 8), macOS
        // 8-byte ones (offset 16). The buffer is larger than either layout.
        var t = stackalloc byte[256];
        if (tcgetattr(_fd, t) != 0)
        {
            throw new IOException($"{PortName} is not a serial port or pty: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
        }

        cfmakeraw(t);
        var speed = IsMac ? (nuint)settings.BaudRate : LinuxSpeed(settings.BaudRate);
        if (cfsetispeed(t, speed) != 0 || cfsetospeed(t, speed) != 0)
        {
            throw new IOException($"{PortName}: baud rate {settings.BaudRate} not supported");
        }

        // Flag values: Linux CSTOPB 0x40, CREAD 0x80, PARENB 0x100, PARODD 0x200, CLOCAL 0x800;
        // macOS CSTOPB 0x400, CREAD 0x800, PARENB 0x1000, PARODD 0x2000, CLOCAL 0x8000.
        ulong cstopb = IsMac ? 0x400u : 0x40u, cread = IsMac ? 0x800u : 0x80u, parenb = IsMac ? 0x1000u : 0x100u;
        ulong parodd = IsMac ? 0x2000u : 0x200u, clocal = IsMac ? 0x8000u : 0x800u;
        ulong cflag = IsMac ? *(ulong*)(t + 16) : *(uint*)(t + 8);
        cflag |= cread | clocal;
        cflag &= ~(parenb | parodd | cstopb);
        if (settings.Parity != SerialParity.None)
        {
            cflag |= parenb | (settings.Parity == SerialParity.Odd ? parodd : 0);
        }

        if (settings.TwoStopBits)
        {
            cflag |= cstopb;
        }

        if (IsMac)
        {
            *(ulong*)(t + 16) = cflag;
        }
        else
        {
            *(uint*)(t + 8) = (uint)cflag;
        }

        if (tcsetattr(_fd, 0 /* TCSANOW */, t) != 0)
        {
            throw new IOException($"cannot configure {PortName}: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
        }

        _ = tcflush(_fd, IsMac ? 3 : 2); // TCIOFLUSH
    }

    private static nuint LinuxSpeed(int baud) => baud switch
    {
        1200 => 0x9,
        2400 => 0xB,
        4800 => 0xC,
        9600 => 0xD,
        19200 => 0xE,
        38400 => 0xF,
        57600 => 0x1001,
        115200 => 0x1002,
        230400 => 0x1003,
        460800 => 0x1004,
        921600 => 0x1007,
        _ => throw new IOException($"baud rate {baud} not supported (1200..921600 standard rates)"),
    };

    [StructLayout(LayoutKind.Sequential)]
    private struct PollFd
    {
        public int Fd;
        public short Events;
        public short Revents;
    }

    [DllImport("libc", SetLastError = true)]
    private static extern int open([MarshalAs(UnmanagedType.LPUTF8Str)] string path, int flags);

    [DllImport("libc", SetLastError = true)]
    private static extern int close(int fd);

    [DllImport("libc", SetLastError = true)]
    private static extern nint read(int fd, byte* buffer, nint count);

    [DllImport("libc", SetLastError = true)]
    private static extern nint write(int fd, byte* buffer, nint count);

    [DllImport("libc", SetLastError = true)]
    private static extern int poll(PollFd* fds, nuint count, int timeout);

    [DllImport("libc", SetLastError = true)]
    private static extern int tcgetattr(int fd, byte* termios);

    [DllImport("libc", SetLastError = true)]
    private static extern int tcsetattr(int fd, int optionalActions, byte* termios);

    [DllImport("libc")]
    private static extern void cfmakeraw(byte* termios);

    [DllImport("libc", SetLastError = true)]
    private static extern int cfsetispeed(byte* termios, nuint speed);

    [DllImport("libc", SetLastError = true)]
    private static extern int cfsetospeed(byte* termios, nuint speed);

    [DllImport("libc", SetLastError = true)]
    private static extern int tcflush(int fd, int queue);
}
