using System.Text;
using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preview;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>A view that records what the presenter shows and lets tests raise the form's events.</summary>
internal sealed class FakeView : IMainView
{
    public IReadOnlyDictionary<TextId, string> Texts { get; set; } = new Dictionary<TextId, string>();
    public HmiLanguage Language { get; set; }
    public ConnectionSettings ConnectionSettings { get; set; } = new(DeviceKind.Simulator);
    public string ConnectionState { get; set; } = string.Empty;
    public string ProgramPath { get; set; } = string.Empty;
    public IReadOnlyList<string> Diagnostics { get; set; } = [];
    public int BlocksPerChunk { get; set; }
    public (double Start, double End) DownloadWindow { get; set; }
    public IReadOnlyList<string> Strategies { get; set; } = [];
    public string SelectedStrategy { get; set; } = "chunk";
    public IReadOnlyList<string> Profiles { get; set; } = [];
    public string SelectedProfile { get; set; } = string.Empty;
    public bool OptionalStop { get; set; }
    public List<string> Banners { get; } = [];
    public string ProgramStopBanner { get => Banners.Count == 0 ? string.Empty : Banners[^1]; set => Banners.Add(value); }
    public IReadOnlyList<string> ChunkFiles { get; set; } = [];
    public List<int> SelectedChunks { get; } = [];
    public int SelectedChunk { get => SelectedChunks.Count == 0 ? -1 : SelectedChunks[^1]; set => SelectedChunks.Add(value); }
    public int ChunkLineCount { get; set; }
    public List<int> ChunkExecutingLines { get; } = [];
    public int ChunkExecutingLine { get => ChunkExecutingLines.Count == 0 ? 0 : ChunkExecutingLines[^1]; set => ChunkExecutingLines.Add(value); }
    public int ProgramLineCount { get; set; }
    public List<int> ExecutingLines { get; } = [];
    public int ExecutingLine { get => ExecutingLines.Count == 0 ? 0 : ExecutingLines[^1]; set => ExecutingLines.Add(value); }
    public int FocusedLine { get; set; }
    public int SelectedLine { get; set; }

    public int? ToBlock { get; set; }
    public CommandStates Commands { get; set; } = CommandStates.None;
    public bool SingleBlock { get; set; }
    public double FeedOverride { get; set; }
    private ToolpathFrame? _toolpath;
    public ToolpathFrame? Toolpath { get => _toolpath; set { _toolpath = value; ToolpathShown++; } }
    public int ToolpathShown { get; private set; }
    public string ToolpathCaption { get; set; } = string.Empty;
    public StatusDisplay Status { get; set; } = null!;
    public List<string> Log { get; } = [];
    public List<string> Errors { get; } = [];
    public List<(string Title, string Text)> Confirmations { get; } = [];
    public bool ConfirmAnswer { get; set; } = true;

    public event EventHandler? LanguageChanged;
    public event EventHandler? ConnectRequested;
    public event EventHandler? DisconnectRequested;
    public event EventHandler<string>? OpenRequested;
    public event EventHandler? CheckRequested;
    public event EventHandler<int>? DiagnosticActivated;
    public event EventHandler? SplitRequested;
    public event EventHandler<int>? ChunkSelected;
    public event EventHandler<LineRequestEventArgs>? ChunkLineNeeded;
    public event EventHandler<LineRequestEventArgs>? ProgramLineNeeded;
    public event EventHandler? ExecuteRequested;
    public event EventHandler? HoldRequested;
    public event EventHandler? ResumeRequested;
    public event EventHandler? AbortRequested;
    public event EventHandler? StartFromLineRequested;
    public event EventHandler? ResumeInterruptedRequested;
    public event EventHandler? SingleBlockChanged;
    public event EventHandler? OptionalStopChanged;
    public event EventHandler? ProfileChanged;
    public event EventHandler? FeedOverrideChanged;
    public event EventHandler? DownloadWindowChanged;

    public void AppendLog(IReadOnlyList<string> lines) => Log.AddRange(lines);

    public Task<bool> ConfirmAsync(string title, string text)
    {
        Confirmations.Add((title, text));
        return Task.FromResult(ConfirmAnswer);
    }

    public void ShowError(string message) => Errors.Add(message);

