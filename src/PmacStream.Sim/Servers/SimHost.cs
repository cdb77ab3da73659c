using System.Net;
using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Sim.Servers;

/// <summary>What a <see cref="SimHost"/> serves: the simulator's settings and the media it listens on.</summary>
public sealed record SimHostOptions
{
    /// <summary>The simulated controller's settings (clock speed, rotary buffer size, the *assumed* behaviour).</summary>
    public SimOptions Simulator { get; init; } = new();

    /// <summary>Ethernet (VR_PMAC packets) on this address; port 0 picks any free port; null serves no Ethernet.</summary>
    public IPEndPoint? TcpEndPoint { get; init; } = new(IPAddress.Loopback, 1025);

    /// <summary>Also serve the serial ASCII protocol on this tty or pty path (e.g. one end of a socat pair); null for none.</summary>
    public string? SerialPath { get; init; }

    /// <summary>Line settings of <see cref="SerialPath"/>.</summary>
    public SerialSettings Serial { get; init; } = new();

    /// <summary>
    /// Where the executed-move log (CSV) goes: written as moves finish (to <c>PATH.tmp</c>) and moved into place when
    /// the host stops; null for none.
    /// </summary>
    public string? ExecutedLogPath { get; init; }

    /// <summary>
    /// The Ethernet server's settings (idle timeout, client slots, reply buffer); its end point and engine lock are
    /// the host's.
    /// </summary>
    public PmacTcpServerOptions TcpServer { get; init; } = new();
}

/// <summary>
/// One simulated Turbo PMAC served over Ethernet and/or a serial line, with its clock running: what
/// <c>pmacstream sim</c> runs, and what tests or an HMI start the same way. <see cref="Start"/> brings it up,
/// <see cref="StopAsync"/> closes the servers, stops the clock and writes the executed-move log.
/// </summary>
public sealed class SimHost : IAsyncDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<SimHost>();

    // The servers share one lock so the engine sees one command at a time, whichever medium it came on.
    private readonly object _engineLock = new();
    private PmacTcpServer? _tcp;
    private PmacSerialServer? _serial;
    private SimCounters? _stopped;
    private ExecutedLogWriter? _log;

    /// <summary>Creates the simulator; nothing is served before <see cref="Start"/>.</summary>
    /// <exception cref="ArgumentException">Neither Ethernet nor a serial line is asked for.</exception>
    public SimHost(SimHostOptions options)
    {
        Options = options ?? throw new ArgumentNullException(nameof(options));
        if (options.TcpEndPoint is null && options.SerialPath is null)
        {
            throw new ArgumentException("nothing to serve: give a TCP end point and/or a serial path", nameof(options));
        }

        Simulator = new PmacSimulator(options.Simulator);
    }

    /// <summary>What this host serves.</summary>
    public SimHostOptions Options { get; }

    /// <summary>The simulated controller behind the servers.</summary>
    public PmacSimulator Simulator { get; }

    /// <summary>The bound Ethernet address (the free port chosen when 0 was asked), or null when no Ethernet is served.</summary>
    public IPEndPoint? TcpEndPoint => _tcp?.LocalEndPoint;

    /// <summary>The Ethernet server once started (its counters: clients, idle closes, evictions, dropped replies), else null.</summary>
    public PmacTcpServer? TcpServer => _tcp;

    /// <summary>
    /// True when <paramref name="endPoint"/> is reachable from other machines (not a loopback address): a PMAC port
    /// has no authentication, so whoever reaches it can move the machine.
    /// </summary>
    public static bool IsExposed(IPEndPoint endPoint)
    {
        ArgumentNullException.ThrowIfNull(endPoint);
        return !IPAddress.IsLoopback(endPoint.Address);
    }

    /// <summary>
    /// Starts the clock and the servers. A <see cref="System.Net.Sockets.SocketException"/> says the TCP address could
    /// not be bound; an <see cref="IOException"/> or <see cref="UnauthorizedAccessException"/> that the serial path
    /// could not be opened. Whatever started before the failure is stopped by <see cref="StopAsync"/>.
    /// </summary>
    public void Start()
    {
        if (_tcp is not null || _serial is not null || _stopped is not null)
        {
            throw new InvalidOperationException("the simulator host was already started");
        }

        if (Options.ExecutedLogPath is { } log)
        {
            _log = new ExecutedLogWriter(log).Attach(Simulator);
        }

        Simulator.StartClock();
        if (Options.TcpEndPoint is { } endPoint)
        {
            if (IsExposed(endPoint))
            {
                Log.Warning("serving the simulated PMAC on {EndPoint}, reachable from other machines: a PMAC port has no authentication", endPoint);
            }

            // A Turbo PMAC's Ethernet interface is one communication port shared by every connection, so a host
            // that reconnects (or a new host after a crash) can CLOSE the rotary buffer the old one opened.
            var ethernet = Simulator.OpenPort("ethernet");
            _tcp = new PmacTcpServer(() => ethernet, Options.TcpServer with { EndPoint = endPoint, EngineLock = _engineLock });
            _tcp.Start();
        }

        if (Options.SerialPath is { } path)
        {
            _serial = PmacSerialServer.OpenDevice(() => Simulator.OpenPort("serial"), path, Options.Serial, _engineLock);
            _serial.Start();
        }
    }

    /// <summary>
    /// Closes the servers, stops the clock and writes the executed-move log if one was asked for; returns the
    /// simulator's counters. A second call returns the same counters and does nothing else.
    /// </summary>
    public async Task<SimCounters> StopAsync()
    {
        if (_stopped is { } done)
        {
            return done;
        }

        if (_tcp is not null)
        {
            await _tcp.DisposeAsync().ConfigureAwait(false);
        }

        if (_serial is not null)
        {
            await _serial.DisposeAsync().ConfigureAwait(false);
        }

        Simulator.StopClock();
        var counters = Simulator.Counters;
        _stopped = counters;
        Log.Information(
            "simulator stopped: {Moves} moves executed, {Underruns} underruns, {Errors} errors, {Lines} lines received",
            counters.MovesExecuted,
            counters.Underruns,
            counters.Errors,
            counters.LinesReceived);
        _log?.Complete();
        return counters;
    }

    /// <summary>Stops (as <see cref="StopAsync"/>) and releases the simulator.</summary>
    public async ValueTask DisposeAsync()
    {
        await StopAsync().ConfigureAwait(false);
        Simulator.Dispose();
    }
}
