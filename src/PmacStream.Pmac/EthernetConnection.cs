using System.Diagnostics;
using System.Net;
using System.Net.Sockets;
using System.Text;
using Serilog;

namespace PmacStream.Pmac;

/// <summary>Options of an <see cref="EthernetConnection"/>.</summary>
public sealed record EthernetOptions
{
    /// <summary>Controller host name or address.</summary>
    public string Host { get; init; } = "127.0.0.1";

    /// <summary>TCP port (1025 on a Turbo PMAC).</summary>
    public int Port { get; init; } = 1025;

    /// <summary>Longest wait for any one reply packet; a dead link is reported within it.</summary>
    public TimeSpan Timeout { get; init; } = TimeSpan.FromSeconds(2);

    /// <summary>Longest wait for the TCP connection.</summary>
    public TimeSpan ConnectTimeout { get; init; } = TimeSpan.FromSeconds(3);

    /// <summary>Reconnect automatically on the next request after the link failed (the failed request still throws).</summary>
    public bool AutoReconnect { get; init; } = true;

    /// <summary>Data bytes per WRITEBUFFER packet (at most 1024).</summary>
    public int WriteBufferBytes { get; init; } = VrPmac.MaxWriteBuffer;

    /// <summary>
    /// With several WRITEBUFFER packets in flight: how long the last reply may be late before a READREADY probe is
    /// sent. The probe's reply, arriving after a lost one, gets the controller's TCP stack to resend the lost reply at
    /// once (selective ACKs) instead of after its retransmission timeout (200 ms or more). READREADY only reads
    /// whether a reply is waiting: it changes nothing on the controller.
    /// </summary>
    public TimeSpan ProbeAfter { get; init; } = TimeSpan.FromMilliseconds(20);

    /// <summary>Most READREADY probes one pipelined download sends (0: none).</summary>
    public int MaxProbes { get; init; } = 4;
}

/// <summary>
/// A Turbo PMAC over Ethernet (TCP 1025, VR_PMAC packets). Commands go through GETRESPONSE and continue with
/// READREADY/GETBUFFER past 1400 bytes; downloads go through WRITEBUFFER batches. Any timeout, I/O failure or
/// cancellation in the middle of an exchange resets the connection (its state is unknown, and nothing it still holds
/// to send may reach the controller later) and throws; the next request reconnects when
/// <see cref="EthernetOptions.AutoReconnect"/> is set.
/// </summary>
public sealed class EthernetConnection : IPmacConnection
{
    private static readonly ILogger Log = Serilog.Log.ForContext<EthernetConnection>();
    private readonly EthernetOptions _options;
    private readonly SemaphoreSlim _gate = new(1, 1);
    private readonly byte[] _send = new byte[VrPmac.HeaderSize + VrPmac.MaxData];
    private readonly byte[] _receive = new byte[VrPmac.MaxData + 64];
    private readonly byte[] _reply = new byte[VrPmac.MaxReply];
    private Socket? _socket;
    private bool _everConnected;
    private bool _disposed;

    /// <summary>Creates the connection; nothing is opened until <see cref="ConnectAsync"/> or the first request.</summary>
    public EthernetConnection(EthernetOptions options)
    {
        ArgumentNullException.ThrowIfNull(options);
        if (options.WriteBufferBytes is < 2 or > VrPmac.MaxWriteBuffer)
        {
            throw new ArgumentOutOfRangeException(nameof(options), $"WriteBufferBytes must be 2..{VrPmac.MaxWriteBuffer}");
        }

        _options = options;
        Description = $"tcp {options.Host}:{options.Port}";
    }

    /// <summary>Creates a connection to <paramref name="host"/>:<paramref name="port"/> with default options.</summary>
    public EthernetConnection(string host, int port = 1025)
        : this(new EthernetOptions { Host = host, Port = port })
    {
    }

    /// <inheritdoc />
    public string Description { get; }

    /// <summary>True while the socket is open.</summary>
    public bool IsConnected => _socket is not null;

