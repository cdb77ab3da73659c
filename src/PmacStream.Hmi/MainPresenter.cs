using PmacStream.GCode;
using PmacStream.Jobs;
using Serilog;

namespace PmacStream.Hmi;

/// <summary>
/// All the HMI's logic, driven by the view's events and by <see cref="TickAsync"/> (the form's
/// <c>timer1_Tick</c>). It owns the open program's line index, the split result, the controller connection, the
/// running job, the chunk lines that follow it and the toolpath pane, and tells the passive <see cref="IMainView"/>
/// what to show. Runs on the UI thread.
/// </summary>
public sealed class MainPresenter : IAsyncDisposable
{
    /// <summary>Lines indexed before a newly opened program is shown (more than any screen holds).</summary>
    public const int FirstScreenLines = 256;

    private long? _openedRevision; // the store revision opened from the Store page, else null (a file)
    private long? _programId; // the store revision the program is: the split's (a file is stored as it is split), else the opened one
    private readonly ILogger _log;
    private readonly IMainView _view;
    private readonly IHmiBackend _backend;
    private readonly HmiLogSink? _logSink;
    private readonly CancellationTokenSource _life = new();
    private readonly ViewOperations _ops;

    private HmiLanguage _language;
    private readonly ConnectionPanel _connection;
    private bool _ticking;
    private ProgramLineSource? _program;
    private int _shownLineCount;
    private readonly ChunkLinesPane _chunkLines;
    private readonly ToolpathPane _toolpath;
    private readonly ProgramGatePanel _gate;
    private SplitView? _split;
    private IHmiJob? _job;
    private HmiJobStatus? _lastStatus;
    private int _shownExecutingLine;
    private double _feedOverride = FeedOverrides.Default;
    private RunSettings _settings;
    private RunSettings _jobSettings;
    private string _jobStrategy = string.Empty;
    private bool _optionalStop = true;
    private string _banner = string.Empty;

    /// <summary>
    /// Wires the presenter to a view and the core. <paramref name="logSink"/> feeds the log pane (the application
    /// adds it to the global Serilog logger); <paramref name="logger"/> replaces the global logger for job events;
    /// <paramref name="settings"/> are the run settings the controls start from (the command line's, from the same
    /// settings file; default <see cref="RunSettings.Default"/>); <paramref name="profile"/> the machine profile the
    /// selector starts at (default <see cref="MachineProfile.Default"/>).
    /// </summary>
    public MainPresenter(IMainView view, IHmiBackend backend, HmiLogSink? logSink = null, ILogger? logger = null, RunSettings? settings = null, MachineProfile? profile = null)
    {
        _settings = settings ?? RunSettings.Default;
        _jobSettings = _settings;
        _log = logger ?? Serilog.Log.ForContext<MainPresenter>();
        _view = view;
        _backend = backend;
        _logSink = logSink;
        _language = view.Language;
        _ops = new ViewOperations(_life.Token, OperationsChanged, OperationFailed);
        _connection = new ConnectionPanel(view, backend, _log);
        _chunkLines = new ChunkLinesPane(view, backend);
        _toolpath = new ToolpathPane(view, backend, _log) { Language = _language };
        _gate = new ProgramGatePanel(view, backend, _log);

        view.LanguageChanged += (_, _) => Run(ChangeLanguageAsync);
        view.ConnectRequested += (_, _) => Run(() => _connection.ConnectAsync(_gate.Profile, _language, _life.Token));
        view.DisconnectRequested += (_, _) => Run(() => _connection.DisconnectAsync(_job is not null, _language));
        view.OpenRequested += (_, path) => Run(() => OpenAsync(path));
        view.CheckRequested += (_, _) => Run(() => _gate.CheckAsync(_program?.Path ?? throw new InvalidOperationException("Open a program first."), _language, _life.Token));
        view.DiagnosticActivated += (_, index) => _view.FocusedLine = _gate.LineOf(index) ?? 0;
        view.ProfileChanged += (_, _) => Run(ProfileChangedAsync);
        view.OptionalStopChanged += (_, _) => Run(OptionalStopChangedAsync);
        view.SplitRequested += (_, _) => Run(SplitAsync);
        view.ChunkSelected += (_, index) => SelectChunk(index);
        view.ChunkLineNeeded += (_, e) => e.Text = _chunkLines.Line(e.Line);
        view.ProgramLineNeeded += (_, e) => e.Text = ProgramLine(e.Line);
        view.ExecuteRequested += (_, _) => Run(() => StartAsync(null));
        view.StartFromLineRequested += (_, _) => Run(StartFromSelectedLineAsync);
        view.ResumeInterruptedRequested += (_, _) => Run(ResumeInterruptedAsync);
        view.HoldRequested += (_, _) => Run(() => JobCommandAsync(j => j.HoldAsync(_life.Token), "hold"));
        view.ResumeRequested += (_, _) => Run(() => JobCommandAsync(j => j.ResumeAsync(_life.Token), "resume"));
        view.AbortRequested += (_, _) => Run(() => JobCommandAsync(j => j.AbortAsync(_life.Token), "abort"));
        view.SingleBlockChanged += (_, _) => Run(SingleBlockChangedAsync);
        view.FeedOverrideChanged += (_, _) => Run(FeedOverrideChangedAsync);
        view.DownloadWindowChanged += (_, _) => Run(DownloadWindowChangedAsync);

        view.Texts = HmiText.All(_language);
        view.Strategies = backend.Strategies;
        _gate.ShowProfiles(profile ?? MachineProfile.Default);
        view.OptionalStop = _optionalStop;
        view.ProgramStopBanner = string.Empty;
        view.ConnectionState = T(TextId.StateDisconnected);
        view.FeedOverride = _feedOverride;
        view.BlocksPerChunk = _settings.BlocksPerChunk;
        view.DownloadWindow = (_settings.WindowStart, _settings.WindowEnd);
        view.ProgramLineCount = 0;
        view.ChunkLineCount = 0;
        RefreshCommands();
        RefreshStatus();
    }

