using System.Diagnostics;
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
/// <c>PmacGetControlResponseA</c> and <c>PmacDownloadA</c>, bound at first use from the library (NativeLibrary +
/// unmanaged function pointers, so the library path is configurable per connection). Compiles everywhere; where the
/// library cannot be loaded every call throws <see cref="PmacLinkException"/> saying so. The library is the
/// constructor's path, else the <c>PMACSTREAM_PCOMM32_LIBRARY</c> environment variable, else <c>Pcomm32.dll</c>
/// (the Linux tests point it at a stand-in built from C).
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

    private readonly string? _libraryPath;
    private Native? _native;

    /// <summary>
    /// Creates the connection to PComm32 device <paramref name="device"/> (0 = the first PMAC configured in PComm).
    /// <paramref name="libraryPath"/> names the driver library file; null = the <c>PMACSTREAM_PCOMM32_LIBRARY</c>
    /// environment variable, else <c>Pcomm32.dll</c> by the system's normal search.
    /// </summary>
    public PComm32Connection(int device, string? libraryPath = null)
    {
        ArgumentOutOfRangeException.ThrowIfNegative(device);
        _device = (uint)device;
        _libraryPath = libraryPath;
        Description = $"pcomm32 device {device}";
    }

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
                var result = Call(() => Lib().PmacDownloadA(_device, onMessage, null, onProgress, file, options.Macro ? 1 : 0, options.Map ? 1 : 0, options.Log ? 1 : 0, options.Dnld ? 1 : 0));
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
                    Lib().PmacFlush(_device);
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
                var ret = Call(() => Lib().PmacGetControlResponseA(_device, buffer, (uint)buffer.Length, (byte)control));
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
                    _ = _native?.ClosePmacDevice(_device);
                }
                catch (PmacLinkException)
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
        var ret = Call(() => Lib().PmacGetResponseA(_device, buffer, (uint)buffer.Length, cmd));
        var status = DecodeStatus(ret, out var count);
        var raw = buffer.AsSpan(0, LengthOf(buffer, Math.Min(count, buffer.Length)));
        if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
        {
            Log.Debug("{Device} > {Command} < {Reply} [{Status}] ({Ms:0.000} ms)", Description, command, ReplyParser.Visible(raw), status, sw.Elapsed.TotalMilliseconds);
        }
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

        if (Call(() => Lib().OpenPmacDevice(_device)) == 0)
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

    private Native Lib()
    {
        if (_native is not null)
        {
            return _native;
        }

        var path = _libraryPath ?? Environment.GetEnvironmentVariable(LibraryEnvironmentVariable);
        if (string.IsNullOrEmpty(path))
        {
            path = "Pcomm32.dll";
        }

        if (!NativeLibrary.TryLoad(path, typeof(PComm32Connection).Assembly, DllImportSearchPath.SafeDirectories | DllImportSearchPath.System32, out var handle))
        {
            throw new PmacLinkException(
                $"PComm32 is not available: the driver library '{path}' could not be loaded. PComm32 is Delta Tau's Windows driver " +
                "(installed with PEWIN32PRO2); elsewhere connect over Ethernet (tcp://HOST:1025) or serial (serial:PORT) instead");
        }

        _native = new Native(handle, path);
        return _native;
    }

    /// <summary>
    /// The driver's exports, bound by name from the loaded library. Windows <c>long</c>, <c>BOOL</c> and <c>DWORD</c>
    /// are all 32-bit; WINAPI and CALLBACK are stdcall (the same as the platform default outside 32-bit x86).
    /// </summary>
    internal sealed unsafe class Native
    {
        private readonly delegate* unmanaged[Stdcall]<uint, int> _open;
        private readonly delegate* unmanaged[Stdcall]<uint, int> _close;
        private readonly delegate* unmanaged[Stdcall]<uint, byte*, uint, byte*, int> _getResponse;
        private readonly delegate* unmanaged[Stdcall]<uint, byte*, uint, byte, int> _getControlResponse;
        private readonly delegate* unmanaged[Stdcall]<uint, void> _flush;
        private readonly delegate* unmanaged[Stdcall]<uint, IntPtr, IntPtr, IntPtr, byte*, int, int, int, int, int> _download;

        public Native(IntPtr library, string path)
        {
            _open = (delegate* unmanaged[Stdcall]<uint, int>)Export(library, path, "OpenPmacDevice");
            _close = (delegate* unmanaged[Stdcall]<uint, int>)Export(library, path, "ClosePmacDevice");
            _getResponse = (delegate* unmanaged[Stdcall]<uint, byte*, uint, byte*, int>)Export(library, path, "PmacGetResponseA");
            _getControlResponse = (delegate* unmanaged[Stdcall]<uint, byte*, uint, byte, int>)Export(library, path, "PmacGetControlResponseA");
            _flush = (delegate* unmanaged[Stdcall]<uint, void>)Export(library, path, "PmacFlush");
            _download = (delegate* unmanaged[Stdcall]<uint, IntPtr, IntPtr, IntPtr, byte*, int, int, int, int, int>)Export(library, path, "PmacDownloadA");
        }

        [UnmanagedFunctionPointer(CallingConvention.StdCall)]
        public delegate void DownloadMsgProc(IntPtr text, int newline);

        [UnmanagedFunctionPointer(CallingConvention.StdCall)]
        public delegate int DownloadGetProc(int index, IntPtr buffer, int maxLength);

        [UnmanagedFunctionPointer(CallingConvention.StdCall)]
        public delegate void DownloadProgress(int percent);

        public int OpenPmacDevice(uint device) => _open(device);

        public int ClosePmacDevice(uint device) => _close(device);

        public int PmacGetResponseA(uint device, byte[] response, uint maxChar, byte[] command)
        {
            fixed (byte* r = response)
            fixed (byte* c = command)
            {
                return _getResponse(device, r, maxChar, c);
            }
        }

        public int PmacGetControlResponseA(uint device, byte[] response, uint maxChar, byte control)
        {
            fixed (byte* r = response)
            {
                return _getControlResponse(device, r, maxChar, control);
            }
        }

        public void PmacFlush(uint device) => _flush(device);

        public int PmacDownloadA(uint device, DownloadMsgProc? message, DownloadGetProc? get, DownloadProgress? progress, byte[] fileName, int macro, int map, int log, int dnld)
        {
            fixed (byte* f = fileName)
            {
                var m = message is null ? IntPtr.Zero : Marshal.GetFunctionPointerForDelegate(message);
                var g = get is null ? IntPtr.Zero : Marshal.GetFunctionPointerForDelegate(get);
                var p = progress is null ? IntPtr.Zero : Marshal.GetFunctionPointerForDelegate(progress);
                var result = _download(device, m, g, p, f, macro, map, log, dnld);
                GC.KeepAlive(message);
                GC.KeepAlive(get);
                GC.KeepAlive(progress);
                return result;
            }
        }

        private static IntPtr Export(IntPtr library, string path, string name) =>
            NativeLibrary.TryGetExport(library, name, out var address)
                ? address
                : throw new PmacLinkException($"PComm32 is not available: '{path}' has no export {name} (not a PComm32 driver?)");
    }
}