    /// <summary>Opens the TCP connection (closing any previous one).</summary>
    public async Task ConnectAsync(CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            await ConnectCoreAsync(cancellationToken).ConfigureAwait(false);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <summary>Drops the link and connects again (after a controller reset or a failure).</summary>
    public Task ReconnectAsync(CancellationToken cancellationToken = default) => ConnectAsync(cancellationToken);

    /// <inheritdoc />
    public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(command);
        var raw = await ExchangeAsync(command, (socket, ct) => GetResponseCoreAsync(socket, command, ct), cancellationToken).ConfigureAwait(false);
        return ReplyParser.Parse(raw, command);
    }

    /// <inheritdoc />
    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(lines);
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var socket = await EnsureConnectedAsync(cancellationToken).ConfigureAwait(false);
            var sw = Stopwatch.StartNew();
            var index = 0;
            var packets = 0;
            while (index < lines.Count)
            {
                // Pack as many whole NUL-terminated lines as fit; the controller stops at the first refused line of a
                // packet and we send nothing more, so no line after a refusal is ever executed.
                var start = index;
                var length = PackPacket(lines, ref index);
                var status = await RunGuardedAsync(
                    async ct =>
                    {
                        await SendAsync(socket, VrPmac.HeaderSize + length, ct).ConfigureAwait(false);
                        await ReceiveExactlyAsync(socket, 4, ct).ConfigureAwait(false);
                        return _receive.AsSpan(0, 4).ToArray();
                    },
                    "WRITEBUFFER",
                    cancellationToken).ConfigureAwait(false);
                packets++;
                if (VrPmac.TryReadWriteBufferError(status, out var err, out var lineInPacket))
                {
                    var failing = start + Math.Min(lineInPacket, index - start - 1);
                    Log.Debug("{Device} WRITEBUFFER refused line {Index}: {Line} -> ERR{Number:000} ({Ms:0.000} ms)", Description, failing, lines[failing], err, sw.Elapsed.TotalMilliseconds);
                    throw new PmacErrorException(err, lines[failing], failing);
                }

                if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
                {
                    Log.Debug("{Device} WRITEBUFFER lines {First}..{Last} ({Bytes} bytes) accepted", Description, start, index - 1, length);
                }
            }

