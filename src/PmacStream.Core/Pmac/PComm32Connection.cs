using System.Diagnostics;
using System.Reflection;
using System.Runtime.InteropServices;
using System.Text;
using Serilog;

namespace PmacStream.Pmac;

/// <summary>The status nibble PComm32 puts in the top 4 bits of <c>PmacGetResponseA</c>'s return value.</summary>
public enum PCommStatus
{
    /// <summary>No status bits (plain character count).</summary>
    None = 0x0,

    /// <summary>Unsolicited data arrived.</summary>
    Unsolicited = 0x1,

    /// <summary>The reply ended normally (ACK seen).</summary>
    Eot = 0x8,

    /// <summary>The controller did not answer in time.</summary>
    Timeout = 0xC,

    /// <summary>Bad checksum on the link.</summary>
    BadChecksum = 0xD,

    /// <summary>The controller answered with an error (ERRnnn).</summary>
    Error = 0xE,

    /// <summary>The driver call failed (device not open, link down).</summary>
    Fail = 0xF,
}

/// <summary>
/// A Turbo PMAC through Delta Tau's PComm32 driver (<c>Pcomm32.dll</c>, Windows): P/Invoke into
/// <c>OpenPmacDevice</c>, <c>ClosePmacDevice</c>, <c>PmacGetResponseA</c>, <c>PmacFlush</c>,
/// <c>PmacGetControlResponseA</c> and <c>PmacDownloadA</c>. Compiles everywhere; where the library cannot be loaded
/// every call throws <see cref="PmacLinkException"/> saying so. The library is found by normal probing, or at
/// <see cref="LibraryPath"/> / the <c>PMACSTREAM_PCOMM32_LIBRARY</c> environment variable (the Linux tests point it at
/// a stand-in built from C).
/// </summary>
public sealed class PComm32Connection : IPmacConnection
{
    /// <summary>Environment variable naming the driver library file to load instead of <c>Pcomm32.dll</c>.</summary>
    public const string LibraryEnvironmentVariable = "PMACSTREAM_PCOMM32_LIBRARY";

    private const int ResponseSize = 65536;
    private static readonly ILogger Log = Serilog.Log.ForContext<PComm32Connection>();
    private readonly SemaphoreSlim _gate = new(1, 1);
    private readonly uint _device;
    private bool _open;
    private bool _disposed;

    static PComm32Connection()
    {
        try
        {
            NativeLibrary.SetDllImportResolver(typeof(PComm32Connection).Assembly, Resolve);
        }
        catch (InvalidOperationException)
        {
            // Another resolver was set for this assembly; normal probing applies.
        }
    }

    /// <summary>Creates the connection to PComm32 device <paramref name="device"/> (0 = the first PMAC configured in PComm).</summary>
    public PComm32Connection(int device)
    {
        ArgumentOutOfRangeException.ThrowIfNegative(device);
        _device = (uint)device;
        Description = $"pcomm32 device {device}";
    }

    /// <summary>The driver library to load (a full path); null = the <c>PMACSTREAM_PCOMM32_LIBRARY</c> variable, else <c>Pcomm32.dll</c>.</summary>
    public static string? LibraryPath { get; set; }

    /// <inheritdoc />
    public string Description { get; }

    /// <summary>Splits a <c>PmacGetResponseA</c> return value into its status nibble and character count.</summary>
    public static PCommStatus DecodeStatus(int returnValue, out int characterCount)
    {
        characterCount = returnValue & 0x0FFFFFFF;
        return (PCommStatus)((uint)returnValue >> 28);
    }

    /// <summary>Opens the device in the driver (done by the first request otherwise).</summary>
    public async Task OpenAsync(CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            EnsureOpen();
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(command);
        return RunAsync(() => GetResponseCore(command, null), cancellationToken);
    }

