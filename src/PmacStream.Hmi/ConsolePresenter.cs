using System.Diagnostics;
using System.Globalization;
using PmacStream.GCode;
using PmacStream.Machine;
using Serilog;

namespace PmacStream.Hmi;

/// <summary>
/// The console pages' logic: the DRO, the alarm banner and histories polled from <see cref="TickAsync"/> (the form's
/// timer), and the operator's console commands (home, jog, MDI, clear alarms, touch-off, the table grids, load library)
/// sent through <see cref="IConsoleBackend"/>. The machine's rules are the console's: a refused command shows its
/// reason. Runs on the UI thread; the view is passive.
/// </summary>
public sealed partial class ConsolePresenter : IAsyncDisposable
{
    /// <summary>The jog increments the panel offers, mm (and continuous).</summary>
    public static IReadOnlyList<double> JogIncrements { get; } = [0.001, 0.01, 0.1, 1];

    /// <summary>Jog speed the panel starts at, mm/min.</summary>
    public const double DefaultJogFeed = 1000;

    /// <summary>Tools the Tools page lists (1..this).</summary>
    public const int ToolRowCount = 24;

    private readonly IConsoleView _view;
    private readonly IConsoleBackend _backend;
    private readonly IHmiBackend _hmi;
    private readonly Func<MachineProfile> _profile;
    private readonly ILogger _log;
    private readonly CancellationTokenSource _life = new();
    private readonly ViewOperations _ops;
    private readonly Stopwatch _sincePoll = new();
    private readonly List<string> _mdiHistory = [];
    private MachineTables? _tables;
    private IReadOnlyList<string> _axes = ["X", "Y", "Z"];
    private string _alarmKey = string.Empty;
    private string? _continuousAxis;
    private bool _polling;
    private bool _jogHeld;
    private bool _wasReady;

    /// <summary>
    /// Wires the presenter to the console view. <paramref name="hmi"/> loads the library of the profile
    /// <paramref name="profile"/> gives (the one the operator chose on the program screen).
    /// </summary>
    public ConsolePresenter(IConsoleView view, IConsoleBackend backend, IHmiBackend hmi, Func<MachineProfile> profile, ILogger? logger = null)
    {
        _view = view;
        _backend = backend;
        _hmi = hmi;
        _profile = profile;
        _log = logger ?? Serilog.Log.ForContext<ConsolePresenter>();
        _ops = new ViewOperations(_life.Token, RefreshEnabled, Failed);
        Wire();
        view.ConsoleAxes = _axes;
        view.JogAxis = "X";
        view.JogIncrement = 1;
        view.JogFeed = DefaultJogFeed;
        view.AlarmBanner = string.Empty;
        view.ConsoleMessage = string.Empty;
        view.TablesMessage = string.Empty;
        view.MdiHistory = [];
        RefreshEnabled();
    }

    /// <summary>How often the DRO is read at most (the form's timer ticks faster; the link is shared with the job).</summary>
    public TimeSpan PollPeriod { get; set; } = TimeSpan.FromMilliseconds(200);

    /// <summary>The last sample of the machine, or null before the first (or after disconnecting).</summary>
    public MachineState? State { get; private set; }

    /// <summary>The tables as the grids were last filled from the controller.</summary>
    public MachineTables? Tables => _tables;

    /// <summary>Blocks sent by MDI, oldest first.</summary>
    public IReadOnlyList<string> MdiHistory => _mdiHistory;

    /// <summary>Completes when every command started by a view event has finished (tests await it).</summary>
    public Task WhenIdleAsync() => _ops.WhenIdleAsync();

    private HmiLanguage Language => _view.Language;

