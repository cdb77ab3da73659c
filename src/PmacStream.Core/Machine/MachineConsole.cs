using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Machine;

/// <summary>
/// The operator's console on one controller: the machine's state (positions in machine and work coordinates, homed
/// axes, feed, alarms), its motion commands (home, jog, MDI, clear alarms) and its tables (work offsets, tools). One
/// for every face: the command line's <c>status</c>, <c>home</c>, <c>jog</c>, <c>mdi</c>, <c>offsets</c>, <c>tools</c>,
/// <c>alarms</c>, and the HMI's presenters, which poll <see cref="ReadStateAsync"/> on their timer. Every command
/// returns a <see cref="ConsoleResult"/>: done, or refused with the reason. Everything it knows it reads from the
/// controller, so separate processes on one controller see one machine. See <c>docs/console.md</c>.
/// </summary>
public sealed partial class MachineConsole
{
    private static readonly ILogger Log = Serilog.Log.ForContext<MachineConsole>();
    private readonly JobService _jobs;
    private readonly Dictionary<string, double> _targets = new(StringComparer.Ordinal);

    // Motors jogging continuously at the panel's speed: their own Ixx22, given back when the jog stops.
    private readonly Dictionary<int, double> _heldJogSpeeds = [];
    private double? _servoCycleMs;

    /// <summary>A console on an open controller.</summary>
    public MachineConsole(JobService jobs, ControllerLink controller, MachineConsoleOptions? options = null)
    {
        _jobs = jobs ?? throw new ArgumentNullException(nameof(jobs));
        Controller = controller ?? throw new ArgumentNullException(nameof(controller));
        Options = options ?? new MachineConsoleOptions();
    }

    /// <summary>The controller.</summary>
    public ControllerLink Controller { get; }

    /// <summary>The console's settings.</summary>
    public MachineConsoleOptions Options { get; }

    private IPmacConnection Connection => Controller.Connection;

    private string Cs => "&" + Options.CoordinateSystem.ToString(CultureInfo.InvariantCulture);

    /// <summary>
    /// One sample of the machine: mode, axes (machine, work, to go, homed), alarms (recorded in the history as they come
    /// and go), work offset, feeds. A presenter polls this.
    /// </summary>
    public async Task<MachineState> ReadStateAsync(CancellationToken cancellationToken = default)
    {
        var words = await MotorWordsAsync(Connection, Options.Axes, cancellationToken).ConfigureAwait(false);
        var machine = await PositionsAsync(cancellationToken).ConfigureAwait(false);
        var shift = await WorkShiftAsync(cancellationToken).ConfigureAwait(false);
        var toGo = await ToGoAsync(machine, cancellationToken).ConfigureAwait(false);
        var axes = Options.Axes.Select((a, i) =>
        {
            var work = machine[i] - (a.TableAxis >= 0 ? shift.Shift[a.TableAxis] : 0);
            return new AxisState(a.Name, a.Motor, Round(machine[i]), Round(work), Round(toGo[i]), words[i].HomeComplete);
        }).ToList();
        var alarms = Options.Axes.SelectMany((a, i) => AlarmText.Decode(words[i], a.Motor, a.Name, Options.Language)).ToList();
        var record = LatestJob();
        Options.History?.Observe(alarms, DateTimeOffset.Now, record?.Checkpoint?.State is SessionState.Completed ? null : record?.Id);

        var cs = CsWord.Parse(await Connection.GetResponseAsync(Cs + "??", cancellationToken).ConfigureAwait(false));
        var feedOverride = await NumberAsync(Cs + "%", cancellationToken).ConfigureAwait(false);
        var executing = (int)await NumberAsync(Options.Settings.TrackVariable, cancellationToken).ConfigureAwait(false);
        var programmed = Options.Settings.Shape.Feed == FeedMode.Paper ? await NumberAsync(Options.Settings.Shape.FeedVariable, cancellationToken).ConfigureAwait(false) : (double?)null;
        var actual = await ActualFeedAsync(cancellationToken).ConfigureAwait(false);
        var spindle = await SpindleAsync(cancellationToken).ConfigureAwait(false);
        var (mode, job) = Mode(alarms, cs, feedOverride, record);
        return new MachineState(mode, axes, alarms, MachineTables.NameOf(shift.Index), feedOverride, programmed, Round(actual), spindle.Programmed, executing, job) { Spindle = spindle };
    }

