using PmacStream.Pmac;

namespace PmacStream.Jobs;

/// <summary>
/// The built-in simulated controller as its host hands it to the job service (Core does not know the simulator
/// itself): a connection to it and its clock.
/// </summary>
/// <param name="Connection">A port of the simulator.</param>
/// <param name="Time">The simulator's clock, so sessions measure and checkpoint in machine time.</param>
public sealed record SimulatorLink(IPmacConnection Connection, TimeProvider Time)
{
    /// <summary>Advances the simulator's clock by a tick's virtual time, when the job's tick loop steps it; null when it runs on its own clock.</summary>
    public Action<TimeSpan>? Step { get; init; }

    /// <summary>Virtual seconds per real second of a stepped clock (1 otherwise).</summary>
    public double ClockFactor { get; init; } = 1;

    /// <summary>True when the simulator was made for this link: it cannot hold an earlier job, so a resume restarts.</summary>
    public bool Fresh { get; init; }
}

/// <summary>
/// An open controller: the link it was opened with, the connection, and the one PComm-style device facade
/// (<see cref="PmacDevices"/>, device 0) every download of every face goes through.
/// </summary>
public sealed class ControllerLink : IAsyncDisposable
{
    /// <summary>Wraps an open connection (<paramref name="simulator"/> when it is the built-in simulator).</summary>
    public ControllerLink(ConnectionSpec spec, IPmacConnection connection, SimulatorLink? simulator = null)
    {
        ArgumentNullException.ThrowIfNull(spec);
        ArgumentNullException.ThrowIfNull(connection);
        Spec = spec;
        Connection = connection;
        Simulator = simulator;
        Devices = PmacDevices.Of(0, connection);
    }

    /// <summary>Where the controller is, as the job record keeps it (<c>pmacstream resume</c> reopens it).</summary>
    public ConnectionSpec Spec { get; }

    /// <summary>The connection.</summary>
    public IPmacConnection Connection { get; }

    /// <summary>The device facade (the connection as device 0); sessions download chunk files through it.</summary>
    public PmacDevices Devices { get; }

    /// <summary>The built-in simulator's clock, or null for a real controller.</summary>
    public SimulatorLink? Simulator { get; }

    /// <summary>The connection's description (<c>tcp 10.0.0.5:1025</c>, <c>sim</c>).</summary>
    public string Description => Connection.Description;

    /// <summary>True for the built-in simulator (its rotary buffer is defined by the job).</summary>
    public bool IsSimulator => Simulator is not null;

    /// <summary>Closes the connection.</summary>
    public ValueTask DisposeAsync() => Devices.DisposeAsync();
}
