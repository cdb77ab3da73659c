using BenchmarkDotNet.Attributes;
using PmacStream.Benchmarks.Generators;
using PmacStream.GCode;
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
        var view = new QuietView();
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
        public Task<string> ConnectAsync(ConnectionSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task DisconnectAsync() => Task.CompletedTask;
        public Task LoadLibraryAsync(MachineProfile profile, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<HmiCheckResult> CheckAsync(string path, MachineProfile profile, HmiLanguage language, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<IReadOnlyList<string>> BuildPreambleAsync(SplitView program, int line, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public ChunkRows ReadChunkRows(SplitView program, int chunk) => throw new NotSupportedException();
        public Task<IHmiJob> StartAsync(HmiJobRequest request, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<InterruptedJobView?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task<IHmiJob> ResumeInterruptedAsync(InterruptedJobView job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public IToolpathSource OpenToolpath(string sourcePath, MachineProfile profile) => new GCodeToolpathSource(sourcePath, profile);
    }
}
