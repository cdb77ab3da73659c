using System.Globalization;
using PmacStream.Jobs;
using Serilog;

namespace PmacStream.Hmi;

/// <summary>A job of the store's history as the Store page lists it (formatted).</summary>
/// <param name="Id">Job id.</param>
/// <param name="Program">The revision (<c>#12 part.nc</c>) or file it ran.</param>
/// <param name="Station">The station that ran it.</param>
/// <param name="Machine">The machine.</param>
/// <param name="Started">Start, local time.</param>
/// <param name="Ended">End, local time, or empty.</param>
/// <param name="Outcome">running, completed, aborted, interrupted or alarm.</param>
/// <param name="Blocks">Blocks executed of the total (<c>1500/1505</c>).</param>
public sealed record StoredJobRow(long Id, string Program, string Station, string Machine, string Started, string Ended, string Outcome, string Blocks);

/// <summary>A program revision of the store as the Store page lists it.</summary>
/// <param name="Id">Revision id.</param>
/// <param name="Name">Its name.</param>
/// <param name="Profile">The profile it was checked under.</param>
/// <param name="Blocks">Blocks.</param>
/// <param name="Errors">Errors the check found.</param>
public sealed record StoredProgramRow(long Id, string Name, string Profile, long Blocks, int Errors);

/// <summary>A machine of the shop as the Store page lists it (what <c>pmacstream shop</c> prints).</summary>
/// <param name="Machine">The machine.</param>
/// <param name="Station">The station holding its lease (<c>–</c> when free).</param>
/// <param name="Job">The job there (<c>–</c> when none).</param>
/// <param name="Program">Its program (<c>#12 part.nc</c>).</param>
/// <param name="Line">The current line (its latest checkpoint's).</param>
/// <param name="Blocks">Blocks executed of the total.</param>
/// <param name="Outcome">The job's outcome (running, completed, ...).</param>
/// <param name="Lease">leased, expired or free, with the last heartbeat.</param>
public sealed record ShopRow(string Machine, string Station, string Job, string Program, string Line, string Blocks, string Outcome, string Lease);

/// <summary>The Store page as a passive view: the store's job history and program revisions, and Open.</summary>
public interface IStoreView
{
    /// <summary>Where the store is (never its password).</summary>
    string StoreLocationText { set; }

    /// <summary>The store's jobs, newest first.</summary>
    IReadOnlyList<StoredJobRow> StoredJobs { set; }

    /// <summary>The store's program revisions, newest first.</summary>
    IReadOnlyList<StoredProgramRow> StoredPrograms { set; }

    /// <summary>The shop: every machine the store knows, who runs what there and the current line.</summary>
    IReadOnlyList<ShopRow> Shop { set; }

    /// <summary>The revision the operator selected, or null.</summary>
    long? SelectedStoredProgram { get; }

    /// <summary>What the last store action did (or why not).</summary>
    string StoreMessage { set; }

    /// <summary>Read the lists again.</summary>
    event EventHandler? StoreRefreshRequested;

    /// <summary>Open the selected revision as the program to run.</summary>
    event EventHandler? OpenStoredProgramRequested;
}

/// <summary>The store as the Store page needs it: the job service's views (no SQL here).</summary>
public interface IStoreBackend
{
    /// <summary>Where the store is (<see cref="JobService.Store"/>'s display form).</summary>
    string StoreDisplay { get; }

    /// <summary>The store's jobs (<see cref="JobService.JobHistory"/>).</summary>
    IReadOnlyList<JobHistoryView> JobHistory();

    /// <summary>The store's program revisions (<see cref="JobService.StoredPrograms"/>).</summary>
    IReadOnlyList<StoredProgramView> StoredPrograms();

    /// <summary>The shop's machines (<see cref="JobService.ShopViews"/>).</summary>
    IReadOnlyList<ShopMachineView> Shop();

    /// <summary>A revision's source as a file to open, and its built-in profile (<see cref="JobService.StoredProgramFile"/>).</summary>
    (string Path, string? Profile) StoredProgramFile(long id);
}

/// <summary>
/// The Store page's logic: lists the store's job history (what <c>jobs --json</c> prints) and its program revisions
/// (what <c>programs list --json</c> prints), and opens a chosen revision as the program to run, under the profile it
/// was imported with (as <c>stream --program ID</c>). The store is read off the UI thread.
/// </summary>
public sealed class StorePresenter
{
    private readonly IStoreView _view;
    private readonly IStoreBackend _backend;
    private readonly Func<string, string?, Task> _open;
    private readonly ILogger _log;
    private readonly ViewOperations _ops;

    /// <summary>
    /// Wires the presenter; <paramref name="open"/> opens a file under a built-in profile name (null: the chosen one),
    /// as the program screen's Open does.
    /// </summary>
    public StorePresenter(IStoreView view, IStoreBackend backend, Func<string, string?, Task> open, ILogger? logger = null)
    {
        _view = view;
        _backend = backend;
        _open = open;
        _log = logger ?? Log.ForContext<StorePresenter>();
        _ops = new ViewOperations(CancellationToken.None, () => { }, Failed);
        view.StoreLocationText = backend.StoreDisplay;
        view.StoredJobs = [];
        view.StoredPrograms = [];
        view.Shop = [];
        view.StoreMessage = string.Empty;
        view.StoreRefreshRequested += (_, _) => _ops.Run(RefreshAsync);
        view.OpenStoredProgramRequested += (_, _) => _ops.Run(OpenSelectedAsync);
    }

