using PmacStream.GCode;
using PmacStream.Machine;

namespace PmacStream.Hmi;

/// <summary>
/// The console pages' side of the real backend: a <see cref="MachineConsole"/> on the controller link the operator
/// opened (the same link the jobs run on), set up with <see cref="ConsoleOptions"/> and the profile the operator chose
/// (MDI is checked and converted under it), and the list of jobs this HMI started.
/// </summary>
public sealed partial class CoreHmiBackend
{
    private readonly List<(SessionJob Job, string Program, string Strategy, DateTimeOffset Started)> _jobs = [];
    private MachineConsole? _console;
    private MachineProfile _profile = MachineProfile.Default;

    /// <summary>
    /// How the console is set up (alarm history, host copy of the tables, MDI's modal state file, language); the
    /// profile is the operator's. Default: none of the files kept.
    /// </summary>
    public MachineConsoleOptions ConsoleOptions { get; init; } = new();

    /// <inheritdoc />
    public bool ConsoleReady => _link is not null;

    /// <summary>The console on the open link (made on first use, again after a profile change).</summary>
    private MachineConsole Console => _console ??= new MachineConsole(Service, Link, ConsoleOptions with
    {
        Profile = _profile,
        History = ConsoleOptions.History is StoreAlarmHistory h ? h.On(Link.Spec.ToString()) : ConsoleOptions.History,
        Axes = _profile.Axes.Count > 0 ? MachineAxis.Of(_profile) : ConsoleOptions.Axes,
        CoordinateSystem = _profile.Axes.Count > 0 ? _profile.CoordinateSystem : ConsoleOptions.CoordinateSystem,
    });

    /// <inheritdoc />
    public Task<MachineState> ReadStateAsync(CancellationToken cancellationToken = default) => Console.ReadStateAsync(cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> HomeAsync(string? axes, CancellationToken cancellationToken = default) => Console.HomeAsync(axes, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> JogAsync(string axis, double distance, double? feed, CancellationToken cancellationToken = default) =>
        Console.JogAsync(axis, distance, feed, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> StartJogAsync(string axis, int direction, double? feed, CancellationToken cancellationToken = default) =>
        Console.StartJogAsync(axis, direction, feed, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> StopJogAsync(string axis, CancellationToken cancellationToken = default) => Console.StopJogAsync(axis, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> MdiAsync(IReadOnlyList<string> blocks, CancellationToken cancellationToken = default) => Console.MdiAsync(blocks, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> ClearAlarmsAsync(CancellationToken cancellationToken = default) => Console.ClearAlarmsAsync(cancellationToken);

    /// <inheritdoc />
    public Task<MachineTables> ReadTablesAsync(CancellationToken cancellationToken = default) => Console.ReadTablesAsync(cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> SetWorkOffsetAsync(string name, double? x, double? y, double? z, CancellationToken cancellationToken = default) =>
        Console.SetWorkOffsetAsync(name, x, y, z, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> TouchOffAsync(string name, string axis, double value, CancellationToken cancellationToken = default) =>
        Console.TouchOffAsync(name, axis, value, cancellationToken);

    /// <inheritdoc />
    public Task<ConsoleResult> SetToolAsync(int number, double length, double radius, double lengthWear, double radiusWear, CancellationToken cancellationToken = default) =>
        Console.SetToolAsync(number, length, radius, lengthWear, radiusWear, cancellationToken);

    /// <inheritdoc />
    public IReadOnlyList<AlarmRecord> AlarmHistory() => (_link is null ? ConsoleOptions.History : Console.Options.History)?.List() ?? [];

    /// <inheritdoc />
    public IReadOnlyList<HmiJobEntry> JobHistory()
    {
        lock (_jobs)
        {
            return _jobs.Where(j => j.Job.Id is not null)
                .Select(j => new HmiJobEntry(j.Job.Id!.Value, j.Program, j.Strategy, j.Started, j.Job.Status.State, j.Job.Status.CurrentLine))
                .Reverse().ToList();
        }
    }

    /// <inheritdoc />
    public string StoreDisplay => Service.StoreDisplay;

    /// <inheritdoc />
    IReadOnlyList<Jobs.JobHistoryView> IStoreBackend.JobHistory() => Service.JobHistory();

    /// <inheritdoc />
    IReadOnlyList<Jobs.ShopMachineView> IStoreBackend.Shop() => Service.ShopViews();

    /// <inheritdoc />
    public IReadOnlyList<Jobs.StoredProgramView> StoredPrograms() => Service.StoredPrograms();

    /// <inheritdoc />
    public (string Path, string? Profile) StoredProgramFile(long id) => Service.StoredProgramFile(id);

    /// <summary>The operator chose another profile: MDI is checked under it from now on.</summary>
    private void ProfileChosen(MachineProfile profile)
    {
        _profile = profile;
        _console = null;
    }

    private SessionJob Track(SessionJob job, string program, string strategy)
    {
        lock (_jobs)
        {
            _jobs.Add((job, program, strategy, DateTimeOffset.Now));
        }

        return job;
    }
}
