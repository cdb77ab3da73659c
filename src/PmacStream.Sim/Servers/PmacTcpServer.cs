using System.Net;
using System.Net.Sockets;
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

    /// <summary>
    /// A connection with no packet for this long is closed (a host that vanished without closing, e.g. behind a
    /// link that went down); <see cref="Timeout.InfiniteTimeSpan"/> keeps idle connections. *Assumed*: a Turbo
    /// PMAC's own timeout is not documented.
    /// </summary>
    public TimeSpan IdleTimeout { get; init; } = TimeSpan.FromMinutes(5);

    /// <summary>
    /// When every slot is taken, a new client is served by closing the connection idle the longest, if it has been
    /// idle at least this long; otherwise the new client is refused. Silent connections cannot lock the port.
    /// </summary>
    public TimeSpan EvictIdleAfter { get; init; } = TimeSpan.FromSeconds(2);

    /// <summary>Delay before answering GETRESPONSE and WRITEBUFFER: a slow controller, for timeout tests.</summary>
    public TimeSpan ResponseDelay { get; init; } = TimeSpan.Zero;

    /// <summary>Most clients served at once (*assumed*; see <see cref="EvictIdleAfter"/> for what happens when full).</summary>
    public int MaxClients { get; init; } = 32;

    /// <summary>
    /// Bytes of unfetched replies (SENDLINE replies never read with GETLINE) kept per connection; the oldest replies
    /// are dropped beyond it, as a controller's response buffer would overflow. *Assumed* size.
    /// </summary>
    public int MaxPendingReplyBytes { get; init; } = 16 * 1024;

    /// <summary>Lock shared with other servers of the same engine, so the engine sees one command at a time.</summary>
    public object? EngineLock { get; init; }
}

/// <summary>
/// The simulated controller's Ethernet side: the VR_PMAC packet protocol on TCP. Each client gets its own engine
/// port from the factory; the packets are parsed by <see cref="VrPmacSession"/>. Malformed or truncated packets close
/// that client's connection (logged at Warning); other clients are unaffected. Idle connections are closed after
/// <see cref="PmacTcpServerOptions.IdleTimeout"/>, and give up their slot to a new client when the server is full. Supported: GETRESPONSE, SENDLINE, GETLINE, FLUSH, READREADY, GETBUFFER, WRITEBUFFER,
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
    private readonly VrPmacCounters _counters = new();
    private int _nextClientId;
    private long _evicted;
    private long _refused;

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
    public long PacketsServed => Interlocked.Read(ref _counters.Packets);

    /// <summary>Connections closed because of a malformed or truncated packet.</summary>
    public long MalformedPackets => Interlocked.Read(ref _counters.Malformed);

    /// <summary>Connections closed after <see cref="PmacTcpServerOptions.IdleTimeout"/> without a packet.</summary>
    public long IdleClosed => Interlocked.Read(ref _counters.IdleClosed);

    /// <summary>Idle connections closed to serve a new client while the server was full.</summary>
    public long Evicted => Interlocked.Read(ref _evicted);

    /// <summary>New clients refused because every slot was taken by a client active within <see cref="PmacTcpServerOptions.EvictIdleAfter"/>.</summary>
    public long Refused => Interlocked.Read(ref _refused);

    /// <summary>Unfetched replies dropped because a connection's reply buffer was full.</summary>
    public long DroppedReplies => Interlocked.Read(ref _counters.DroppedReplies);

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
                if (_clients.Values.Count(c => !c.Evicted) >= _options.MaxClients && !EvictIdlest())
                {
                    Interlocked.Increment(ref _refused);
                    Log.Warning("refusing client {Remote}: {Max} clients already, none idle for {Seconds:0.#} s", socket.RemoteEndPoint, _options.MaxClients, _options.EvictIdleAfter.TotalSeconds);
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

    /// <summary>Closes the connection idle the longest when it has been idle long enough (under the clients lock).</summary>
    private bool EvictIdlest()
    {
        Client? idlest = null;
        foreach (var c in _clients.Values)
        {
            if (c.Evicted)
            {
                continue; // already closing: its slot frees in a moment, but another is needed now
            }

            if (idlest is null || c.LastActivity < idlest.LastActivity)
            {
                idlest = c;
            }
        }

        var idleMs = idlest is null ? 0 : Environment.TickCount64 - idlest.LastActivity;
        if (idlest is null || idleMs < _options.EvictIdleAfter.TotalMilliseconds)
        {
            return false;
        }

        idlest.Evicted = true;
        Interlocked.Increment(ref _evicted);
        Log.Warning("server full ({Max} clients): closing client {Id}, idle {Seconds:0.#} s, to serve a new one", _options.MaxClients, idlest.Id, idleMs / 1000.0);
        idlest.Socket.Close(0);
        return true;
    }

    private async Task ServeAsync(Client client)
    {
        var remote = client.Socket.RemoteEndPoint?.ToString() ?? "?";
        Log.Debug("tcp client {Id} connected from {Remote}", client.Id, remote);
        try
        {
            var port = _portFactory();
            await using var stream = new NetworkStream(client.Socket, ownsSocket: false);
            var session = new VrPmacSession(stream, port, _engineLock, _options, _counters, client.Id);
            client.Session = session;
            var end = await session.RunAsync(_stop.Token).ConfigureAwait(false);
            Log.Debug("tcp client {Id}: {End}", client.Id, end);
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

        public VrPmacSession? Session { get; set; }

        /// <summary>Closed to make room for a new client (its slot frees when its task ends).</summary>
        public bool Evicted { get; set; }

        private long Connected { get; } = Environment.TickCount64;

        public long LastActivity => Session?.LastActivity ?? Connected;
    }
}