    private void Wire()
    {
        _view.LanguageChanged += (_, _) => Show();
        _view.HomeAllRequested += (_, _) => Command(c => _backend.HomeAsync(null, c));
        _view.HomeAxisRequested += (_, axis) => Command(c => _backend.HomeAsync(axis, c));
        _view.JogPressed += (_, e) => Command(c => JogAsync(e.Direction, c));
        _view.JogReleased += (_, _) => StopContinuousJog();
        _view.MdiRequested += (_, _) => Run(MdiAsync);
        _view.MdiHistoryPicked += (_, i) => _view.MdiText = i >= 0 && i < _mdiHistory.Count ? _mdiHistory[i] : _view.MdiText;
        _view.ClearAlarmsRequested += (_, _) => Command(c => _backend.ClearAlarmsAsync(c));
        _view.TouchOffRequested += (_, axis) => Run(() => TouchOffAsync(axis));
        _view.OffsetsApplyRequested += (_, _) => Run(ApplyOffsetsAsync);
        _view.ToolsApplyRequested += (_, _) => Run(ApplyToolsAsync);
        _view.TablesReloadRequested += (_, _) => Run(ReloadTablesAsync);
        _view.LoadLibraryRequested += (_, _) => Run(LoadLibraryAsync);
        _view.HistoryRefreshRequested += (_, _) => ShowHistories();
    }

    /// <summary>
    /// One timer period: reads the machine (at most every <see cref="PollPeriod"/>, never two reads at once) and shows
    /// the DRO, the summary line and the alarm banner; the first tick after connecting fills the table grids.
    /// </summary>
    public async Task TickAsync()
    {
        if (_polling)
        {
            return;
        }

        if (!_backend.ConsoleReady)
        {
            Disconnected();
            return;
        }

        if (_sincePoll.IsRunning && _sincePoll.Elapsed < PollPeriod)
        {
            return;
        }

        _polling = true;
        try
        {
            _sincePoll.Restart();
            State = await _backend.ReadStateAsync(_life.Token).ConfigureAwait(true);
            Show();
            if (!_wasReady)
            {
                _wasReady = true;
                RefreshEnabled();
                Run(ReloadTablesAsync);
            }
        }
        finally
        {
            _polling = false;
        }
    }

    /// <inheritdoc />
    public async ValueTask DisposeAsync()
    {
        _life.Cancel();
        try
        {
            await _ops.WhenIdleAsync().ConfigureAwait(false);
        }
        catch (Exception)
        {
            // Already shown when it happened.
        }

        _life.Dispose();
    }

    private void Disconnected()
    {
        if (!_wasReady)
        {
            return;
        }

        _wasReady = false;
        State = null;
        _sincePoll.Reset();
        _view.Dro = [];
        _view.AlarmBanner = string.Empty;
        _view.MachineSummary = string.Empty;
        RefreshEnabled();
    }

    /// <summary>The last sample on the view: DRO rows, the summary line, the banner (and the alarm history when the alarms changed).</summary>
    private void Show()
    {
        if (State is not { } s)
        {
            return;
        }

        _view.Dro = s.Axes.Select(a => new DroRow(a.Name, Mm(a.Machine), Mm(a.Work), Mm(a.ToGo), a.Homed)).ToList();
        if (!s.Axes.Select(a => a.Name).SequenceEqual(_axes))
        {
            // The machine's axes (the profile's, X Y Z by default): the jog panel offers them.
            var jogAxis = _view.JogAxis;
            _axes = s.Axes.Select(a => a.Name).ToList();
            _view.ConsoleAxes = _axes;
            _view.JogAxis = _axes.Contains(jogAxis) ? jogAxis : _axes.FirstOrDefault() ?? "X";
        }
        _view.MachineSummary = Summary(s);
        _view.AlarmBanner = s.Alarms.Count == 0 ? string.Empty : T(TextId.AlarmBanner, string.Join("; ", s.Alarms.Select(AlarmLine)));
        var key = string.Join(",", s.Alarms.Select(a => a.Code + a.Motor));
        if (key != _alarmKey)
        {
            _alarmKey = key;
            ShowHistories();
        }
    }

