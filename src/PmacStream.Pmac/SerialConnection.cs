using System.Diagnostics;
using System.Text;
using Serilog;

namespace PmacStream.Pmac;

/// <summary>Options of a <see cref="SerialConnection"/>.</summary>
public sealed record SerialOptions
{
    /// <summary>Port: <c>/dev/ttyS0</c>, <c>/dev/ttyUSB0</c>, a pty path, or <c>COM1</c>.</summary>
    public string PortName { get; init; } = OperatingSystem.IsWindows() ? "COM1" : "/dev/ttyS0";

    /// <summary>Baud rate, parity, stop bits (Turbo PMAC default 38400 8N1).</summary>
    public SerialSettings Settings { get; init; } = new();

    /// <summary>Longest wait for a complete reply; a dead line is reported within it.</summary>
    public TimeSpan Timeout { get; init; } = TimeSpan.FromSeconds(2);
}

/// <summary>
/// A Turbo PMAC over RS-232, ASCII protocol with I3=2 and I6=1: each command ends with CR; a reply is read up to its
/// ACK, an error from BEL to the next CR. After a timeout the line state is unknown, so the next request first sends
/// Ctrl-X and discards what arrived late. Downloads go line by line (the serial protocol has no batch packet).
/// </summary>
public sealed class SerialConnection : IPmacConnection
{
    private const byte CtrlX = 0x18;
    private static readonly ILogger Log = Serilog.Log.ForContext<SerialConnection>();
    private readonly Func<ISerialPort> _open;
    private readonly TimeSpan _timeout;
    private readonly SemaphoreSlim _gate = new(1, 1);
    private readonly byte[] _buffer = new byte[4096];
    private readonly List<byte> _reply = [];
    private ISerialPort? _port;
    private bool _dirty;
    private bool _disposed;

    /// <summary>Creates the connection; the port is opened on the first request.</summary>
    public SerialConnection(SerialOptions options)
    {
        ArgumentNullException.ThrowIfNull(options);
        _open = () => SerialPorts.Open(options.PortName, options.Settings);
        _timeout = options.Timeout;
        Description = $"serial {options.PortName}@{options.Settings.BaudRate}";
    }

    /// <summary>Uses an already opened port (any <see cref="ISerialPort"/>).</summary>
    public SerialConnection(ISerialPort port, TimeSpan timeout, string? description = null)
    {
        ArgumentNullException.ThrowIfNull(port);
        _port = port;
        _open = () => throw new PmacLinkException($"{description ?? port.PortName}: the port was closed");
        _timeout = timeout;
        Description = description ?? $"serial {port.PortName}";
    }

    /// <inheritdoc />
    public string Description { get; }

    /// <inheritdoc />
    public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(command);
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var sw = Stopwatch.StartNew();
            var raw = await OffPool(() => Exchange(command, cancellationToken), cancellationToken).ConfigureAwait(false);
            if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
            {
                Log.Debug("{Device} > {Command} < {Reply} ({Ms:0.000} ms)", Description, command, ReplyParser.Visible(raw), sw.Elapsed.TotalMilliseconds);
            }
            return ReplyParser.Parse(raw, command);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(lines);
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var sw = Stopwatch.StartNew();
            await OffPool(
                () =>
                {
                    for (var i = 0; i < lines.Count; i++)
                    {
                        var raw = Exchange(lines[i], cancellationToken);
                        try
                        {
                            ReplyParser.Parse(raw, lines[i]);
                        }
                        catch (PmacErrorException e)
                        {
                            Log.Debug("{Device} download refused line {Index}: {Line} -> ERR{Number:000}", Description, i, lines[i], e.Number);
                            throw new PmacErrorException(e.Number, lines[i], i);
                        }
                    }
                },
                cancellationToken).ConfigureAwait(false);
            Log.Debug("{Device} downloaded {Count} lines ({Ms:0.000} ms)", Description, lines.Count, sw.Elapsed.TotalMilliseconds);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public async Task FlushAsync(CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            await OffPool(
                () =>
                {
                    var port = Port();
                    Guard(() =>
                    {
                        port.Write([CtrlX]);
                        Thread.Sleep(20);
                        port.DiscardInput();
                    });
                    _dirty = false;
                },
                cancellationToken).ConfigureAwait(false);
            Log.Debug("{Device} > <CTRL-X>", Description);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public async Task<string> ControlAsync(char control, CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var sw = Stopwatch.StartNew();
            var raw = await OffPool(
                () =>
                {
                    var port = Port();
                    return Guard(() =>
                    {
                        Recover(port);
                        port.Write([(byte)control]);

                        // The reply has no terminator: it ends when the line goes quiet.
                        var reply = new List<byte>();
                        var n = port.Read(_buffer, _timeout);
                        while (n > 0)
                        {
                            reply.AddRange(_buffer.AsSpan(0, n));
                            cancellationToken.ThrowIfCancellationRequested();
                            n = port.Read(_buffer, TimeSpan.FromMilliseconds(30));
                        }

                        return reply.ToArray();
                    });
                },
                cancellationToken).ConfigureAwait(false);
            Log.Debug("{Device} > <CTRL-{Char}> < {Reply} ({Ms:0.000} ms)", Description, (char)(control + 64), ReplyParser.Visible(raw), sw.Elapsed.TotalMilliseconds);
            return Encoding.ASCII.GetString(raw);
        }
        finally
        {
            _gate.Release();
        }
    }

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
            _port?.Dispose();
            _port = null;
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <summary>
    /// Runs blocking port I/O on its own thread, not the pool: System.IO.Ports on Unix completes its read timeouts on
    /// pool threads, so a caller that blocked one (or a busy HMI) would make a 300 ms timeout fire seconds late.
    /// A thread per request, not one long-lived worker: the caller's continuation then runs on the thread that
    /// finished (no pool needed), and a caller that waits synchronously there cannot block the next request (tried:
    /// a single worker with asynchronous continuations waited for the busy pool again).
    /// </summary>
    private static Task<T> OffPool<T>(Func<T> work, CancellationToken cancellationToken) =>
        Task.Factory.StartNew(work, cancellationToken, TaskCreationOptions.LongRunning | TaskCreationOptions.DenyChildAttach, TaskScheduler.Default);

