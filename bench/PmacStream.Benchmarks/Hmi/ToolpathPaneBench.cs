using System.Diagnostics;
using System.Globalization;
using PmacStream.Benchmarks.Generators;
using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preview;

namespace PmacStream.Benchmarks.Hmi;

/// <summary>
/// The HMI's toolpath pane on a large program, whole-process (issue 18): the presenter opens a generated surfacing
/// program (10,000,000 lines by default, about 360 MB), ticked every 50 ms as the form's timer does, until the pane
/// shows the planned toolpath (time to first picture); then a job whose M0 runs through the whole program in big
/// steps, so the pane traces every executed move (UI time per tick, the whole trace); peak memory of the process
/// (VmHWM), and the live managed heap after a full collection once the picture is shown and once the trace is done
/// (what the pane keeps, as opposed to the garbage the interpreter's pass leaves for the next collection).
/// Run: <c>dotnet run -c Release --project bench/PmacStream.Benchmarks -- hmi-toolpath [LINES] [LINES_PER_TICK]</c>
/// (or <c>bench/scripts/toolpath-pane-bench.sh</c>).
/// </summary>
public static class ToolpathPaneBench
{
    private static readonly TimeSpan Tick = TimeSpan.FromMilliseconds(50);

    /// <summary>Runs the benchmark; returns the exit code.</summary>
    public static int Run(string[] args)
    {
        var lines = args.Length > 0 ? long.Parse(args[0], CultureInfo.InvariantCulture) : 10_000_000;
        var perTick = args.Length > 1 ? int.Parse(args[1], CultureInfo.InvariantCulture) : 200_000;
        var dir = Directory.CreateTempSubdirectory("pmacstream-toolpath-bench-").FullName;
        try
        {
            var path = Path.Combine(dir, "big.nc");
            var gen = Stopwatch.StartNew();
            SurfacingGenerator.Write(path, lines);
            Console.WriteLine($"program: {lines:N0} lines, {new FileInfo(path).Length / 1e6:0} MB, generated in {gen.Elapsed.TotalSeconds:0.0} s");
            RunAsync(path, (int)lines, perTick, dir).GetAwaiter().GetResult();
            return 0;
        }
        finally
        {
            Directory.Delete(dir, recursive: true);
        }
    }

    private static async Task RunAsync(string path, int lines, int perTick, string dir)
    {
        var baseline = Process.GetCurrentProcess().WorkingSet64;

        var view = new QuietView();
        var backend = new BenchBackend(dir, lines, perTick);
        await using var presenter = new MainPresenter(view, backend);
        var clock = Stopwatch.StartNew();
        var cpu = Process.GetCurrentProcess().TotalProcessorTime;
        await presenter.OpenAsync(path);
        while (!presenter.ToolpathReady)
        {
            await Task.Delay(Tick);
            await presenter.TickAsync();
        }

        var firstPicture = clock.Elapsed;
        var pictureCpu = Process.GetCurrentProcess().TotalProcessorTime - cpu;
        var liveAtPicture = GC.GetTotalMemory(forceFullCollection: true);
        Console.WriteLine($"first picture: {firstPicture.TotalSeconds:0.00} s after open, {pictureCpu.TotalSeconds:0.00} s CPU ({view.Caption})");

        view.Connect();
        await presenter.WhenIdleAsync();
        view.Split();
        await presenter.WhenIdleAsync();
        view.Execute();
        await presenter.WhenIdleAsync();

        // M0 runs through the program in big steps; each tick the pane draws what it can within its budget.
        var ticks = new List<double>();
        clock.Restart();
        var stall = 0;
        var lastDrawn = -1L;
        while (presenter.JobActive || presenter.ToolpathExecutedMoves != lastDrawn)
        {
            lastDrawn = presenter.ToolpathExecutedMoves;
            var t = Stopwatch.StartNew();
            await presenter.TickAsync();
            ticks.Add(t.Elapsed.TotalMilliseconds);
            stall = presenter.ToolpathExecutedMoves == lastDrawn && !presenter.JobActive ? stall + 1 : 0;
            if (stall > 3)
            {
                break;
            }
        }

        var trace = clock.Elapsed;
        var liveAfterTrace = GC.GetTotalMemory(forceFullCollection: true);
        var process = Process.GetCurrentProcess();
        ticks.Sort();
        Console.WriteLine($"executed trace: {presenter.ToolpathExecutedMoves:N0} moves in {trace.TotalSeconds:0.0} s over {ticks.Count} ticks; " +
            $"UI time per tick median {ticks[ticks.Count / 2]:0.0} ms, 99th percentile {ticks[(int)(ticks.Count * 0.99)]:0.0} ms, max {ticks[^1]:0.0} ms; " +
            $"{presenter.ToolpathExecutedMoves / Math.Max(1e-9, ticks.Sum() / 1000):N0} moves per second of UI time");
        Console.WriteLine($"memory: peak working set {process.PeakWorkingSet64 / 1e6:0.0} MB (at start {baseline / 1e6:0.0} MB); live managed heap {liveAtPicture / 1e6:0.0} MB with the picture shown, {liveAfterTrace / 1e6:0.0} MB after the trace; frames shown {view.Frames}");
    }

