using BenchmarkDotNet.Attributes;
using PmacStream.Benchmarks.Generators;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preview;

namespace PmacStream.Benchmarks.Hmi;

/// <summary>
/// The HMI opening a 10,000,000-line program (about 360 MB, generated once into the temp folder and deleted
/// afterwards): time until the first screen of ListBox2 is served through the presenter, as the form sees it, and
/// time until the whole file is indexed (which goes on in the background while the operator already scrolls).
/// Goal (issue 8): first screen in under 2 s.
/// Run: <c>dotnet run -c Release --project bench/PmacStream.Benchmarks -- --filter '*OpenLargeProgram*'</c>.
/// </summary>
[SimpleJob(launchCount: 1, warmupCount: 1, iterationCount: 5)]
[MemoryDiagnoser]
public class OpenLargeProgramBenchmark
{
    private const int Lines = 10_000_000;
    private const int ScreenRows = 40;
    private string _path = string.Empty;

    [GlobalSetup]
    public void Setup()
    {
        _path = Path.Combine(Path.GetTempPath(), $"pmacstream-hmi-bench-{Lines}.nc");
        if (!File.Exists(_path))
        {
            SurfacingGenerator.Write(_path, Lines);
        }
    }

    [GlobalCleanup]
    public void Cleanup() => File.Delete(_path);

    /// <summary>Open through the presenter and fetch the rows of the first screen.</summary>
    [Benchmark]
    public async Task<int> FirstScreenThroughPresenter()
    {
        var view = new NullView();
        await using var presenter = new MainPresenter(view, new NoBackend());
        await presenter.OpenAsync(_path);
        var chars = 0;
        for (var i = 1; i <= ScreenRows; i++)
        {
            chars += presenter.ProgramLine(i).Length;
        }

        return chars + view.ProgramLineCount;
    }

    /// <summary>Index the whole file (the background scan's total time).</summary>
    [Benchmark]
    public async Task<int> WholeIndex()
    {
        using var source = ProgramLineSource.Open(_path);
        await source.Completion;
        return source.IndexedLines + source.GetLine(Lines - 1).Length;
    }

    /// <summary>Jump to a line near the end (scroll-bar drag) once indexed.</summary>
    [Benchmark]
    public async Task<int> JumpToEndAfterIndex()
    {
        using var source = ProgramLineSource.Open(_path);
        await source.Completion;
        var chars = 0;
        for (var i = Lines - ScreenRows; i <= Lines; i++)
        {
            chars += source.GetLine(i).Length;
        }

        return chars;
    }

    private sealed class NoBackend : IHmiBackend
    {
        public IReadOnlyList<string> Strategies { get; } = ["chunk"];
        public Task<ControllerLink> ConnectAsync(ConnectionSettings settings, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<HmiCheckResult> CheckAsync(string path, HmiLanguage language, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<HmiSplitResult> PrepareAsync(string sourcePath, RunSettings settings, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<IReadOnlyList<string>> BuildPreambleAsync(HmiSplitResult program, int line, RunSettings settings, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<IHmiJob> StartAsync(ControllerLink controller, HmiJobRequest request, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<HmiInterruptedJob?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<IHmiJob> ResumeInterruptedAsync(ControllerLink controller, HmiInterruptedJob job, double feedOverride, RunSettings settings, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public IToolpathSource OpenToolpath(string sourcePath) => new GCodeToolpathSource(sourcePath);
    }

    private sealed class NullView : IMainView
    {
        public IReadOnlyDictionary<TextId, string> Texts { set { } }
        public HmiLanguage Language => HmiLanguage.English;
        public ConnectionSettings ConnectionSettings => new(DeviceKind.Simulator);
        public string ConnectionState { set { } }
        public string ProgramPath { set { } }
        public IReadOnlyList<string> Diagnostics { set { } }
        public int LinesPerChunk { get; set; }
        public (double Start, double End) DownloadWindow { get; set; }
        public IReadOnlyList<string> Strategies { set { } }
        public string SelectedStrategy => "chunk";
        public IReadOnlyList<string> ChunkFiles { set { } }
        public int SelectedChunk { set { } }
        public int ChunkLineCount { set { } }
        public int ChunkExecutingLine { set { } }
        public int ProgramLineCount { get; set; }
        public int ExecutingLine { set { } }
        public int FocusedLine { set { } }
        public int SelectedLine => 0;
        public CommandStates Commands { set { } }
        public bool SingleBlock => false;
        public double FeedOverride { get; set; }
        public ToolpathFrame Toolpath { set { } }
        public string ToolpathCaption { set { } }
        public StatusDisplay Status { set { } }
#pragma warning disable CS0067 // events the benchmark never raises
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
        public event EventHandler? FeedOverrideChanged;
        public event EventHandler? DownloadWindowChanged;
#pragma warning restore CS0067
        public void AppendLog(IReadOnlyList<string> lines) { }
        public Task<bool> ConfirmAsync(string title, string text) => Task.FromResult(false);
        public void ShowError(string message) => throw new InvalidOperationException(message);
    }
}