    /// <summary>The open program's line index (null before a program is opened).</summary>
    public ProgramLineSource? Program => _program;

    /// <summary>The running or last job's status.</summary>
    public HmiJobStatus? JobStatus => _lastStatus;

    /// <summary>The machine profile the operator chose (the console's Load library downloads its library).</summary>
    public MachineProfile Profile => _gate.Profile;

    /// <summary>The run settings the next job starts with (blocks per chunk and window as the controls last set them).</summary>
    public RunSettings Settings => _settings;

    /// <summary>The timer period the form ticks with (<see cref="TickAsync"/>).</summary>
    public TimeSpan TickPeriod => _settings.TickPeriod;

    /// <summary>True while a job is running or held.</summary>
    public bool JobActive => _job is not null;

    /// <summary>The chunk shown in the chunk-lines list (0-based, -1 for none).</summary>
    public int ShownChunk => _chunkLines.Shown;

    /// <summary>True while the chunk-lines list follows execution.</summary>
    public bool ChunkLinesFollow => _chunkLines.Following;

    /// <summary>True once the toolpath pane shows the planned toolpath of the open program.</summary>
    public bool ToolpathReady => _toolpath.Ready;

    /// <summary>Executed moves drawn in the toolpath pane for the current job.</summary>
    public long ToolpathExecutedMoves => _toolpath.ExecutedMoves;

    /// <summary>Completes when every operation started by a view event has finished (tests await it).</summary>
    public Task WhenIdleAsync() => _ops.WhenIdleAsync();

    /// <summary>
    /// One timer period (the form's <c>timer1_Tick</c>): moves log lines to the pane, shows indexing progress,
    /// lets the job stream (read M0, download the next chunk once), shows its line and status, and brings the
    /// toolpath pane up to it. A tick that arrives while the previous one is still at work is skipped, so ticks
    /// never overlap.
    /// </summary>
    public async Task TickAsync()
    {
        if (_ticking)
        {
            return;
        }

        _ticking = true;
        try
        {
            DrainLog();
            RefreshProgramLineCount();
            if (_job is { } job)
            {
                try
                {
                    await job.TickAsync(_life.Token).ConfigureAwait(true);
                }
                catch (Exception e) when (e is not OperationCanceledException)
                {
                    _log.Error(e, "Streaming stopped: {Message:l}. The job can be resumed after interruption", e.Message);
                    _lastStatus = job.Status with { State = HmiJobState.Failed, Message = e.Message };
                    await FinishJobAsync().ConfigureAwait(true);
                    _toolpath.Tick(_lastStatus);
                    return;
                }

                _lastStatus = job.Status;
                if (_lastStatus.IsFinished)
                {
                    await FinishJobAsync().ConfigureAwait(true);
                }
                else
                {
                    ShowJob();
                }
            }

            _toolpath.Tick(_lastStatus);
            DrainLog();
        }
        finally
        {
            _ticking = false;
        }
    }

