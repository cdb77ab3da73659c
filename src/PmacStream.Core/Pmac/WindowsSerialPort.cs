using System.Runtime.InteropServices;
using System.Runtime.Versioning;
using Microsoft.Win32.SafeHandles;

namespace PmacStream.Pmac;

/// <summary>
/// A serial port through the Win32 comm API (CreateFile, SetCommState, SetCommTimeouts, ReadFile, WriteFile).
/// Reads return as soon as a byte arrives or when the timeout passes (MAXDWORD interval and multiplier).
/// </summary>
[SupportedOSPlatform("windows")]
internal sealed unsafe class WindowsSerialPort : ISerialPort
{
    private const uint GenericRead = 0x80000000, GenericWrite = 0x40000000, OpenExisting = 3;
    private const uint PurgeRxClear = 0x0008;
    private readonly SafeFileHandle _handle;
    private uint _timeoutMs = uint.MaxValue;

    public WindowsSerialPort(string portName, SerialSettings settings)
    {
        PortName = portName;
        var path = portName.StartsWith(@"\\.\", StringComparison.Ordinal) ? portName : @"\\.\" + portName;
        _handle = CreateFileW(path, GenericRead | GenericWrite, 0, IntPtr.Zero, OpenExisting, 0, IntPtr.Zero);
        if (_handle.IsInvalid)
        {
            throw new IOException($"cannot open serial port {portName}: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
        }

        var dcb = default(Dcb);
        dcb.DCBlength = (uint)sizeof(Dcb);
        if (!GetCommState(_handle, ref dcb))
        {
            _handle.Dispose();
            throw new IOException($"{portName} is not a serial port: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
        }

        dcb.BaudRate = (uint)settings.BaudRate;
        dcb.Flags = 0x1 | (settings.Parity != SerialParity.None ? 0x2u : 0u); // fBinary, fParity
        dcb.ByteSize = 8;
        dcb.Parity = settings.Parity switch { SerialParity.Odd => 1, SerialParity.Even => 2, _ => 0 };
        dcb.StopBits = settings.TwoStopBits ? (byte)2 : (byte)0;
        if (!SetCommState(_handle, ref dcb))
        {
            _handle.Dispose();
            throw new IOException($"cannot configure {portName}: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
        }
    }

    public string PortName { get; }

    public void Write(ReadOnlySpan<byte> data)
    {
        fixed (byte* p = data)
        {
            var done = 0;
            while (done < data.Length)
            {
                if (!WriteFile(_handle, p + done, (uint)(data.Length - done), out var n, IntPtr.Zero))
                {
                    throw new IOException($"write to {PortName} failed: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
                }

                done += (int)n;
            }
        }
    }

    public int Read(Span<byte> buffer, TimeSpan timeout)
    {
        var ms = (uint)Math.Clamp(timeout.TotalMilliseconds, 1, uint.MaxValue - 1);
        if (ms != _timeoutMs)
        {
            var t = new CommTimeouts { ReadIntervalTimeout = uint.MaxValue, ReadTotalTimeoutMultiplier = uint.MaxValue, ReadTotalTimeoutConstant = ms };
            if (!SetCommTimeouts(_handle, ref t))
            {
                throw new IOException($"cannot set timeouts on {PortName}: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
            }

            _timeoutMs = ms;
        }

        fixed (byte* p = buffer)
        {
            if (!ReadFile(_handle, p, (uint)buffer.Length, out var n, IntPtr.Zero))
            {
                throw new IOException($"read from {PortName} failed: {Marshal.GetPInvokeErrorMessage(Marshal.GetLastPInvokeError())}");
            }

            return (int)n;
        }
    }

    public void DiscardInput() => PurgeComm(_handle, PurgeRxClear);

    public void Dispose() => _handle.Dispose();

    [StructLayout(LayoutKind.Sequential)]
    private struct Dcb
    {
        public uint DCBlength;
        public uint BaudRate;
        public uint Flags;
        public ushort WReserved;
        public ushort XonLim;
        public ushort XoffLim;
        public byte ByteSize;
        public byte Parity;
        public byte StopBits;
        public sbyte XonChar;
        public sbyte XoffChar;
        public sbyte ErrorChar;
        public sbyte EofChar;
        public sbyte EvtChar;
        public ushort WReserved1;
    }

    [StructLayout(LayoutKind.Sequential)]
    private struct CommTimeouts
    {
        public uint ReadIntervalTimeout;
        public uint ReadTotalTimeoutMultiplier;
        public uint ReadTotalTimeoutConstant;
        public uint WriteTotalTimeoutMultiplier;
        public uint WriteTotalTimeoutConstant;
    }

    [DllImport("kernel32", SetLastError = true, CharSet = CharSet.Unicode)]
    private static extern SafeFileHandle CreateFileW(string name, uint access, uint share, IntPtr security, uint creation, uint flags, IntPtr template);

    [DllImport("kernel32", SetLastError = true)]
    [return: MarshalAs(UnmanagedType.Bool)]
    private static extern bool GetCommState(SafeFileHandle handle, ref Dcb dcb);

    [DllImport("kernel32", SetLastError = true)]
    [return: MarshalAs(UnmanagedType.Bool)]
    private static extern bool SetCommState(SafeFileHandle handle, ref Dcb dcb);

    [DllImport("kernel32", SetLastError = true)]
    [return: MarshalAs(UnmanagedType.Bool)]
    private static extern bool SetCommTimeouts(SafeFileHandle handle, ref CommTimeouts timeouts);

    [DllImport("kernel32", SetLastError = true)]
    [return: MarshalAs(UnmanagedType.Bool)]
    private static extern bool ReadFile(SafeFileHandle handle, byte* buffer, uint count, out uint read, IntPtr overlapped);

    [DllImport("kernel32", SetLastError = true)]
    [return: MarshalAs(UnmanagedType.Bool)]
    private static extern bool WriteFile(SafeFileHandle handle, byte* buffer, uint count, out uint written, IntPtr overlapped);

    [DllImport("kernel32", SetLastError = true)]
    [return: MarshalAs(UnmanagedType.Bool)]
    private static extern bool PurgeComm(SafeFileHandle handle, uint flags);
}