    private static Task OffPool(Action work, CancellationToken cancellationToken) =>
        Task.Factory.StartNew(work, cancellationToken, TaskCreationOptions.LongRunning | TaskCreationOptions.DenyChildAttach, TaskScheduler.Default);

    /// <summary>Sends one line and reads its complete reply (blocking; runs on its own thread).</summary>
    private byte[] Exchange(string line, CancellationToken cancellationToken)
    {
        var port = Port();
        return Guard(() =>
        {
            Recover(port);
            var bytes = new byte[Encoding.ASCII.GetByteCount(line) + 1];
            Encoding.ASCII.GetBytes(line, bytes);
            bytes[^1] = ReplyParser.Cr;
            port.Write(bytes);
            _reply.Clear();
            var deadline = Stopwatch.StartNew();
            while (true)
            {
                cancellationToken.ThrowIfCancellationRequested();
                var left = _timeout - deadline.Elapsed;
                if (left <= TimeSpan.Zero)
                {
                    _dirty = true;
                    throw new PmacLinkException($"{Description}: no complete reply to '{line}' within {_timeout.TotalMilliseconds:0} ms (got '{ReplyParser.Visible(_reply.ToArray())}')");
                }

                var n = port.Read(_buffer, left < TimeSpan.FromMilliseconds(100) ? left : TimeSpan.FromMilliseconds(100));
                if (n == 0)
                {
                    continue;
                }

                _reply.AddRange(_buffer.AsSpan(0, n));
                var end = VrPmac.ReplyLength(System.Runtime.InteropServices.CollectionsMarshal.AsSpan(_reply));
                if (end >= 0)
                {
                    // Anything after the terminator was not asked for; the next command starts clean.
                    _dirty = end < _reply.Count;
                    return _reply.GetRange(0, end).ToArray();
                }
            }
        });
    }

    /// <summary>After a timeout or stray bytes: Ctrl-X and drop what is waiting, so replies line up again.</summary>
    private void Recover(ISerialPort port)
    {
        if (!_dirty)
        {
            return;
        }

        port.Write([CtrlX]);
        Thread.Sleep(20);
        while (port.Read(_buffer, TimeSpan.FromMilliseconds(20)) > 0)
        {
        }

        port.DiscardInput();
        _dirty = false;
    }

    private ISerialPort Port()
    {
        ObjectDisposedException.ThrowIf(_disposed, this);
        if (_port is null)
        {
            try
            {
                _port = _open();
                _dirty = false;
                Log.Debug("{Device} opened", Description);
            }
            catch (IOException e)
            {
                throw new PmacLinkException($"{Description}: {e.Message}", e);
            }
        }

        return _port;
    }

    /// <summary>I/O failures close the port (reopened on the next request) and become <see cref="PmacLinkException"/>.</summary>
    private T Guard<T>(Func<T> body)
    {
        try
        {
            return body();
        }
        catch (IOException e)
        {
            _port?.Dispose();
            _port = null;
            throw new PmacLinkException($"{Description}: {e.Message}", e);
        }
    }

    private void Guard(Action body) => Guard(() =>
    {
        body();
        return 0;
    });
}
