using PmacStream.Machine;

namespace PmacStream.Hmi;

/// <summary>A job the HMI started or resumed in this session, as the History page lists it.</summary>
/// <param name="JobId">The job store's id.</param>
/// <param name="Program">The program file.</param>
/// <param name="Strategy">Download strategy name.</param>
/// <param name="Started">When the HMI started (or resumed) it.</param>
/// <param name="State">Where it stands now.</param>
/// <param name="Line">The last executed source line.</param>
public sealed record HmiJobEntry(long JobId, string Program, string Strategy, DateTimeOffset Started, HmiJobState State, int Line);

/// <summary>
/// The operator's console as the HMI's console pages need it: the seam between their presenter and
/// <see cref="MachineConsole"/> on the backend's open controller link. Every command returns the console's
/// <see cref="ConsoleResult"/>: the rules (motion refused while a program runs, not homed, an alarm) are the console's.
/// </summary>
public interface IConsoleBackend
{
    /// <summary>True while a controller link is open (the console exists only on one).</summary>
    bool ConsoleReady { get; }

    /// <summary>One sample of the machine (<see cref="MachineConsole.ReadStateAsync"/>).</summary>
    Task<MachineState> ReadStateAsync(CancellationToken cancellationToken = default);

    /// <summary>Homes the axes named (null: all).</summary>
    Task<ConsoleResult> HomeAsync(string? axes, CancellationToken cancellationToken = default);

    /// <summary>Incremental jog of <paramref name="distance"/> mm at <paramref name="feed"/> mm/min (null: the motor's jog speed).</summary>
    Task<ConsoleResult> JogAsync(string axis, double distance, double? feed, CancellationToken cancellationToken = default);

    /// <summary>Starts a continuous jog (the button pressed) at <paramref name="feed"/> mm/min (null: the motor's jog speed).</summary>
    Task<ConsoleResult> StartJogAsync(string axis, int direction, double? feed, CancellationToken cancellationToken = default);

    /// <summary>Stops a continuous jog (the button released).</summary>
    Task<ConsoleResult> StopJogAsync(string axis, CancellationToken cancellationToken = default);

    /// <summary>Runs MDI blocks through the job gate.</summary>
    Task<ConsoleResult> MdiAsync(IReadOnlyList<string> blocks, CancellationToken cancellationToken = default);

    /// <summary>Clears the alarms a clear can end.</summary>
    Task<ConsoleResult> ClearAlarmsAsync(CancellationToken cancellationToken = default);

    /// <summary>The work offsets and tools as the controller holds them.</summary>
    Task<MachineTables> ReadTablesAsync(CancellationToken cancellationToken = default);

    /// <summary>Sets a work offset's axes (null: unchanged).</summary>
    Task<ConsoleResult> SetWorkOffsetAsync(string name, double? x, double? y, double? z, CancellationToken cancellationToken = default);

    /// <summary>Sets <paramref name="axis"/> of work offset <paramref name="name"/> so the current position reads <paramref name="value"/>.</summary>
    Task<ConsoleResult> TouchOffAsync(string name, string axis, double value, CancellationToken cancellationToken = default);

    /// <summary>Sets a tool's length, radius and wear.</summary>
    Task<ConsoleResult> SetToolAsync(int number, double length, double radius, double lengthWear, double radiusWear, CancellationToken cancellationToken = default);

    /// <summary>Every alarm the console has seen, newest first (empty when no history is kept).</summary>
    IReadOnlyList<AlarmRecord> AlarmHistory();

    /// <summary>
    /// The jobs this HMI started or resumed, newest first. (A listing of the whole job store needs a view of its records
    /// in the job service; the store is being moved for issue 26.)
    /// </summary>
    IReadOnlyList<HmiJobEntry> JobHistory();
}