    // What the form's controls do.
    public void ChooseLanguage(HmiLanguage l) { Language = l; LanguageChanged?.Invoke(this, EventArgs.Empty); }
    public void ClickConnect() => ConnectRequested?.Invoke(this, EventArgs.Empty);
    public void ClickDisconnect() => DisconnectRequested?.Invoke(this, EventArgs.Empty);
    public void ChooseFile(string path) => OpenRequested?.Invoke(this, path);
    public void ClickCheck() => CheckRequested?.Invoke(this, EventArgs.Empty);
    public void DoubleClickDiagnostic(int i) => DiagnosticActivated?.Invoke(this, i);
    public void ClickSplit() => SplitRequested?.Invoke(this, EventArgs.Empty);
    public void SelectChunk(int i) => ChunkSelected?.Invoke(this, i);
    public void ClickExecute() => ExecuteRequested?.Invoke(this, EventArgs.Empty);
    public void ClickHold() => HoldRequested?.Invoke(this, EventArgs.Empty);
    public void ClickResume() => ResumeRequested?.Invoke(this, EventArgs.Empty);
    public void ClickAbort() => AbortRequested?.Invoke(this, EventArgs.Empty);
    public void ClickStartFromLine() => StartFromLineRequested?.Invoke(this, EventArgs.Empty);
    public void ClickResumeInterrupted() => ResumeInterruptedRequested?.Invoke(this, EventArgs.Empty);
    public void ToggleSingleBlock(bool on) { SingleBlock = on; SingleBlockChanged?.Invoke(this, EventArgs.Empty); }
    public void ToggleOptionalStop(bool on) { OptionalStop = on; OptionalStopChanged?.Invoke(this, EventArgs.Empty); }
    public void ChooseProfile(string name) { SelectedProfile = name; ProfileChanged?.Invoke(this, EventArgs.Empty); }
    public void MoveFeedOverride(double v) { FeedOverride = v; FeedOverrideChanged?.Invoke(this, EventArgs.Empty); }
    public void SetWindow(double start, double end) { DownloadWindow = (start, end); DownloadWindowChanged?.Invoke(this, EventArgs.Empty); }

    public string ProgramRow(int line)
    {
        var e = new LineRequestEventArgs(line);
        ProgramLineNeeded?.Invoke(this, e);
        return e.Text;
    }

    public string ChunkRow(int line)
    {
        var e = new LineRequestEventArgs(line);
        ChunkLineNeeded?.Invoke(this, e);
        return e.Text;
    }
}

/// <summary>
/// Stands in for the checker, splitter and streaming session: a line with "BAD" is an error, every non-empty line
/// is a block, chunk files really are written (no manifest: the split is a view), no controller is opened, and a job advances <see cref="LinesPerTick"/> lines a tick.
/// </summary>
internal sealed class FakeBackend : IHmiBackend
{
    public IReadOnlyList<string> Strategies { get; } = ["chunk", "pr", "adaptive"];
    public int LinesPerTick { get; set; } = 7;
    public List<HmiJobRequest> Started { get; } = [];
    public List<RunSettings> Prepared { get; } = [];
    public List<long?> PreparedRevisions { get; } = [];
    public List<RunSettings> Resumed { get; } = [];
    public List<string> ProfilesUsed { get; } = [];
    public List<string> LibrariesLoaded { get; } = [];
    public List<FakeJob> Jobs { get; } = [];
    public InterruptedJobView? Interrupted { get; set; }
    public bool Connected { get; private set; }

    public Task LoadLibraryAsync(MachineProfile profile, CancellationToken cancellationToken = default)
    {
        LibrariesLoaded.Add(profile.Name);
        return Task.CompletedTask;
    }

    public Task<string> ConnectAsync(ConnectionSettings settings, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        LibrariesLoaded.Add(profile.Name);
        if (settings.Device == DeviceKind.Ethernet && settings.EthernetAddress == "unreachable")
        {
            throw new PmacLinkException("ethernet unreachable:1025: connection refused");
        }

        Connected = true;
        return Task.FromResult("fake");
    }

    public Task DisconnectAsync()
    {
        Connected = false;
        return Task.CompletedTask;
    }

    public Task<HmiCheckResult> CheckAsync(string path, MachineProfile profile, HmiLanguage language, CancellationToken cancellationToken = default)
    {
        ProfilesUsed.Add("check " + profile.Name);
        var diags = new List<Diagnostic>();
        var blocks = 0;
        var n = 0;
        foreach (var line in File.ReadLines(path))
        {
            n++;
            if (line.Trim().Length > 0)
            {
                blocks++;
            }

            var col = line.IndexOf("BAD", StringComparison.Ordinal);
            if (col >= 0)
            {
                diags.Add(new Diagnostic(Severity.Error, "E101", n, col + 1, language == HmiLanguage.Chinese ? "非法字符 'B'" : "illegal character 'B'"));
            }
        }

        return Task.FromResult(HmiCheckResult.FromList(diags, blocks));
    }