    /// <summary>A job whose M0 advances <c>perTick</c> lines a tick through the program.</summary>
    private sealed class BenchJob(int lines, int perTick) : IHmiJob
    {
        private int _line;

        public HmiJobStatus Status => new(_line >= lines ? HmiJobState.Completed : HmiJobState.Running, 1, _line, 100.0 * _line / lines, 100, 1500, TimeSpan.Zero, null);

        public Task TickAsync(CancellationToken cancellationToken = default)
        {
            _line = Math.Min(lines, _line + perTick);
            return Task.CompletedTask;
        }

        public Task HoldAsync(CancellationToken cancellationToken = default) => Task.CompletedTask;

        public Task ResumeAsync(CancellationToken cancellationToken = default) => Task.CompletedTask;

        public Task AbortAsync(CancellationToken cancellationToken = default) => Task.CompletedTask;

        public Task SetFeedOverrideAsync(double percent, CancellationToken cancellationToken = default) => Task.CompletedTask;

        public Task SetSingleBlockAsync(bool on, CancellationToken cancellationToken = default) => Task.CompletedTask;

        public Task SetOptionalStopAsync(bool on, CancellationToken cancellationToken = default) => Task.CompletedTask;

        public ValueTask DisposeAsync() => ValueTask.CompletedTask;
    }

    /// <summary>The core as far as the pane needs it: a one-chunk "split" (its file a stub) and the job above.</summary>
    private sealed class BenchBackend(string dir, int lines, int perTick) : IHmiBackend
    {
        public IReadOnlyList<string> Strategies { get; } = ["chunk"];

        public Task<string> ConnectAsync(ConnectionSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) => Task.FromResult("bench");

        public Task DisconnectAsync() => Task.CompletedTask;

        public Task LoadLibraryAsync(MachineProfile profile, CancellationToken cancellationToken = default) => Task.CompletedTask;

        public Task<HmiCheckResult> CheckAsync(string path, MachineProfile profile, HmiLanguage language, CancellationToken cancellationToken = default) => throw new NotSupportedException();

        public Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default)
        {
            File.WriteAllText(Path.Combine(dir, "big_0001.pmc"), "CLOSE\nOPEN ROT\nM0==8 N8 X1 F(P500)\nCLOSE\n");
            // One chunk spanning the program for the status; its file (and block count) that of an ordinary chunk.
            return Task.FromResult(new SplitView(sourcePath, dir, [new ChunkView(1, "big_0001.pmc", 1, lines, 1)], lines));
        }

        public Task<IReadOnlyList<string>> BuildPreambleAsync(SplitView program, int line, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default) => throw new NotSupportedException();

        public ChunkRows ReadChunkRows(SplitView program, int chunk) => new([8], [3]);

        public Task<IHmiJob> StartAsync(HmiJobRequest request, CancellationToken cancellationToken = default) =>
            Task.FromResult<IHmiJob>(new BenchJob(lines, perTick));

        public Task<InterruptedJobView?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) => Task.FromResult<InterruptedJobView?>(null);

        public Task<IHmiJob> ResumeInterruptedAsync(InterruptedJobView job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop, CancellationToken cancellationToken = default) => throw new NotSupportedException();

        public IToolpathSource OpenToolpath(string sourcePath, MachineProfile profile) => new GCodeToolpathSource(sourcePath, profile);
    }
}
