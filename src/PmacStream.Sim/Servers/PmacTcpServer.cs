using System.Buffers.Binary;
using System.Net;
using System.Net.Sockets;
using System.Text;
using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Sim.Servers;

/// <summary>Options of a <see cref="PmacTcpServer"/>.</summary>
public sealed record PmacTcpServerOptions
{
    /// <summary>Address and port to listen on; port 0 picks any free port (see <see cref="PmacTcpServer.Port"/>).</summary>
    public IPEndPoint EndPoint { get; init; } = new(IPAddress.Loopback, 1025);

    /// <summary>How long a client may take to send the rest of a packet it started; then it is disconnected.</summary>
    public TimeSpan PacketTimeout { get; init; } = TimeSpan.FromSeconds(5);

    /// <summary>Delay before answering GETRESPONSE and WRITEBUFFER: a slow controller, for timeout tests.</summary>
    public TimeSpan ResponseDelay { get; init; } = TimeSpan.Zero;

    /// <summary>Most clients served at once; more are refused (closed at once).</summary>
    public int MaxClients { get; init; } = 32;

    /// <summary>Lock shared with other servers of the same engine, so the engine sees one command at a time.</summary>
    public object? EngineLock { get; init; }
}

/// <summary>
/// The simulated controller's Ethernet side: the VR_PMAC packet protocol on TCP. Each client gets its own engine
/// port from the factory. Malformed or truncated packets close that client's connection (logged at Warning); other
/// clients are unaffected. Supported: GETRESPONSE, SENDLINE, GETLINE, FLUSH, READREADY, GETBUFFER, WRITEBUFFER,
/// CTRL_RESPONSE. Empty replies (nothing pending, no control answer) are one NUL byte, since TCP cannot carry none.
/// </summary>
public sealed class PmacTcpServer : IAsyncDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacTcpServer>();
    private readonly Func<IPmacPortEndpoint> _portFactory;
    private readonly PmacTcpServerOptions _options;
    private readonly object _engineLock;
    private readonly CancellationTokenSource _stop = new();
    private readonly Dictionary<int, Client> _clients = [];
    private Socket? _listener;
    private Task? _acceptLoop;
    private int _nextClientId;
    private long _packets;
    private long _malformed;

    /// <summary>Creates the server; <see cref="Start"/> binds it.</summary>
    public PmacTcpServer(Func<IPmacPortEndpoint> portFactory, PmacTcpServerOptions? options = null)
    {
        _portFactory = portFactory ?? throw new ArgumentNullException(nameof(portFactory));
        _options = options ?? new PmacTcpServerOptions();
        _engineLock = _options.EngineLock ?? new object();
    }

    /// <summary>The bound address (after <see cref="Start"/>).</summary>
    public IPEndPoint LocalEndPoint => (IPEndPoint?)_listener?.LocalEndPoint ?? throw new InvalidOperationException("the server is not started");

    /// <summary>The bound port (the free port chosen when 0 was asked).</summary>
    public int Port => LocalEndPoint.Port;

    /// <summary>Clients connected now.</summary>
    public int ClientCount
    {
        get
        {
            lock (_clients)
            {
                return _clients.Count;
            }
        }
    }

    /// <summary>Packets answered since start.</summary>
    public long PacketsServed => Interlocked.Read(ref _packets);

    /// <summary>Connections closed because of a malformed or truncated packet.</summary>
    public long MalformedPackets => Interlocked.Read(ref _malformed);

    /// <summary>Binds and starts accepting clients.</summary>
    public void Start()
    {
        if (_listener is not null)
        {
            throw new InvalidOperationException("already started");
        }

        var listener = new Socket(_options.EndPoint.AddressFamily, SocketType.Stream, ProtocolType.Tcp);
        try
        {
            listener.Bind(_options.EndPoint);
            listener.Listen(64);
        }
        catch
        {
            listener.Dispose();
            throw;
        }

        _listener = listener;
        Log.Information("PMAC simulator listening on tcp {EndPoint}", LocalEndPoint);
        _acceptLoop = Task.Run(AcceptLoopAsync);
    }

    /// <summary>Closes every client connection now (a dropped link, for tests); the server keeps listening.</summary>
    public void DisconnectAll()
    {
        lock (_clients)
        {
            foreach (var c in _clients.Values)
            {
                c.Socket.Close(0);
            }
        }
    }

    /// <summary>Stops listening and closes all clients.</summary>
    public async Task StopAsync()
    {
        if (_stop.IsCancellationRequested)
        {
            return;
        }

        await _stop.CancelAsync().ConfigureAwait(false);
        _listener?.Dispose();
        Task[] handlers;
        lock (_clients)
        {
            handlers = [.. _clients.Values.Select(c => c.Task)];
            foreach (var c in _clients.Values)
            {
                c.Socket.Close(0);
            }
        }

        if (_acceptLoop is not null)
        {
            await _acceptLoop.ConfigureAwait(false);
        }

        await Task.WhenAll(handlers).ConfigureAwait(false);
        Log.Information("PMAC simulator tcp server stopped ({Packets} packets served)", PacketsServed);
    }

    /// <inheritdoc />
    public async ValueTask DisposeAsync()
    {
        await StopAsync().ConfigureAwait(false);
        _stop.Dispose();
    }

    private async Task AcceptLoopAsync()
    {
        while (!_stop.IsCancellationRequested)
        {
            Socket socket;
            try
            {
                socket = await _listener!.AcceptAsync(_stop.Token).ConfigureAwait(false);
            }
            catch (Exception e) when (e is OperationCanceledException or ObjectDisposedException or SocketException)
            {
                if (_stop.IsCancellationRequested)
                {
                    return;
                }

                Log.Warning("accept failed: {Error}", e.Message);
                continue;
            }

            socket.NoDelay = true;
            lock (_clients)
            {
                if (_clients.Count >= _options.MaxClients)
                {
                    Log.Warning("refusing client {Remote}: {Max} clients already", socket.RemoteEndPoint, _options.MaxClients);
                    socket.Close(0);
                    continue;
                }

                var id = ++_nextClientId;
                var client = new Client(id, socket);
                _clients[id] = client;
                client.Task = Task.Run(() => ServeAsync(client));
            }
        }
    }

    private async Task ServeAsync(Client client)
    {
        var remote = client.Socket.RemoteEndPoint?.ToString() ?? "?";
        Log.Debug("tcp client {Id} connected from {Remote}", client.Id, remote);
        try
        {
            var port = _portFactory();
            var session = new Session(this, client.Socket, port, client.Id);
            await session.RunAsync(_stop.Token).ConfigureAwait(false);
        }
        catch (Exception e) when (e is OperationCanceledException or ObjectDisposedException or SocketException or IOException)
        {
            // The client went away or the server stops.
        }
        catch (Exception e)
        {
            // A bug in a handler or the engine must not take down the server: drop this client only.
            Log.Error(e, "tcp client {Id}: unexpected failure, connection closed", client.Id);
        }
        finally
        {
            client.Socket.Dispose();
            lock (_clients)
            {
                _clients.Remove(client.Id);
            }

            Log.Debug("tcp client {Id} disconnected", client.Id);
        }
    }

    private sealed class Client(int id, Socket socket)
    {
        public int Id { get; } = id;

        public Socket Socket { get; } = socket;

        public Task Task { get; set; } = Task.CompletedTask;
    }

    /// <summary>One client's protocol state: its engine port and the reply bytes not yet fetched.</summary>
    private sealed class Session(PmacTcpServer server, Socket socket, IPmacPortEndpoint port, int id)
    {
        private readonly byte[] _header = new byte[VrPmac.HeaderSize];
        private readonly byte[] _data = new byte[VrPmac.MaxData];
        private readonly List<byte> _pending = [];
        private readonly byte[] _out = new byte[VrPmac.MaxReply + 8];

        public async Task RunAsync(CancellationToken stop)
        {
            while (true)
            {
                if (!await ReadPacketPartAsync(_header, VrPmac.HeaderSize, stop, first: true).ConfigureAwait(false))
                {
                    return;
                }

                var type = _header[0];
                var request = _header[1];
                var wValue = BinaryPrimitives.ReadUInt16BigEndian(_header.AsSpan(2));
                var wLength = BinaryPrimitives.ReadUInt16BigEndian(_header.AsSpan(6));
                if (type != VrPmac.Download && type != VrPmac.Upload)
                {
                    Malformed($"request type 0x{type:X2}");
                    return;
                }

                var length = 0;
                if (type == VrPmac.Download)
                {
                    if (wLength > VrPmac.MaxData)
                    {
                        Malformed($"wLength {wLength} > {VrPmac.MaxData}");
                        return;
                    }

                    length = wLength;
                    if (length > 0 && !await ReadPacketPartAsync(_data, length, stop, first: false).ConfigureAwait(false))
                    {
                        return;
                    }
                }

                if (!await HandleAsync(type, request, wValue, length, stop).ConfigureAwait(false))
                {
                    return;
                }

                Interlocked.Increment(ref server._packets);
            }
        }

        private async Task<bool> HandleAsync(byte type, byte request, ushort wValue, int length, CancellationToken stop)
        {
            switch (request)
            {
                case VrPmac.GetResponse when type == VrPmac.Download:
                    {
                        var command = Command(_data.AsSpan(0, length));
                        await DelayAsync(stop).ConfigureAwait(false);
                        var reply = Execute(command);
                        _pending.Clear();
                        _pending.AddRange(reply);
                        await SendPendingReplyAsync(stop).ConfigureAwait(false);
                        return true;
                    }

                case VrPmac.SendLine when type == VrPmac.Download:
                    _pending.AddRange(Execute(Command(_data.AsSpan(0, length))));
                    await SendAsync(new byte[] { request }, stop).ConfigureAwait(false);
                    return true;

                case VrPmac.GetLine:
                case VrPmac.GetBuffer:
                    await SendPendingReplyAsync(stop).ConfigureAwait(false);
                    return true;

                case VrPmac.ReadReady:
                    await SendAsync(new byte[] { _pending.Count > 0 ? (byte)1 : (byte)0, 0 }, stop).ConfigureAwait(false);
                    return true;

                case VrPmac.Flush:
                    lock (server._engineLock)
                    {
                        port.Flush();
                    }

                    _pending.Clear();
                    Log.Debug("tcp {Id} > <FLUSH>", id);
                    await SendAsync(new byte[] { request }, stop).ConfigureAwait(false);
                    return true;

                case VrPmac.CtrlResponse:
                    {
                        // Drivers disagree on wValue's byte order: take the character from whichever byte holds it.
                        var c = (char)((wValue >> 8) != 0 ? wValue >> 8 : wValue & 0xFF);
                        byte[] reply;
                        lock (server._engineLock)
                        {
                            reply = c == 0 ? [] : port.Control(c);
                        }

                        Log.Debug("tcp {Id} > <CTRL-{Char}> < {Reply}", id, (char)(c + 64), ReplyParser.Visible(reply));
                        var n = Math.Min(reply.Length, VrPmac.MaxReply);
                        await SendAsync(n == 0 ? new byte[] { 0 } : reply.AsMemory(0, n), stop).ConfigureAwait(false);
                        return true;
                    }

                case VrPmac.WriteBuffer when type == VrPmac.Download:
                    await DelayAsync(stop).ConfigureAwait(false);
                    WriteBuffer(length);
                    await SendAsync(_out.AsMemory(0, 4), stop).ConfigureAwait(false);
                    return true;

                default:
                    Malformed($"unsupported request 0x{type:X2}/0x{request:X2}");
                    return false;
            }
        }

        private void WriteBuffer(int length)
        {
            if (length > VrPmac.MaxWriteBuffer)
            {
                Log.Warning("tcp {Id}: WRITEBUFFER of {Length} bytes refused (at most {Max})", id, length, VrPmac.MaxWriteBuffer);
                VrPmac.WriteBufferStatus(_out, PmacErrors.UnknownCommand, 0);
                return;
            }

            var data = _data.AsSpan(0, length);
            var line = 0;
            while (!data.IsEmpty)
            {
                var nul = data.IndexOf((byte)0);
                var text = nul >= 0 ? data[..nul] : data;
                data = nul >= 0 ? data[(nul + 1)..] : [];
                var reply = Execute(Command(text), quiet: true);
                if (Array.IndexOf(reply, ReplyParser.Bel) >= 0)
                {
                    var number = ErrorNumber(reply);
                    Log.Debug("tcp {Id} WRITEBUFFER line {Line} refused: ERR{Number:000}", id, line, number);
                    VrPmac.WriteBufferStatus(_out, number, line);
                    return;
                }

                line++;
            }

            Log.Debug("tcp {Id} WRITEBUFFER {Lines} lines accepted", id, line);
            VrPmac.WriteBufferStatus(_out, 0, 0);
        }

        private byte[] Execute(string command, bool quiet = false)
        {
            byte[] reply;
            lock (server._engineLock)
            {
                reply = port.Execute(command);
            }

            if (!quiet && Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
            {
                Log.Debug("tcp {Id} > {Command} < {Reply}", id, command, ReplyParser.Visible(reply));
            }

            return reply;
        }

        /// <summary>Sends the first reply waiting in <see cref="_pending"/> by the controller's termination rules, at most 1400 bytes.</summary>
        private Task SendPendingReplyAsync(CancellationToken stop)
        {
            if (_pending.Count == 0)
            {
                return SendAsync(new byte[] { 0 }, stop);
            }

            var span = System.Runtime.InteropServices.CollectionsMarshal.AsSpan(_pending);
            var n = VrPmac.ReplyLength(span);
            n = n < 0 ? span.Length : n;
            n = Math.Min(n, VrPmac.MaxReply);
            span[..n].CopyTo(_out);
            _pending.RemoveRange(0, n);
            return SendAsync(_out.AsMemory(0, n), stop);
        }

        private async Task SendAsync(ReadOnlyMemory<byte> bytes, CancellationToken stop)
        {
            while (!bytes.IsEmpty)
            {
                var n = await socket.SendAsync(bytes, SocketFlags.None, stop).ConfigureAwait(false);
                bytes = bytes[n..];
            }
        }

        private Task DelayAsync(CancellationToken stop) =>
            server._options.ResponseDelay > TimeSpan.Zero ? Task.Delay(server._options.ResponseDelay, stop) : Task.CompletedTask;

        /// <summary>
        /// Reads <paramref name="count"/> bytes. The first byte of a packet may take forever (an idle client); once a
        /// packet has started, the rest must come within the packet timeout. False on a clean close between packets
        /// or on a truncated packet (already counted as malformed).
        /// </summary>
        private async Task<bool> ReadPacketPartAsync(byte[] buffer, int count, CancellationToken stop, bool first)
        {
            var n = 0;
            if (first)
            {
                n = await socket.ReceiveAsync(buffer.AsMemory(0, count), SocketFlags.None, stop).ConfigureAwait(false);
                if (n == 0)
                {
                    return false;
                }
            }

            using var timeout = CancellationTokenSource.CreateLinkedTokenSource(stop);
            timeout.CancelAfter(server._options.PacketTimeout);
            while (n < count)
            {
                int got;
                try
                {
                    got = await socket.ReceiveAsync(buffer.AsMemory(n, count - n), SocketFlags.None, timeout.Token).ConfigureAwait(false);
                }
                catch (OperationCanceledException) when (!stop.IsCancellationRequested)
                {
                    got = 0;
                }

                if (got == 0)
                {
                    Malformed("packet truncated");
                    return false;
                }

                n += got;
            }

            return true;
        }

        private void Malformed(string why)
        {
            Interlocked.Increment(ref server._malformed);
            Log.Warning("tcp client {Id}: {Why}; connection closed", id, why);
        }

        private static string Command(ReadOnlySpan<byte> data)
        {
            // Hosts may or may not end the command with CR or NUL; the controller ignores them.
            while (!data.IsEmpty && (data[^1] == ReplyParser.Cr || data[^1] == 0 || data[^1] == 0x0A))
            {
                data = data[..^1];
            }

            return Encoding.Latin1.GetString(data);
        }

        private static int ErrorNumber(byte[] reply)
        {
            var text = Encoding.ASCII.GetString(reply);
            var i = text.IndexOf("ERR", StringComparison.Ordinal);
            if (i >= 0 && i + 6 <= text.Length && int.TryParse(text.AsSpan(i + 3, 3), out var n))
            {
                return n;
            }

            return PmacErrors.UnknownCommand;
        }
    }
}
