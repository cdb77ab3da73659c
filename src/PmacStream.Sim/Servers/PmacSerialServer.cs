using System.Text;
using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Sim.Servers;

/// <summary>
/// The simulated controller's RS-232 side: the ASCII protocol over any byte stream (one engine port per stream).
/// Each CR ends a command, whose framed reply is written back; LF is ignored; Ctrl-X flushes the port and drops a
/// partial line; other control characters (Ctrl-B, C, F, G, P, V ...) are answered at once. Use
/// <see cref="OpenDevice"/> to serve a tty or one end of a socat pty pair.
/// </summary>
public sealed class PmacSerialServer : IAsyncDisposable
{
    private const int MaxLine = 1024;
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSerialServer>();
    private readonly Func<IPmacPortEndpoint> _portFactory;
    private readonly Stream _stream;
    private readonly object _engineLock;
    private readonly CancellationTokenSource _stop = new();
    private readonly string _name;
    private Task? _loop;
    private long _commands;

    /// <summary>Serves <paramref name="stream"/> (owned: disposed when the server stops).</summary>
    public PmacSerialServer(Func<IPmacPortEndpoint> portFactory, Stream stream, string name = "serial", object? engineLock = null)
    {
        _portFactory = portFactory ?? throw new ArgumentNullException(nameof(portFactory));
        _stream = stream ?? throw new ArgumentNullException(nameof(stream));
        _name = name;
        _engineLock = engineLock ?? new object();
    }

    /// <summary>Opens a serial device or pty path raw and serves it.</summary>
    public static PmacSerialServer OpenDevice(Func<IPmacPortEndpoint> portFactory, string path, SerialSettings? settings = null, object? engineLock = null)
    {
        var port = SerialPorts.Open(path, settings ?? new SerialSettings());
        return new PmacSerialServer(portFactory, new SerialPortStream(port), $"serial {path}", engineLock);
    }

    /// <summary>Commands answered so far.</summary>
    public long CommandsServed => Interlocked.Read(ref _commands);

    /// <summary>The serving loop (completes when stopped or the stream ends).</summary>
    public Task Completion => _loop ?? Task.CompletedTask;

    /// <summary>Starts serving in the background.</summary>
    public void Start()
    {
        if (_loop is not null)
        {
            throw new InvalidOperationException("already started");
        }

        Log.Information("PMAC simulator serving {Name}", _name);
        _loop = Task.Run(() => RunAsync(_stop.Token));
    }

    /// <summary>Stops serving and closes the stream.</summary>
    public async Task StopAsync()
    {
        if (!_stop.IsCancellationRequested)
        {
            await _stop.CancelAsync().ConfigureAwait(false);
        }

        if (_loop is not null)
        {
            await _loop.ConfigureAwait(false);
        }

        await _stream.DisposeAsync().ConfigureAwait(false);
    }

    /// <inheritdoc />
    public async ValueTask DisposeAsync()
    {
        await StopAsync().ConfigureAwait(false);
        _stop.Dispose();
    }

    private async Task RunAsync(CancellationToken stop)
    {
        var port = _portFactory();
        var buffer = new byte[4096];
        var line = new List<byte>(256);
        try
        {
            while (!stop.IsCancellationRequested)
            {
                var n = await _stream.ReadAsync(buffer, stop).ConfigureAwait(false);
                if (n == 0)
                {
                    Log.Information("{Name}: end of stream", _name);
                    return;
                }

                for (var i = 0; i < n; i++)
                {
                    var b = buffer[i];
                    if (b == ReplyParser.Cr)
                    {
                        var command = Encoding.Latin1.GetString(System.Runtime.InteropServices.CollectionsMarshal.AsSpan(line));
                        line.Clear();
                        byte[] reply;
                        lock (_engineLock)
                        {
                            reply = port.Execute(command);
                        }

                        if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
                        {
                            Log.Debug("{Name} > {Command} < {Reply}", _name, command, ReplyParser.Visible(reply));
                        }
                        await _stream.WriteAsync(reply, stop).ConfigureAwait(false);
                        Interlocked.Increment(ref _commands);
                    }
                    else if (b == 0x0A)
                    {
                        // Terminals send CR LF; LF alone means nothing to the controller.
                    }
                    else if (b == 0x18)
                    {
                        line.Clear();
                        lock (_engineLock)
                        {
                            port.Flush();
                        }

                        Log.Debug("{Name} > <CTRL-X>", _name);
                    }
                    else if (b < 0x20 && b != 0x09)
                    {
                        byte[] reply;
                        lock (_engineLock)
                        {
                            reply = port.Control((char)b);
                        }

                        Log.Debug("{Name} > <CTRL-{Char}> < {Reply}", _name, (char)(b + 64), ReplyParser.Visible(reply));
                        await _stream.WriteAsync(reply, stop).ConfigureAwait(false);
                    }
                    else if (line.Count < MaxLine)
                    {
                        line.Add(b);
                    }
                }
            }
        }
        catch (OperationCanceledException) when (stop.IsCancellationRequested)
        {
        }
        catch (IOException e)
        {
            Log.Information("{Name}: {Error}", _name, e.Message);
        }
        catch (ObjectDisposedException)
        {
        }
    }
}