    /// <summary>Refuses a program with a "BAD" line (the service's gate), else writes chunk files of <see cref="RunSettings.BlocksPerChunk"/> lines.</summary>
    public async Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, long? programId, CancellationToken cancellationToken = default)
    {
        PreparedRevisions.Add(programId);
        var split = await PrepareAsync(sourcePath, settings, profile, cancellationToken);
        if (programId is not null || StoreFilesAs is null)
        {
            return split with { ProgramId = programId };
        }

        var (id, why) = StoreFilesAs(sourcePath, profile);
        return split with { ProgramId = id, NotStored = why };
    }

    /// <summary>As a backend with a store: the revision a file's split names (or why it is not stored); null: a file stays a file.</summary>
    public Func<string, MachineProfile, (long? Id, string? NotStored)>? StoreFilesAs { get; set; }

    public async Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        Prepared.Add(settings);
        ProfilesUsed.Add("prepare " + profile.Name);
        var check = await CheckAsync(sourcePath, profile, HmiLanguage.English, cancellationToken);
        if (check.Errors > 0)
        {
            throw new ProgramRefusedException(sourcePath, check.Diagnostics, check.Errors, $"{check.Errors} error(s)");
        }

        return Split(sourcePath, settings.BlocksPerChunk);
    }

    public SplitView Split(string sourcePath, int linesPerChunk)
    {
        var lines = File.ReadAllLines(sourcePath);
        var dir = Path.Combine(Path.GetDirectoryName(sourcePath)!, Path.GetFileNameWithoutExtension(sourcePath) + "_chunks");
        Directory.CreateDirectory(dir);
        var chunks = new List<ChunkView>();
        for (int first = 1, index = 1; first <= lines.Length; first += linesPerChunk, index++)
        {
            var last = Math.Min(lines.Length, first + linesPerChunk - 1);
            var name = $"{Path.GetFileNameWithoutExtension(sourcePath)}_{index:0000}.pmc";
            var sb = new StringBuilder("CLOSE\nOPEN ROT\n");
            for (var i = first; i <= last; i++)
            {
                sb.Append("M0==").Append(i).Append(' ').Append(lines[i - 1]).Append(" F(P500)\n");
            }

            sb.Append("CLOSE\n");
            File.WriteAllText(Path.Combine(dir, name), sb.ToString());
            chunks.Add(new ChunkView(index, name, first, last, last - first + 1));
        }

        return new SplitView(sourcePath, dir, chunks, lines.Length);
    }

    /// <summary>Row r + 2 of a chunk file tracks its r-th line (after CLOSE and OPEN ROT).</summary>
    public ChunkRows ReadChunkRows(SplitView program, int chunk)
    {
        var c = program.Chunks[chunk - 1];
        var lines = Enumerable.Range(c.FirstSourceLine, c.LastSourceLine - c.FirstSourceLine + 1).ToArray();
        return new ChunkRows(lines, lines.Select(l => l - c.FirstSourceLine + 3).ToArray());
    }

    public Task<IReadOnlyList<string>> BuildPreambleAsync(SplitView program, int line, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        ProfilesUsed.Add("preamble " + profile.Name);
        return Task.FromResult<IReadOnlyList<string>>(["G21 G17 G90 G54", $"RAPID Z50 (to line {line})"]);
    }

    public Task<IHmiJob> StartAsync(HmiJobRequest request, CancellationToken cancellationToken = default)
    {
        Started.Add(request);
        ProfilesUsed.Add("start " + request.Profile.Name);
        var job = new FakeJob(request.Program, request.FromLine ?? 1, LinesPerTick, request.SingleBlock, request.FeedOverride) { OptionalStop = request.OptionalStop, StopAt = StopAt };
        Jobs.Add(job);
        return Task.FromResult<IHmiJob>(job);
    }

    public Task<InterruptedJobView?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) =>
        Task.FromResult(Interrupted is { } j && j.Program.SourcePath == sourcePath ? j : null);

    /// <summary>Where the next job started stops (a program stop at that line), null for none.</summary>
    public JobStop? StopAt { get; set; }

    public Task<IHmiJob> ResumeInterruptedAsync(InterruptedJobView job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop,
        CancellationToken cancellationToken = default)
    {
        ProfilesUsed.Add("resume " + profile.Name);
        Resumed.Add(settings);
        var j = new FakeJob(job.Program, job.ResumeLine, LinesPerTick, false, feedOverride);
        Jobs.Add(j);
        return Task.FromResult<IHmiJob>(j);
    }

    /// <summary>The revisions whose preview was asked from the store, in order.</summary>
    public List<long> StoredToolpaths { get; } = [];

    public IToolpathSource OpenStoredToolpath(long programId, string sourcePath, MachineProfile profile)
    {
        StoredToolpaths.Add(programId);
        return new GCodeToolpathSource(sourcePath, profile);
    }

    public IToolpathSource OpenToolpath(string sourcePath, MachineProfile profile)
    {
        ProfilesUsed.Add("toolpath " + profile.Name);
        return new GCodeToolpathSource(sourcePath, profile);
    }
}