    private string Summary(MachineState s)
    {
        var mode = s.Mode switch
        {
            MachineMode.Running => HmiText.Get(TextId.StateRunning, Language),
            MachineMode.Held => HmiText.Get(TextId.StateHeld, Language),
            MachineMode.Stopped => HmiText.Get(TextId.ModeStopped, Language),
            MachineMode.Alarm => HmiText.Get(TextId.ModeAlarm, Language),
            _ => HmiText.Get(TextId.StateIdle, Language),
        };
        return T(TextId.MachineSummary, mode, s.WorkOffset, Num(s.ActualFeed), s.ProgrammedFeed is { } f ? Num(f) : "–", Num(s.FeedOverride),
            s.Spindle is { } sp ? T(TextId.SpindleReadout, Num(sp.Actual), Num(sp.Programmed)) : s.SpindleSpeed is { } ss ? Num(ss) : "–", s.Job ?? "–");
    }

    /// <summary>An alarm in the operator's language (the console decodes in its own; the code is stable).</summary>
    private string AlarmLine(MachineAlarm a) => AlarmText.Text(a.Code, a.Axis, a.Motor, Language == HmiLanguage.Chinese ? "zh-CN" : "en");

    private void ShowHistories()
    {
        var alarms = _backend.AlarmHistory();
        _view.AlarmHistory = alarms.Select(a => T(TextId.AlarmRow, a.Raised.ToLocalTime(), AlarmText.Text(a.Code, a.Axis, a.Motor, Language == HmiLanguage.Chinese ? "zh-CN" : "en"),
            a.Cleared is { } c ? T(TextId.AlarmCleared, c.ToLocalTime()) : string.Empty)).ToList();
        _view.JobHistory = _backend.JobHistory().Select(j => T(TextId.JobRow, j.JobId, Path.GetFileName(j.Program), j.Strategy, JobStateText(j.State), j.Line, j.Started.ToLocalTime())).ToList();
    }

    private string JobStateText(HmiJobState state) => HmiText.Get(state switch
    {
        HmiJobState.Running => TextId.StateRunning,
        HmiJobState.Held => TextId.StateHeld,
        HmiJobState.Completed => TextId.StateCompleted,
        HmiJobState.Aborted => TextId.StateAborted,
        HmiJobState.Failed => TextId.StateFailed,
        HmiJobState.Stopped => TextId.ModeStopped,
        _ => TextId.StateIdle,
    }, Language);

    private void RefreshEnabled()
    {
        _view.ConsoleEnabled = _backend.ConsoleReady && _ops.Busy == 0;

        // A held jog button stays usable while its jog runs: its release must reach the presenter.
        _view.JogEnabled = _backend.ConsoleReady;
    }

    private void Failed(Exception e)
    {
        _log.Error("{Message:l}", e.Message);
        _view.ConsoleMessage = e.Message;
    }

    private void Run(Func<Task> operation) => _ops.Run(operation);

    /// <summary>A console command: refused at once without a controller; its result (done, or refused and why) shown.</summary>
    private void Command(Func<CancellationToken, Task<ConsoleResult>> command) => Run(async () =>
    {
        if (!_backend.ConsoleReady)
        {
            _view.ConsoleMessage = HmiText.Get(TextId.ConnectFirst, Language);
            return;
        }

        ShowResult(await command(_life.Token).ConfigureAwait(true));
    });

    private void ShowResult(ConsoleResult result)
    {
        var text = T(result.Done ? TextId.ConsoleDone : TextId.ConsoleRefused, result.Message);
        _view.ConsoleMessage = text;
        _log.Information("Console: {Text:l}", text);
    }

    private string T(TextId id, params object[] args) => HmiText.Format(id, Language, args);

    private static string Mm(double v) => v.ToString("0.000", CultureInfo.InvariantCulture);

    private static string Num(double v) => v.ToString("0.#", CultureInfo.InvariantCulture);
}