    /// <summary>
    /// Opens a revision by id, file and profile (the program screen's <c>OpenStoredAsync</c>), so its job records the
    /// revision; null: the constructor's open, which knows only the file.
    /// </summary>
    public Func<long, string, string?, Task>? OpenRevision { get; init; }

    /// <summary>The language the page's messages and outcomes are in (the form's language switch).</summary>
    public Func<HmiLanguage> Language { get; init; } = static () => HmiLanguage.English;

    /// <summary>Completes when every action started by a view event has finished (tests await it).</summary>
    public Task WhenIdleAsync() => _ops.WhenIdleAsync();

    /// <summary>Reads both lists from the store and shows them.</summary>
    public async Task RefreshAsync()
    {
        var (jobs, programs, shop) = await Task.Run(() => (_backend.JobHistory(), _backend.StoredPrograms(), _backend.Shop())).ConfigureAwait(true);
        _view.StoredJobs = jobs.Select(j => Row(j, Language())).ToList();
        _view.StoredPrograms = programs.Select(p => new StoredProgramRow(p.Id, p.Name, p.Profile, p.Blocks, p.Errors)).ToList();
        _view.Shop = shop.Select(Row).ToList();
        _view.StoreMessage = T(TextId.StoreSummary, jobs.Count, programs.Count, _backend.StoreDisplay);
    }

    /// <summary>Opens the selected revision: its source from the store, under its profile; refused for one with errors.</summary>
    public async Task OpenSelectedAsync()
    {
        if (_view.SelectedStoredProgram is not { } id)
        {
            _view.StoreMessage = T(TextId.StoreSelectFirst);
            return;
        }

        var programs = await Task.Run(() => _backend.StoredPrograms()).ConfigureAwait(true);
        if (programs.FirstOrDefault(p => p.Id == id) is { Errors: > 0 } bad)
        {
            _view.StoreMessage = T(TextId.StoreHasErrors, id, bad.Name, bad.Errors);
            return;
        }

        var (path, profile) = await Task.Run(() => _backend.StoredProgramFile(id)).ConfigureAwait(true);
        await (OpenRevision is { } openRevision ? openRevision(id, path, profile) : _open(path, profile)).ConfigureAwait(true);
        _view.StoreMessage = profile is null ? T(TextId.StoreOpened, id, Path.GetFileName(path)) : T(TextId.StoreOpenedUnder, id, Path.GetFileName(path), profile);
        _log.Information("Opened stored program {Id} from {Store:l}: {Path:l}", id, _backend.StoreDisplay, path);
    }

    private string T(TextId id, params object[] args) => HmiText.Format(id, Language(), args);

    private static StoredJobRow Row(JobHistoryView j, HmiLanguage language) => new(
        j.Id,
        (j.ProgramId is { } pid ? $"#{pid.ToString(CultureInfo.InvariantCulture)} " : string.Empty) + Path.GetFileName(j.Program),
        j.Station ?? "–",
        j.Machine,
        j.Started.ToLocalTime().ToString("yyyy-MM-dd HH:mm:ss", CultureInfo.InvariantCulture),
        j.Ended?.ToLocalTime().ToString("yyyy-MM-dd HH:mm:ss", CultureInfo.InvariantCulture) ?? string.Empty,
        j.Outcome switch
        {
            "running" => HmiText.Get(TextId.StoreOutcomeRunning, language),
            "completed" => HmiText.Get(TextId.StoreOutcomeCompleted, language),
            "aborted" => HmiText.Get(TextId.StoreOutcomeAborted, language),
            "interrupted" => HmiText.Get(TextId.StoreOutcomeInterrupted, language),
            "alarm" => HmiText.Get(TextId.StoreOutcomeAlarm, language),
            _ => j.Outcome,
        },
        string.Create(CultureInfo.InvariantCulture, $"{j.BlocksExecuted}/{(j.BlocksTotal is { } t ? t.ToString(CultureInfo.InvariantCulture) : "?")}"));

    private static ShopRow Row(ShopMachineView m)
    {
        var ci = CultureInfo.InvariantCulture;
        return new ShopRow(
            m.Machine,
            m.Station ?? "–",
            m.JobId?.ToString(ci) ?? "–",
            m.JobId is null ? "–" : (m.ProgramId is { } pid ? $"#{pid.ToString(ci)} " : string.Empty) + m.Program,
            m.Line?.ToString(ci) ?? "–",
            m.JobId is null ? "–" : string.Create(ci, $"{m.BlocksExecuted ?? 0}/{(m.BlocksTotal is { } t ? t.ToString(ci) : "?")}"),
            m.Outcome ?? "–",
            m.Heartbeat is { } beat ? $"{m.State}, beat {beat.ToLocalTime().ToString("HH:mm:ss", ci)}" : m.State);
    }

    /// <summary>A store that cannot be read, a revision without its source: said on the page, nothing opened.</summary>
    private void Failed(Exception e)
    {
        _log.Error("{Message:l}", e.Message);
        _view.StoreMessage = e.Message;
    }
}