internal sealed class FakeJob(SplitView manifest, int firstLine, int linesPerTick, bool singleBlock, double feedOverride) : IHmiJob
{
    private int _line = firstLine - 1;
    private HmiJobState _state = HmiJobState.Running;
    private double _override = feedOverride;
    private int _ticks;

    public List<string> Commands { get; } = [];
    public bool SingleBlock { get; private set; } = singleBlock;
    public bool Disposed { get; private set; }
    public Exception? FailOnTick { get; set; }

    /// <summary>The override the controller reports while it slews to a new setting (null: the setting).</summary>
    public double? ControllerOverride { get; set; }

    /// <summary>The program's feed at the executing block (what P500 carries).</summary>
    public double? ProgrammedFeed { get; set; }

    public bool OptionalStop { get; set; } = true;

    /// <summary>A program stop the job reaches (it stops there once), null for none.</summary>
    public JobStop? StopAt { get; set; }

    public HmiJobStatus Status => new(_state, manifest.Chunks.FirstOrDefault(c => c.LastSourceLine >= Math.Max(1, _line))?.Number ?? 0, _line,
        100.0 * _line / manifest.TotalBlocks, ControllerOverride ?? _override, ProgrammedFeed, TimeSpan.FromSeconds(_ticks), TimeSpan.FromSeconds(manifest.TotalBlocks - _line),
        Stop: _state == HmiJobState.Stopped ? StopAt : null, OptionalStop: OptionalStop);

    public TaskCompletionSource? TickGate { get; set; }
    public int TickCalls { get; private set; }

    public async Task TickAsync(CancellationToken cancellationToken = default)
    {
        TickCalls++;
        if (TickGate is { } gate)
        {
            await gate.Task;
        }

        if (FailOnTick is { } e)
        {
            throw e;
        }

        _ticks++;
        if (_state == HmiJobState.Running && !SingleBlock)
        {
            Advance(linesPerTick);
        }
    }

    private void Advance(int n)
    {
        if (StopAt is { } stop && _line < stop.Line && _line + n >= stop.Line)
        {
            _line = stop.Line;
            _state = HmiJobState.Stopped;
            return;
        }

        _line = (int)Math.Min(manifest.TotalBlocks, _line + n);
        if (_line == manifest.TotalBlocks)
        {
            _state = HmiJobState.Completed;
        }
    }

    public Task HoldAsync(CancellationToken cancellationToken = default) { Commands.Add("H"); _state = HmiJobState.Held; return Task.CompletedTask; }

    public Task ResumeAsync(CancellationToken cancellationToken = default)
    {
        Commands.Add("R");
        if (_state == HmiJobState.Stopped)
        {
            StopAt = null; // left: the next ticks move on
        }

        _state = HmiJobState.Running;
        if (SingleBlock)
        {
            Advance(1);
        }

        return Task.CompletedTask;
    }

    public Task AbortAsync(CancellationToken cancellationToken = default) { Commands.Add("A"); _state = HmiJobState.Aborted; return Task.CompletedTask; }
    public Task SetFeedOverrideAsync(double percent, CancellationToken cancellationToken = default) { Commands.Add($"%{percent}"); _override = percent; return Task.CompletedTask; }
    public Task SetSingleBlockAsync(bool on, CancellationToken cancellationToken = default) { Commands.Add($"single={on}"); SingleBlock = on; return Task.CompletedTask; }
    public Task SetOptionalStopAsync(bool on, CancellationToken cancellationToken = default) { Commands.Add($"optional-stop={on}"); OptionalStop = on; return Task.CompletedTask; }
    public ValueTask DisposeAsync() { Disposed = true; return ValueTask.CompletedTask; }
}