    /// <summary>
    /// The axes of <paramref name="axes"/> that are not homed (Home Complete clear), and the alarms that stop motion:
    /// what a job start checks (<see cref="MachineRules"/>).
    /// </summary>
    public static async Task<(IReadOnlyList<string> Unhomed, IReadOnlyList<MachineAlarm> Alarms)> ReadinessAsync(IPmacConnection connection, IReadOnlyList<MachineAxis> axes, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(connection);
        ArgumentNullException.ThrowIfNull(axes);
        var words = await MotorWordsAsync(connection, axes, cancellationToken).ConfigureAwait(false);
        var unhomed = axes.Where((a, i) => !words[i].HomeComplete).Select(a => a.Name).ToList();
        var alarms = axes.SelectMany((a, i) => AlarmText.Decode(words[i], a.Motor, a.Name)).Where(a => a.Severity == AlarmSeverity.Alarm).ToList();
        return (unhomed, alarms);
    }

    /// <summary>
    /// Where X, Y and Z are commanded in the running program's work coordinates: motor positions plus following errors
    /// (<c>P</c> + <c>F</c>), less the displacement the library applied last (Q(n+14)..Q(n+16), its <c>ADIS</c>); null
    /// when the machine has no X, Y and Z.
    /// </summary>
    public static async Task<GCode.Point3?> WorkPositionAsync(IPmacConnection connection, IReadOnlyList<MachineAxis> axes, LibraryMap map, int coordinateSystem, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(connection);
        ArgumentNullException.ThrowIfNull(axes);
        ArgumentNullException.ThrowIfNull(map);
        var xyz = new[] { "X", "Y", "Z" }.Select(n => axes.FirstOrDefault(a => a.Name == n)).ToList();
        if (xyz.Any(a => a is null))
        {
            return null;
        }

        // Commanded = actual plus following error: a motor killed on a fault stands off its trajectory by its error.
        var actual = Numbers(await connection.GetResponseAsync(string.Concat(xyz.Select(a => $"#{a!.Motor}P")), cancellationToken).ConfigureAwait(false));
        var error = Numbers(await connection.GetResponseAsync(string.Concat(xyz.Select(a => $"#{a!.Motor}F")), cancellationToken).ConfigureAwait(false));
        var p = actual.Select((v, i) => v + (i < error.Count ? error[i] : 0)).ToList();
        var q = Numbers(await connection.GetResponseAsync($"&{coordinateSystem.ToString(CultureInfo.InvariantCulture)} {map.Q(14)} {map.Q(15)} {map.Q(16)}", cancellationToken).ConfigureAwait(false));
        double W(int i) => (i < p.Count ? p[i] / xyz[i]!.CountsPerMm : 0) - (i < q.Count ? q[i] : 0);
        return new GCode.Point3(W(0), W(1), W(2));
    }

    /// <summary>The status words of the axes' motors, in order.</summary>
    internal static async Task<MotorWord[]> MotorWordsAsync(IPmacConnection connection, IReadOnlyList<MachineAxis> axes, CancellationToken cancellationToken)
    {
        var words = new MotorWord[axes.Count];
        for (var i = 0; i < axes.Count; i++)
        {
            var reply = await connection.GetResponseAsync($"#{axes[i].Motor}?", cancellationToken).ConfigureAwait(false);
            words[i] = MotorWord.Parse(reply) ?? throw new PmacLinkException($"motor {axes[i].Motor} status '{reply.Trim()}' is not two hex words");
        }

        return words;
    }

    /// <summary>Actual positions of the axes, millimetres (motor counts over the scale).</summary>
    private async Task<double[]> PositionsAsync(CancellationToken cancellationToken)
    {
        var query = string.Concat(Options.Axes.Select(a => $"#{a.Motor}P"));
        var values = Numbers(await Connection.GetResponseAsync(query, cancellationToken).ConfigureAwait(false));
        return Options.Axes.Select((a, i) => (i < values.Count ? values[i] : 0) / a.CountsPerMm).ToArray();
    }

