using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Testing;

/// <summary>
/// The real splitter, the real simulator with the real PROG 1000/1001 library (what the CLI and the HMI download),
/// and a deterministic tick loop on the simulator's virtual clock: a streaming session on <see cref="SimHarness"/>,
/// the rig's bottom layer.
/// </summary>
public sealed class SimRig : IDisposable
{
    private readonly TestFolder _folder;
    private readonly IReadOnlyDictionary<int, int> _expanded;

    /// <summary>Virtual second 0 of every rig's clock, so checkpoint times are the same in every run.</summary>
    public static readonly DateTimeOffset TestEpoch = new(2026, 1, 1, 0, 0, 0, TimeSpan.Zero);

    /// <summary>The generated PROG 1000/1001 G and M code library for the default machine profile, one line each.</summary>
    public static IReadOnlyList<string> Library { get; } = ControllerLibrary.Lines();

    public SimRig(string source, int blocksPerChunk, StreamingOptions options, TrackingPlacement placement = TrackingPlacement.Exact, SimOptions? simOptions = null)
    {
        _folder = new TestFolder("rig");
        var split = Splitter.Split(source, new SplitOptions { BlocksPerChunk = blocksPerChunk, OutDir = Path.Combine(Folder, "chunks"), Tracking = placement });
        Program = ChunkedProgram.Open(split.ManifestPath);
        _expanded = Program.ExpandedBlocks(); // read now: a test may change a chunk later
        Harness = new SimHarness(simOptions, "stream");
        Connection = new InProcessConnection(Port, "sim");
        LoadLibrary(Port);
        Options = options;
        Time = Clock(Sim);
        Session = new StreamingSession(Connection, Program, options, Sink, time: Time);
    }

    public string Folder => _folder.Path;

    public ChunkedProgram Program { get; }

    /// <summary>The layer below: the simulator and the port the session streams through.</summary>
    public SimHarness Harness { get; }

    public PmacSimulator Sim => Harness.Sim;

    public SimPort Port => Harness.Port;

    public IPmacConnection Connection { get; set; }

    public StreamingOptions Options { get; }

    public SimTimeProvider Time { get; }

    public MemorySink Sink { get; } = new();

    public StreamingSession Session { get; set; }

    /// <summary>Downloads <see cref="Library"/> through a port; the simulator accepts every line of it.</summary>
    public static void LoadLibrary(IPmacPortEndpoint port) =>
        new InProcessConnection(port, "library").DownloadAsync(Library).GetAwaiter().GetResult();

    /// <summary>The simulator's virtual clock as a TimeProvider starting at <see cref="TestEpoch"/>.</summary>
    public static SimTimeProvider Clock(PmacSimulator sim) => new(sim, TestEpoch);

    /// <summary>
    /// The rig's job-service layer: the job service's built-in simulator (<c>JobServiceOptions.Simulator</c>) as the
    /// test's <paramref name="sim"/>, through a port named <paramref name="port"/>, on its <see cref="Clock"/>; with
    /// <paramref name="step"/> the job service advances it (a console's moves), else the test does.
    /// </summary>
    public static Func<CancellationToken, Task<SimulatorLink>> BuiltIn(PmacSimulator sim, string port = "console", bool step = true) =>
        _ => Task.FromResult(new SimulatorLink(new InProcessConnection(sim.OpenPort(port), "simulator (in-process)"), Clock(sim)) { Step = step ? sim.Advance : null });

    public async Task<bool> RunAsync(double virtualSecondsPerTick, int maxTicks = 100_000)
    {
        for (var i = 0; i < maxTicks; i++)
        {
            await Session.TickAsync();
            if (Session.State == SessionState.Completed)
            {
                Sim.RunUntilIdle(TimeSpan.FromHours(1));
                return true;
            }

            if (Session.State is SessionState.Faulted or SessionState.Aborted)
            {
                return false;
            }

            Sim.Advance(TimeSpan.FromSeconds(virtualSecondsPerTick));
        }

        return false;
    }

    /// <summary>The source line of each block executed (a block's further moves not counted, a repeated block twice), preamble (0) left out.</summary>
    public List<int> ExecutedLines() => MoveLines.Blocks(Sim.ExecutedMoves, _expanded);

    public void Dispose()
    {
        Harness.Dispose();
        _folder.Dispose();
    }
}