    /// <summary>
    /// Opens a stored revision's source (the Store page) under the built-in profile it was imported with (null: the
    /// chosen one), as <c>stream --program ID</c> runs it.
    /// </summary>
    public Task OpenStoredAsync(string path, string? profile) => OpenStoredAsync(null, path, profile);

    /// <summary>
    /// Opens stored revision <paramref name="id"/> (its source written to <paramref name="path"/>) under its profile; the
    /// split and the job of it name the revision (the job history's program id), as <c>stream --program ID</c>.
    /// </summary>
    public async Task OpenStoredAsync(long? id, string path, string? profile)
    {
        if (profile is not null && _job is null && !string.Equals(profile, _gate.Profile.Name, StringComparison.OrdinalIgnoreCase))
        {
            _view.SelectedProfile = profile;
            await ProfileChangedAsync().ConfigureAwait(true);
        }

        await OpenAsync(path, id).ConfigureAwait(true);
    }

    /// <summary>
    /// Opens a program: indexes its lines in the background and shows the first screen at once. A program opened from
    /// the store names its revision (<paramref name="storedId"/>): the preview draws its stored blocks, not the file.
    /// </summary>
    public async Task OpenAsync(string path, long? storedId = null)
    {
        if (_job is not null)
        {
            throw new InvalidOperationException("A job is running: abort it before opening another program.");
        }

        if (!File.Exists(path))
        {
            throw new FileNotFoundException($"{path}: no such program file", path);
        }

        CloseProgram();
        _openedRevision = _programId = storedId; // after CloseProgram, which forgets the revision of the program before
        var source = ProgramLineSource.Open(path);
        _program = source;
        _view.ProgramPath = path;
        _toolpath.Open(path, _gate.Profile, storedId);
        await source.WaitForLinesAsync(FirstScreenLines, _life.Token).ConfigureAwait(true);
        if (source.Completion.IsFaulted)
        {
            CloseProgram();
            await source.Completion.ConfigureAwait(true);
        }

        RefreshProgramLineCount();
        _log.Information("Opened {Path:l} ({Size:N0} bytes)", path, source.FileSize);
        RefreshCommands();
        RefreshStatus();
    }

    /// <summary>The text of program line <paramref name="line"/> for the virtual list.</summary>
    public string ProgramLine(int line) =>
        _program is { } p && line >= 1 && line <= p.IndexedLines ? p.GetLine(line) : string.Empty;

    /// <inheritdoc />
    public async ValueTask DisposeAsync()
    {
        _life.Cancel();
        try
        {
            await WhenIdleAsync().ConfigureAwait(false);
        }
        catch (Exception)
        {
            // Already reported when it happened.
        }

        if (_job is not null)
        {
            await _job.DisposeAsync().ConfigureAwait(false);
            _job = null;
        }

        await _connection.DisposeAsync().ConfigureAwait(false);

        // No view calls here: the window may already be gone (the application disposes after the message loop).
        _program?.Dispose();
        _program = null;
        _chunkLines.Dispose();
        _toolpath.Dispose();
        _life.Dispose();
    }

    private string T(TextId id) => HmiText.Get(id, _language);

    private string F(TextId id, params object[] args) => HmiText.Format(id, _language, args);

    /// <summary>Runs an operation started by a view event: commands are disabled meanwhile, errors are shown.</summary>
    private void Run(Func<Task> operation) => _ops.Run(operation);