    /// <summary>
    /// What lies between machine and work coordinates, as the library's N99100 computes it: the active table
    /// (Q20; 0, before the library ran, reads as G54), the external offset (P7100..), G52 (Q21..), G92 (Q24..) and on Z the
    /// applied tool length (Q27).
    /// </summary>
    private async Task<(int Index, double[] Shift)> WorkShiftAsync(CancellationToken cancellationToken)
    {
        var m = Options.Map;
        var q = Numbers(await Connection.GetResponseAsync($"{Cs} {string.Join(' ', Enumerable.Range(0, 8).Select(m.Q))}", cancellationToken).ConfigureAwait(false));
        var index = q.Count > 0 && q[0] >= 1 ? (int)q[0] : 1;
        var at = m.WorkOffsets + (3 * index);
        var p = Numbers(await Connection.GetResponseAsync($"P{at} P{at + 1} P{at + 2} P{m.WorkOffsets} P{m.WorkOffsets + 1} P{m.WorkOffsets + 2}", cancellationToken).ConfigureAwait(false));
        double Q(int n) => n < q.Count ? q[n] : 0;
        double P(int n) => n < p.Count ? p[n] : 0;
        var shift = new double[3];
        for (var a = 0; a < 3; a++)
        {
            shift[a] = P(a) + P(3 + a) + Q(1 + a) + Q(4 + a) + (a == 2 ? Q(7) : 0);
        }

        return (index, shift);
    }

    /// <summary>Vector speed of the axes now, mm/min (<c>V</c> is counts per servo cycle; I10 gives the cycle).</summary>
    private async Task<double> ActualFeedAsync(CancellationToken cancellationToken)
    {
        _servoCycleMs ??= await NumberAsync("I10", cancellationToken).ConfigureAwait(false) / 8_388_608.0;
        var v = Numbers(await Connection.GetResponseAsync(string.Concat(Options.Axes.Select(a => $"#{a.Motor}V")), cancellationToken).ConfigureAwait(false));
        var sum = Options.Axes.Select((a, i) => i < v.Count ? v[i] / a.CountsPerMm : 0).Sum(x => x * x);
        return _servoCycleMs > 0 ? Math.Sqrt(sum) / _servoCycleMs.Value * 60_000 : 0;
    }

    private static (MachineMode Mode, string? Job) Mode(IReadOnlyList<MachineAlarm> alarms, CsWord? cs, double feedOverride, JobRecord? record)
    {
        var job = record is null ? null : $"job {record.Id} {(record.Checkpoint?.State ?? SessionState.Idle).ToString().ToLowerInvariant()}";
        if (alarms.Any(a => a.Severity == AlarmSeverity.Alarm))
        {
            return (MachineMode.Alarm, job);
        }

        if (cs is { ProgramRunning: true } && record?.Checkpoint?.State != SessionState.Completed)
        {
            return (feedOverride == 0 || record?.Checkpoint?.State == SessionState.Held ? MachineMode.Held : MachineMode.Running, job);
        }

        return record?.Checkpoint?.State switch
        {
            SessionState.Held or SessionState.Faulted => (MachineMode.Held, job),
            SessionState.Stopped or SessionState.Aborted => (MachineMode.Stopped, job),
            _ => (MachineMode.Idle, job),
        };
    }

    /// <summary>The newest job recorded on this controller, or null.</summary>
    private JobRecord? LatestJob()
    {
        if (!JobStores.Exists(_jobs.Store))
        {
            return null;
        }

        try
        {
            using var store = JobStores.Open(_jobs.Store);
            return store.Latest(Controller.Spec.ToString());
        }
        catch (JobStoreException e)
        {
            Log.Warning("Job store {Path:l} not read: {Message:l}", _jobs.JobDatabase, e.Message);
            return null;
        }
    }

    private async Task<double> NumberAsync(string query, CancellationToken cancellationToken) =>
        Numbers(await Connection.GetResponseAsync(query, cancellationToken).ConfigureAwait(false)) is [var v, ..] ? v : 0;

    /// <summary>The numbers of a reply (one per query, separated by CR, LF or blanks).</summary>
    internal static List<double> Numbers(string reply) =>
        reply.Split(['\r', '\n', ' ', '\u0006'], StringSplitOptions.RemoveEmptyEntries)
            .Select(v => double.TryParse(v, NumberStyles.Float, CultureInfo.InvariantCulture, out var d) ? d : 0)
            .ToList();

    private static double Round(double v) => Math.Round(v, 4) is var r && r == 0 ? 0 : r;
}