            Log.Debug("{Device} downloaded {Count} lines in {Packets} packets ({Ms:0.000} ms)", Description, lines.Count, packets, sw.Elapsed.TotalMilliseconds);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public async Task DownloadAsync(IReadOnlyList<string> lines, int packetsInFlight, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(lines);
        if (packetsInFlight <= 1)
        {
            await DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
            return;
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var socket = await EnsureConnectedAsync(cancellationToken).ConfigureAwait(false);
            var sw = Stopwatch.StartNew();
            var run = new PipelinedDownload(lines.Count, packetsInFlight, _options.MaxProbes);
            while (!run.Finished)
            {
                // Each reply has the whole reply timeout, as with one packet in flight.
                await RunGuardedAsync(
                    async ct =>
                    {
                        await FillWindowAsync(socket, lines, run, ct).ConfigureAwait(false);
                        await ReceiveNextAsync(socket, run, ct).ConfigureAwait(false);
                        return 0;
                    },
                    "WRITEBUFFER",
                    cancellationToken).ConfigureAwait(false);
            }

            Log.Debug("{Device} downloaded {Count} lines in {Packets} packets, up to {Window} in flight, {Probes} probes ({Ms:0.000} ms)", Description, lines.Count, run.Packets, packetsInFlight, run.ProbesSent, sw.Elapsed.TotalMilliseconds);
            if (run.Refusal is { } r)
            {
                Log.Debug("{Device} WRITEBUFFER refused line {Index}: {Line} -> ERR{Number:000}; {After} lines of later packets stored after it", Description, r.Line, lines[r.Line], r.Number, run.StoredAfterGap);
                throw new PmacErrorException(r.Number, lines[r.Line], r.Line) { LinesStoredAfterGap = run.StoredAfterGap };
            }
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public Task FlushAsync(CancellationToken cancellationToken = default) =>
        ExchangeAsync(
            "<FLUSH>",
            async (socket, ct) =>
            {
                VrPmac.WriteHeader(_send, VrPmac.Download, VrPmac.Flush, 0, 0, 0);
                await SendAsync(socket, VrPmac.HeaderSize, ct).ConfigureAwait(false);
                await ReceiveExactlyAsync(socket, 1, ct).ConfigureAwait(false);
                return Array.Empty<byte>();
            },
            cancellationToken);

    /// <inheritdoc />
    public async Task<string> ControlAsync(char control, CancellationToken cancellationToken = default)
    {
        var raw = await ExchangeAsync(
            $"<CTRL-{(char)(control + 64)}>",
            async (socket, ct) =>
            {
                // wValue big-endian puts the character in the second header byte; servers accept either byte.
                VrPmac.WriteHeader(_send, VrPmac.Upload, VrPmac.CtrlResponse, control, 0, 0);
                await SendAsync(socket, VrPmac.HeaderSize, ct).ConfigureAwait(false);
                var n = await ReceiveSomeAsync(socket, 0, ct).ConfigureAwait(false);

                // The reply has no terminator: take what arrived plus anything already queued behind it.
                while (socket.Available > 0 && n < _receive.Length)
                {
                    n += await ReceiveSomeAsync(socket, n, ct).ConfigureAwait(false);
                }

                return _receive.AsSpan(0, n).ToArray();
            },
            cancellationToken).ConfigureAwait(false);
        return Encoding.ASCII.GetString(raw).TrimEnd('\0');
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
            CloseSocket();
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <summary>Packs whole NUL-terminated lines from <paramref name="index"/> into <c>_send</c>; returns the data length.</summary>
    private int PackPacket(IReadOnlyList<string> lines, ref int index)
    {
        var length = 0;
        var data = _send.AsSpan(VrPmac.HeaderSize);
        while (index < lines.Count)
        {
            var line = lines[index];
            if (line.Length + 1 > _options.WriteBufferBytes)
            {
                throw new ArgumentException($"line {index} is {line.Length} characters, longer than a WRITEBUFFER packet allows", nameof(lines));
            }

            if (length + line.Length + 1 > _options.WriteBufferBytes)
            {
                break;
            }

            length += Encoding.ASCII.GetBytes(line, data[length..]);
            data[length++] = 0;
            index++;
        }

        VrPmac.WriteHeader(_send, VrPmac.Download, VrPmac.WriteBuffer, 0, 0, (ushort)length);
        return length;
    }

    /// <summary>Sends packets until the window is full, everything is sent, or a refusal came back (nothing more goes then).</summary>
    private async Task FillWindowAsync(Socket socket, IReadOnlyList<string> lines, PipelinedDownload run, CancellationToken ct)
    {
        while (run.MaySend)
        {
            var start = run.NextLine;
            var index = start;
            var length = PackPacket(lines, ref index);
            await SendAsync(socket, VrPmac.HeaderSize + length, ct).ConfigureAwait(false);
            run.Sent(start, index);
        }
    }

    /// <summary>
    /// Reads the oldest reply in flight (a probe's 2 bytes, or a packet's 4-byte status). While a packet's reply is late
    /// and nothing more can be sent, probes with READREADY so a lost reply is resent at once (see <see cref="EthernetOptions.ProbeAfter"/>).
    /// </summary>
    private async Task ReceiveNextAsync(Socket socket, PipelinedDownload run, CancellationToken ct)
    {
        if (run.HeadIsProbe)
        {
            await ReceiveExactlyAsync(socket, 2, ct).ConfigureAwait(false);
            run.Received(default);
            return;
        }

        var receive = ReceiveExactlyAsync(socket, 4, ct);
        using var stopDelays = CancellationTokenSource.CreateLinkedTokenSource(ct);
        var wait = _options.ProbeAfter;
        while (!receive.IsCompleted && run.MayProbe && wait > TimeSpan.Zero)
        {
            var delay = Task.Delay(wait, stopDelays.Token);
            if (await Task.WhenAny(receive, delay).ConfigureAwait(false) == receive)
            {
                break;
            }

            VrPmac.WriteHeader(_send, VrPmac.Upload, VrPmac.ReadReady, 0, 0, 2);
            await SendAsync(socket, VrPmac.HeaderSize, ct).ConfigureAwait(false);
            run.Probed();
            wait *= 2;
        }

        await stopDelays.CancelAsync().ConfigureAwait(false);
        await receive.ConfigureAwait(false);
        run.Received(_receive.AsSpan(0, 4));
    }

    private async Task<byte[]> ExchangeAsync(string what, Func<Socket, CancellationToken, Task<byte[]>> exchange, CancellationToken cancellationToken)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var socket = await EnsureConnectedAsync(cancellationToken).ConfigureAwait(false);
            var sw = Stopwatch.StartNew();
            var raw = await RunGuardedAsync(ct => exchange(socket, ct), what, cancellationToken).ConfigureAwait(false);
            if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
            {
                Log.Debug("{Device} > {Command} < {Reply} ({Ms:0.000} ms)", Description, what, ReplyParser.Visible(raw), sw.Elapsed.TotalMilliseconds);
            }
            return raw;
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <summary>
    /// Runs one exchange under the reply timeout; any failure aborts the socket (a reset, see <see cref="AbortSocket"/>),
    /// so a request whose reply was not seen is never delivered later.
    /// </summary>
    private async Task<T> RunGuardedAsync<T>(Func<CancellationToken, Task<T>> body, string what, CancellationToken cancellationToken)
    {
        using var timeout = CancellationTokenSource.CreateLinkedTokenSource(cancellationToken);
        timeout.CancelAfter(_options.Timeout);
        try
        {
            return await body(timeout.Token).ConfigureAwait(false);
        }
        catch (OperationCanceledException) when (!cancellationToken.IsCancellationRequested)
        {
            AbortSocket();
            Log.Debug("{Device} {What}: no reply within {Timeout}", Description, what, _options.Timeout);
            throw new PmacLinkException($"{Description}: no reply to '{what}' within {_options.Timeout.TotalMilliseconds:0} ms");
        }
        catch (OperationCanceledException)
        {
            AbortSocket();
            throw;
        }
        catch (Exception e) when (e is SocketException or IOException or ObjectDisposedException)
        {
            AbortSocket();
            Log.Debug("{Device} {What}: link failed: {Error}", Description, what, e.Message);
            throw new PmacLinkException($"{Description}: link failed during '{what}': {e.Message}", e);
        }
    }

    private async Task<byte[]> GetResponseCoreAsync(Socket socket, string command, CancellationToken ct)
    {
        var bytes = Encoding.ASCII.GetByteCount(command);
        if (bytes > VrPmac.MaxData)
        {
            throw new ArgumentException($"command is {bytes} bytes, more than one packet holds", nameof(command));
        }

        Encoding.ASCII.GetBytes(command, _send.AsSpan(VrPmac.HeaderSize));
        VrPmac.WriteHeader(_send, VrPmac.Download, VrPmac.GetResponse, 0, 0, (ushort)bytes);
        await SendAsync(socket, VrPmac.HeaderSize + bytes, ct).ConfigureAwait(false);
        var reply = new List<byte>();
        var n = await ReceiveReplyAsync(socket, ct).ConfigureAwait(false);
        reply.AddRange(_reply.AsSpan(0, n));
        while (VrPmac.ReplyLength(System.Runtime.InteropServices.CollectionsMarshal.AsSpan(reply)) < 0)
        {
            // A full 1400-byte packet without a terminator: the rest waits in the controller.
            VrPmac.WriteHeader(_send, VrPmac.Upload, VrPmac.ReadReady, 0, 0, 2);
            await SendAsync(socket, VrPmac.HeaderSize, ct).ConfigureAwait(false);
            await ReceiveExactlyAsync(socket, 2, ct).ConfigureAwait(false);
            if (_receive[0] == 0)
            {
                await Task.Delay(1, ct).ConfigureAwait(false);
                continue;
            }

            VrPmac.WriteHeader(_send, VrPmac.Upload, VrPmac.GetBuffer, 0, 0, VrPmac.MaxReply);
            await SendAsync(socket, VrPmac.HeaderSize, ct).ConfigureAwait(false);
            n = await ReceiveReplyAsync(socket, ct).ConfigureAwait(false);
            reply.AddRange(_reply.AsSpan(0, n));
        }

        return [.. reply];
    }

    /// <summary>Reads one reply packet: until its terminator or 1400 bytes.</summary>
    private async Task<int> ReceiveReplyAsync(Socket socket, CancellationToken ct)
    {
        var n = 0;
        while (n < VrPmac.MaxReply)
        {
            var got = await socket.ReceiveAsync(_reply.AsMemory(n, VrPmac.MaxReply - n), SocketFlags.None, ct).ConfigureAwait(false);
            if (got == 0)
            {
                throw new IOException("the controller closed the connection");
            }

            n += got;
            if (VrPmac.ReplyLength(_reply.AsSpan(0, n)) >= 0)
            {
                break;
            }
        }

        return n;
    }

    private async Task<int> ReceiveSomeAsync(Socket socket, int offset, CancellationToken ct)
    {
        var got = await socket.ReceiveAsync(_receive.AsMemory(offset), SocketFlags.None, ct).ConfigureAwait(false);
        if (got == 0)
        {
            throw new IOException("the controller closed the connection");
        }

        return got;
    }

    private async Task ReceiveExactlyAsync(Socket socket, int count, CancellationToken ct)
    {
        var n = 0;
        while (n < count)
        {
            var got = await socket.ReceiveAsync(_receive.AsMemory(n, count - n), SocketFlags.None, ct).ConfigureAwait(false);
            if (got == 0)
            {
                throw new IOException("the controller closed the connection");
            }

            n += got;
        }
    }

    private async Task SendAsync(Socket socket, int count, CancellationToken ct)
    {
        var sent = 0;
        while (sent < count)
        {
            sent += await socket.SendAsync(_send.AsMemory(sent, count - sent), SocketFlags.None, ct).ConfigureAwait(false);
        }
    }

    private async Task<Socket> EnsureConnectedAsync(CancellationToken cancellationToken)
    {
        ObjectDisposedException.ThrowIf(_disposed, this);
        if (_socket is { } s)
        {
            return s;
        }

        if (_everConnected && !_options.AutoReconnect)
        {
            throw new PmacLinkException($"{Description}: the link is down (call ReconnectAsync)");
        }

        return await ConnectCoreAsync(cancellationToken).ConfigureAwait(false);
    }

    private async Task<Socket> ConnectCoreAsync(CancellationToken cancellationToken)
    {
        ObjectDisposedException.ThrowIf(_disposed, this);
        CloseSocket();
        var sw = Stopwatch.StartNew();
        var socket = new Socket(SocketType.Stream, ProtocolType.Tcp) { NoDelay = true };
        LossyLinkSocket.Tune(socket);
        using var timeout = CancellationTokenSource.CreateLinkedTokenSource(cancellationToken);
        timeout.CancelAfter(_options.ConnectTimeout);
        try
        {
            if (IPAddress.TryParse(_options.Host, out var address))
            {
                await socket.ConnectAsync(new IPEndPoint(address, _options.Port), timeout.Token).ConfigureAwait(false);
            }
            else
            {
                await socket.ConnectAsync(_options.Host, _options.Port, timeout.Token).ConfigureAwait(false);
            }
        }
        catch (OperationCanceledException) when (!cancellationToken.IsCancellationRequested)
        {
            socket.Dispose();
            throw new PmacLinkException($"{Description}: no connection within {_options.ConnectTimeout.TotalMilliseconds:0} ms");
        }
        catch (SocketException e)
        {
            socket.Dispose();
            throw new PmacLinkException($"{Description}: cannot connect: {e.Message}", e);
        }
        catch
        {
            socket.Dispose();
            throw;
        }

        _socket = socket;
        _everConnected = true;
        Log.Debug("{Device} connected ({Ms:0.000} ms)", Description, sw.Elapsed.TotalMilliseconds);
        return socket;
    }

    /// <summary>
    /// Drops the connection with a reset instead of a close: the kernel discards what it still holds to send. After a
    /// timeout in a link outage that is the request the host gave up on (a WRITEBUFFER of program lines, a command);
    /// closed gracefully, the kernel would go on retransmitting it once the link is back, and the controller would
    /// store it after a resume had already sent those lines again on a new connection.
    /// </summary>
    private void AbortSocket()
    {
        if (_socket is { } s)
        {
            _socket = null;
            try
            {
                s.LingerState = new LingerOption(true, 0);
            }
            catch (SocketException)
            {
                // Already gone.
            }

            s.Dispose();
        }
    }

    private void CloseSocket()
    {
        if (_socket is { } s)
        {
            _socket = null;
            try
            {
                s.Shutdown(SocketShutdown.Both);
            }
            catch (SocketException)
            {
                // Already gone.
            }

            s.Dispose();
        }
    }
}