    /// <inheritdoc />
    /// <remarks>Line by line through <c>PmacGetResponseA</c>, so a refused line is known exactly and nothing after it is sent.</remarks>
    public Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(lines);
        return RunAsync(
            () =>
            {
                for (var i = 0; i < lines.Count; i++)
                {
                    cancellationToken.ThrowIfCancellationRequested();
                    GetResponseCore(lines[i], i);
                }

                return 0;
            },
            cancellationToken);
    }

    /// <summary>
    /// PComm's own file download (<c>PmacDownloadA</c>): the driver reads, preprocesses and sends the file, reporting
    /// through the message and progress callbacks. Returns the driver's verdict (non-zero return = success, assumed).
    /// </summary>
    public Task<bool> DownloadFileAsync(string path, DownloadOptions options, Action<string>? message = null, Action<int>? progress = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(path);
        ArgumentNullException.ThrowIfNull(options);
        return RunAsync(
            () =>
            {
                Native.DownloadMsgProc onMessage = (text, newline) =>
                {
                    var s = Marshal.PtrToStringAnsi(text) ?? string.Empty;
                    Log.Debug("{Device} download: {Message}", Description, s);
                    message?.Invoke(s);
                };
                Native.DownloadProgress onProgress = percent => progress?.Invoke(percent);
                var file = Encoding.Default.GetBytes(Path.GetFullPath(path) + "\0");
                var result = Call(() => Native.PmacDownloadA(_device, onMessage, null, onProgress, file, options.Macro ? 1 : 0, options.Map ? 1 : 0, options.Log ? 1 : 0, options.Dnld ? 1 : 0));
                GC.KeepAlive(onMessage);
                GC.KeepAlive(onProgress);
                return result != 0;
            },
            cancellationToken);
    }

    /// <inheritdoc />
    public Task FlushAsync(CancellationToken cancellationToken = default) =>
        RunAsync(
            () =>
            {
                Call(() =>
                {
                    Native.PmacFlush(_device);
                    return 0;
                });
                Log.Debug("{Device} > <CTRL-X>", Description);
                return 0;
            },
            cancellationToken);

    /// <inheritdoc />
    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) =>
        RunAsync(
            () =>
            {
                var sw = Stopwatch.StartNew();
                var buffer = new byte[ResponseSize];
                var ret = Call(() => Native.PmacGetControlResponseA(_device, buffer, (uint)buffer.Length, (byte)control));
                var status = DecodeStatus(ret, out var count);
                ThrowOnLinkStatus(status, $"<CTRL-{(char)(control + 64)}>");
                count = Math.Min(count, buffer.Length);
                var text = Encoding.ASCII.GetString(buffer, 0, LengthOf(buffer, count));
                Log.Debug("{Device} > <CTRL-{Char}> < {Reply} [{Status}] ({Ms:0.000} ms)", Description, (char)(control + 64), text, status, sw.Elapsed.TotalMilliseconds);
                return text;
            },
            cancellationToken);

    /// <inheritdoc />
    public async ValueTask DisposeAsync()
    {
        if (_disposed)
        {
            return;
        }

        await _gate.WaitAsync().ConfigureAwait(false);
        try
        {
            _disposed = true;
            if (_open)
            {
                _open = false;
                try
                {
                    _ = Native.ClosePmacDevice(_device);
                }
                catch (Exception e) when (e is DllNotFoundException or EntryPointNotFoundException or BadImageFormatException)
                {
                    // Nothing was opened through a missing library.
                }
            }
        }
        finally
        {
            _gate.Release();
        }
    }

    private string GetResponseCore(string command, int? lineInBatch)
    {
        EnsureOpen();
        var sw = Stopwatch.StartNew();
        var buffer = new byte[ResponseSize];
        var cmd = Encoding.ASCII.GetBytes(command + "\0");
        var ret = Call(() => Native.PmacGetResponseA(_device, buffer, (uint)buffer.Length, cmd));
        var status = DecodeStatus(ret, out var count);
        var raw = buffer.AsSpan(0, LengthOf(buffer, Math.Min(count, buffer.Length)));
        Log.Debug("{Device} > {Command} < {Reply} [{Status}] ({Ms:0.000} ms)", Description, command, ReplyParser.Visible(raw), status, sw.Elapsed.TotalMilliseconds);
        ThrowOnLinkStatus(status, command);
        var text = Encoding.ASCII.GetString(raw);
        var err = text.IndexOf("ERR", StringComparison.Ordinal);
        if (status == PCommStatus.Error || raw.IndexOf(ReplyParser.Bel) >= 0)
        {
            var number = err >= 0 && err + 6 <= text.Length && int.TryParse(text.AsSpan(err + 3, 3), out var n) ? n : PmacErrors.UnknownCommand;
            throw new PmacErrorException(number, command, lineInBatch);
        }

        return text.TrimEnd('\x06', '\r', '\n').Replace('\r', '\n');
    }

    private void ThrowOnLinkStatus(PCommStatus status, string command)
    {
        switch (status)
        {
            case PCommStatus.Timeout:
                throw new PmacLinkException($"{Description}: the controller did not answer '{command}' in time");
            case PCommStatus.BadChecksum:
                throw new PmacLinkException($"{Description}: bad checksum answering '{command}'");
            case PCommStatus.Fail:
                throw new PmacLinkException($"{Description}: the driver failed to send '{command}' (device not open or link down)");
        }
    }

    private void EnsureOpen()
    {
        ObjectDisposedException.ThrowIf(_disposed, this);
        if (_open)
        {
            return;
        }

        if (Call(() => Native.OpenPmacDevice(_device)) == 0)
        {
            throw new PmacLinkException($"{Description}: OpenPmacDevice({_device}) failed (is the device configured in PComm32 and the controller on?)");
        }

        _open = true;
        Log.Debug("{Device} opened", Description);
    }

    private async Task<T> RunAsync<T>(Func<T> body, CancellationToken cancellationToken)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            // Driver calls block; keep them off the caller's thread.
            return await Task.Run(
                () =>
                {
                    EnsureOpen();
                    return body();
                },
                cancellationToken).ConfigureAwait(false);
        }
        finally
        {
            _gate.Release();
        }
    }

    private static T Call<T>(Func<T> call)
    {
        try
        {
            return call();
        }
        catch (Exception e) when (e is DllNotFoundException or EntryPointNotFoundException or BadImageFormatException)
        {
            throw new PmacLinkException(
                $"PComm32 is not available: {e.Message.Split('\n')[0].Trim()} PComm32 is Delta Tau's Windows driver (installed with PEWIN32PRO2); " +
                "elsewhere connect over Ethernet (tcp://HOST:1025) or serial (serial:PORT) instead",
                e);
        }
    }

    private static int LengthOf(byte[] buffer, int count)
    {
        // Some driver builds count the terminating NUL; never read past it.
        var nul = Array.IndexOf(buffer, (byte)0, 0, count);
        return nul >= 0 ? nul : count;
    }

    private static IntPtr Resolve(string libraryName, Assembly assembly, DllImportSearchPath? searchPath)
    {
        if (libraryName != Native.Library)
        {
            return IntPtr.Zero;
        }

        var path = LibraryPath ?? Environment.GetEnvironmentVariable(LibraryEnvironmentVariable);
        return !string.IsNullOrEmpty(path) && NativeLibrary.TryLoad(path, out var handle) ? handle : IntPtr.Zero;
    }

    /// <summary>The driver's exports. Windows <c>long</c>, <c>BOOL</c> and <c>DWORD</c> are all 32-bit; WINAPI is stdcall.</summary>
    internal static class Native
    {
        public const string Library = "Pcomm32";

        [UnmanagedFunctionPointer(CallingConvention.StdCall)]
        public delegate void DownloadMsgProc(IntPtr text, int newline);

        [UnmanagedFunctionPointer(CallingConvention.StdCall)]
        public delegate int DownloadGetProc(int index, IntPtr buffer, int maxLength);

        [UnmanagedFunctionPointer(CallingConvention.StdCall)]
        public delegate void DownloadProgress(int percent);

        [DllImport(Library, CallingConvention = CallingConvention.StdCall)]
        public static extern int OpenPmacDevice(uint device);

        [DllImport(Library, CallingConvention = CallingConvention.StdCall)]
        public static extern int ClosePmacDevice(uint device);

        [DllImport(Library, CallingConvention = CallingConvention.StdCall)]
        public static extern int PmacGetResponseA(uint device, [Out] byte[] response, uint maxChar, [In] byte[] command);

        [DllImport(Library, CallingConvention = CallingConvention.StdCall)]
        public static extern int PmacGetControlResponseA(uint device, [Out] byte[] response, uint maxChar, byte control);

        [DllImport(Library, CallingConvention = CallingConvention.StdCall)]
        public static extern void PmacFlush(uint device);

        [DllImport(Library, CallingConvention = CallingConvention.StdCall)]
        public static extern int PmacDownloadA(uint device, DownloadMsgProc? message, DownloadGetProc? get, DownloadProgress? progress, [In] byte[] fileName, int macro, int map, int log, int dnld);
    }
}