    private void OperationFailed(Exception e)
    {
        _log.Error("{Message:l}", e.Message);
        _view.ShowError(e.Message);
    }

    private void OperationsChanged()
    {
        DrainLog();
        RefreshCommands();
        RefreshStatus();
    }

    private Task ChangeLanguageAsync()
    {
        _language = _view.Language;
        _toolpath.Language = _language;
        _view.Texts = HmiText.All(_language);
        _connection.ShowState(_language);
        ShowChunkFiles();
        return Task.CompletedTask;
    }

    private async Task SplitAsync()
    {
        var program = _program ?? throw new InvalidOperationException("Open a program first.");
        // The job service checks the shape (one place: ChunkShape.Validate); the box only offers 1 and more.
        _settings = _settings with { BlocksPerChunk = _view.BlocksPerChunk };

        // The job service's gate: the program is checked under the machine profile whether or not Check ran. A file
        // is found in or imported into the store as it is split (at each split: it may have been edited since).
        var split = await _gate.SplitAsync(program.Path, _settings, _language, _life.Token, _openedRevision).ConfigureAwait(true);
        SetSplit(split);
        _log.Information("Split {Path:l}{Revision:l} into {Chunks} chunk files ({Blocks} blocks) in {Directory:l}",
            program.Path, split.ProgramId is { } id ? $" (program {id} of the store)" : string.Empty, split.Chunks.Count, split.TotalBlocks, split.Folder);
        if (split.NotStored is { } why)
        {
            _log.Warning("Not stored, run as a file (its job records no program): {Why:l}", why);
        }
    }

    /// <summary>Another machine profile: the check and the split were the old one's; the toolpath is drawn under the new one, the simulator gets its library.</summary>
    private async Task ProfileChangedAsync()
    {
        if (!_gate.ChooseProfile(_job is not null))
        {
            return;
        }

        DropSplit();
        if (_program is { } p)
        {
            _toolpath.Open(p.Path, _gate.Profile, _programId);
        }

        if (_connection.Link is not null)
        {
            await _backend.LoadLibraryAsync(_gate.Profile, _life.Token).ConfigureAwait(true);
        }
    }

    private async Task OptionalStopChangedAsync()
    {
        _optionalStop = _view.OptionalStop;
        if (_job is { } job)
        {
            await job.SetOptionalStopAsync(_optionalStop, _life.Token).ConfigureAwait(true);
        }

        _log.Information("Optional stop {State:l}", _optionalStop ? "on (M01 stops)" : "off (M01 runs through)");
    }

    private Task DownloadWindowChangedAsync()
    {
        var (start, end) = _view.DownloadWindow;
        var next = _settings with { WindowStart = start, WindowEnd = end };
        try
        {
            next.Validate();
        }
        catch (ArgumentException e)
        {
            _view.DownloadWindow = (_settings.WindowStart, _settings.WindowEnd);
            throw new InvalidOperationException(e.Message, e);
        }

        _settings = next;
        _log.Information("Download window set to {Window:l} of a chunk{When:l}", next.Window, _job is null ? string.Empty : " (from the next job)");
        return Task.CompletedTask;
    }

    /// <summary>
    /// The split to run: the program is now the revision it was prepared from (its job, start from a line and the
    /// executed path read the store), or the opened one.
    /// </summary>
    private void SetSplit(SplitView split)
    {
        _split = split;
        _programId = split.ProgramId ?? _openedRevision;
        _toolpath.Stored(_programId);
        _chunkLines.SetProgram(split);
        ShowChunkFiles();
    }

    private void DropSplit()
    {
        _split = null;
        _programId = _openedRevision; // a file's revision is its split's (under another profile it is another revision)
        _chunkLines.SetProgram(null);
        ShowChunkFiles();
    }

    private void ShowChunkFiles()
    {
        _view.ChunkFiles = _split is null
            ? []
            : _split.Chunks.Select(c => F(TextId.ChunkRow, c.FileName, c.FirstSourceLine, c.LastSourceLine, c.BlockCount)).ToList();
    }

    private void SelectChunk(int index)
    {
        _chunkLines.Select(index, _job is null ? 0 : _lastStatus?.CurrentChunk ?? 0);
        if (_split is { } split && index >= 0 && index < split.Chunks.Count)
        {
            _view.FocusedLine = split.Chunks[index].FirstSourceLine;
        }

        if (_lastStatus is { } s)
        {
            // The executing block stays highlighted when it lies in the chunk chosen.
            _chunkLines.Follow(s.CurrentChunk, s.CurrentLine);
        }
    }

    private async Task StartFromSelectedLineAsync()
    {
        var split = RequireReady();
        var line = _view.SelectedLine;
        if (line < 1)
        {
            throw new InvalidOperationException(T(TextId.SelectLineFirst));
        }

        var to = _view.ToBlock;
        var preamble = await _backend.BuildPreambleAsync(split, line, _settings, _gate.Profile, _life.Token).ConfigureAwait(true);
        var text = F(TextId.ConfirmStartText, line, string.Join(Environment.NewLine, preamble)) + (to is { } last ? Environment.NewLine + F(TextId.ConfirmRangeEnd, last) : string.Empty);
        var ok = await _view.ConfirmAsync(T(TextId.ConfirmStartTitle), text).ConfigureAwait(true);
        if (!ok)
        {
            _log.Information("Start from line {Line} declined by the operator", line);
            return;
        }

        await StartAsync(line, to).ConfigureAwait(true);
    }

    private async Task StartAsync(int? fromLine, int? toLine = null)
    {
        var split = RequireReady();
        var request = new HmiJobRequest(split, _view.SelectedStrategy, fromLine, _view.SingleBlock, _feedOverride, _settings)
        {
            Profile = _gate.Profile, OptionalStop = _optionalStop, ProgramId = _programId, ToLine = toLine,
        };
        var job = await _backend.StartAsync(request, _life.Token).ConfigureAwait(true);
        BeginJob(job, request.Strategy, fromLine ?? 1);
        _log.Information("Job started{From:l} with strategy {Strategy:l}, feed override {Override} %",
            fromLine is null ? string.Empty : $" from line {fromLine}", request.Strategy, _feedOverride);
    }

    private async Task ResumeInterruptedAsync()
    {
        if (_job is not null)
        {
            throw new InvalidOperationException("A job is already running.");
        }

        var program = _program ?? throw new InvalidOperationException("Open a program first.");
        _ = _connection.Link ?? throw new InvalidOperationException("Connect to a controller first.");
        var interrupted = await _backend.FindInterruptedAsync(program.Path, _life.Token).ConfigureAwait(true)
            ?? throw new InvalidOperationException(T(TextId.NoInterruptedJob));
        var preamble = await _backend.BuildPreambleAsync(interrupted.Program, interrupted.ResumeLine, _settings, _gate.Profile, _life.Token).ConfigureAwait(true);
        var text = F(TextId.ConfirmResumeText, interrupted.JobId, interrupted.ResumeLine, interrupted.Chunk, string.Join(Environment.NewLine, preamble));
        if (!await _view.ConfirmAsync(T(TextId.ConfirmResumeTitle), text).ConfigureAwait(true))
        {
            _log.Information("Resume of job {Job} declined by the operator", interrupted.JobId);
            return;
        }

        if (_split is null || _split.Folder != interrupted.Program.Folder)
        {
            SetSplit(interrupted.Program);
        }

        var job = await _backend.ResumeInterruptedAsync(interrupted, _feedOverride, _settings, _gate.Profile, _optionalStop, _life.Token).ConfigureAwait(true);
        BeginJob(job, interrupted.Strategy, interrupted.ResumeLine);
        _log.Information("Job {Job} resumed at line {Line} (chunk {Chunk})", interrupted.JobId, interrupted.ResumeLine, interrupted.Chunk);
    }

    private SplitView RequireReady()
    {
        if (_job is not null)
        {
            throw new InvalidOperationException("A job is already running.");
        }

        if (_connection.Link is null)
        {
            throw new InvalidOperationException("Connect to a controller first.");
        }

        return _split ?? throw new InvalidOperationException("Split the program first.");
    }

    private void BeginJob(IHmiJob job, string strategy, int firstLine)
    {
        _job = job;
        _jobSettings = _settings;
        _jobStrategy = strategy;
        _lastStatus = job.Status;
        _shownExecutingLine = -1;
        _chunkLines.BeginJob();
        _toolpath.BeginJob(firstLine);
        ShowJob();
    }

    private async Task FinishJobAsync()
    {
        var job = _job;
        _job = null;
        if (job is not null)
        {
            await job.DisposeAsync().ConfigureAwait(true);
        }

        var s = _lastStatus;
        if (s is not null)
        {
            if (s.State == HmiJobState.Failed)
            {
                _view.ShowError(s.Message ?? T(TextId.StateFailed));
            }

            _log.Information("Job {State} at line {Line}, {Percent:0.0}%{Message:l}", s.State, s.CurrentLine, s.Percent,
                s.Message is null ? string.Empty : ": " + s.Message);
        }

        ShowJob();
        RefreshCommands();
    }

    private async Task JobCommandAsync(Func<IHmiJob, Task> command, string name)
    {
        var job = _job ?? throw new InvalidOperationException("No job is running.");
        await command(job).ConfigureAwait(true);
        _lastStatus = job.Status;
        _log.Information("Operator {Command:l} at line {Line}", name, _lastStatus.CurrentLine);
        if (_lastStatus.IsFinished)
        {
            await FinishJobAsync().ConfigureAwait(true);
        }
        else
        {
            ShowJob();
        }
    }

    private async Task SingleBlockChangedAsync()
    {
        var on = _view.SingleBlock;
        if (_job is { } job)
        {
            await job.SetSingleBlockAsync(on, _life.Token).ConfigureAwait(true);
        }

        _log.Information("Single block {State:l}", on ? "on" : "off");
    }

    private async Task FeedOverrideChangedAsync()
    {
        // The operator's setting holds: the program's F words never change it (they set the programmed feed only).
        var value = Math.Clamp(_view.FeedOverride, FeedOverrides.Minimum, FeedOverrides.Maximum);
        _feedOverride = value;
        if (_job is { } job)
        {
            await job.SetFeedOverrideAsync(value, _life.Token).ConfigureAwait(true);
            _lastStatus = job.Status;
        }

        _log.Information("Feed override set to {Override} %", value);
    }

    private void ShowJob()
    {
        var line = _lastStatus?.CurrentLine ?? 0;
        if (line != _shownExecutingLine)
        {
            _shownExecutingLine = line;
            _view.ExecutingLine = line;
        }

        if (_lastStatus is { } s)
        {
            _chunkLines.Follow(s.CurrentChunk, s.CurrentLine);
        }

        var banner = StatusStrip.Banner(_job is null ? null : _lastStatus, _language);
        if (banner.Length > 0 && banner != _banner)
        {
            _log.Information("{Stop:l}", StatusStrip.Banner(_lastStatus, HmiLanguage.English));
        }

        _view.ProgramStopBanner = _banner = banner;
        RefreshCommands();
        RefreshStatus();
    }

    private void DrainLog() => _logSink?.DrainTo(_view);

    private void RefreshProgramLineCount()
    {
        if (_program is { } p && p.IndexedLines != _shownLineCount)
        {
            _shownLineCount = p.IndexedLines;
            _view.ProgramLineCount = _shownLineCount;
            RefreshStatus();
        }
    }

    private void RefreshCommands() =>
        _view.Commands = CommandRules.For(_ops.Busy > 0 || _connection.Connecting, _connection.Link is not null, _program is not null, _split is not null, _job is not null,
            _lastStatus?.State == HmiJobState.Held, _job is not null && _lastStatus?.State == HmiJobState.Stopped);

    private void RefreshStatus()
    {
        var active = _job is not null;
        _view.Status = StatusStrip.Show(
            new StatusFacts(_lastStatus, active, _split, _program, _feedOverride, active ? _jobSettings : _settings, active ? _jobStrategy : _view.SelectedStrategy),
            _language);
    }

    private void CloseProgram()
    {
        _program?.Dispose();
        _program = null;
        _openedRevision = _programId = null;
        _shownLineCount = 0;
        DropSplit();
        _toolpath.Close();
        _view.ProgramLineCount = 0;
        _gate.Clear();
    }
}
