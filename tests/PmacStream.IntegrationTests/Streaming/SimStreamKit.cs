using PmacStream.Pmac;
using PmacStream.Program;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>The real splitter, the real simulator (with a PROG 1000/1001 library) and a deterministic tick loop.</summary>
public sealed class SimRig : IDisposable
{
    /// <summary>Virtual second 0 of every rig's clock, so checkpoint times are the same in every run.</summary>
    public static readonly DateTimeOffset TestEpoch = new(2026, 1, 1, 0, 0, 0, TimeSpan.Zero);

    public static readonly string[] Library =
    [
        "OPEN PROG 1000 CLEAR",
        "N0 RAPID RET",
        "N1000 LINEAR RET",
        "N2000 CIRCLE1 RET",
        "N3000 CIRCLE2 RET",
        "N4000 READ(P) DWELL(Q116) RET",
        "N17000 NORMAL K-1 RET",
        "N18000 NORMAL J-1 RET",
        "N19000 NORMAL I-1 RET",
        "N90000 ABS RET",
        "N91000 INC RET",
        "CLOSE",
        "OPEN PROG 1001 CLEAR",
        "N3000 M1=1 RET",
        "N5000 DWELL0 M1=0 RET",
        "CLOSE",
    ];

    public SimRig(string source, int linesPerChunk, StreamingOptions options, TrackingPlacement placement = TrackingPlacement.Exact, SimOptions? simOptions = null)
    {
        Folder = Path.Combine(Path.GetTempPath(), "pmacstream-it", Guid.NewGuid().ToString("N"));
        Directory.CreateDirectory(Folder);
        var split = Splitter.Split(source, new SplitOptions { LinesPerChunk = linesPerChunk, OutDir = Path.Combine(Folder, "chunks"), Tracking = placement });
        Program = ChunkedProgram.Open(split.ManifestPath);
        Sim = new PmacSimulator(simOptions);
        Port = Sim.OpenPort("stream");
        Connection = new InProcessConnection(Port, "sim");
        Connection.DownloadAsync(Library).GetAwaiter().GetResult();
        Options = options;
        Time = new SimTimeProvider(Sim, TestEpoch);
        Session = new StreamingSession(Connection, Program, options, Sink, time: Time);
    }

    public string Folder { get; }

    public ChunkedProgram Program { get; }

    public PmacSimulator Sim { get; }

    public SimPort Port { get; }

    public IPmacConnection Connection { get; set; }

    public StreamingOptions Options { get; }

    public SimTimeProvider Time { get; }

    public MemorySinkIt Sink { get; } = new();

    public StreamingSession Session { get; set; }

    public static string RepoRoot()
    {
        var d = new DirectoryInfo(AppContext.BaseDirectory);
        while (d is not null && !File.Exists(Path.Combine(d.FullName, "PmacStream.sln")))
        {
            d = d.Parent;
        }

        return d?.FullName ?? throw new InvalidOperationException("repo root not found");
    }

    public static string DemoPath => Path.Combine(RepoRoot(), "samples", "demo.nc");

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

    /// <summary>Source lines of executed moves, consecutive repeats (one block, several moves) folded, preamble (0) left out.</summary>
    public List<int> ExecutedLines()
    {
        var list = new List<int>();
        foreach (var m in Sim.ExecutedMoves)
        {
            if (m.SourceLine > 0 && (list.Count == 0 || list[^1] != m.SourceLine))
            {
                list.Add(m.SourceLine);
            }
        }

        return list;
    }

    public void Dispose()
    {
        Sim.Dispose();
        try
        {
            Directory.Delete(Folder, true);
        }
        catch (IOException)
        {
        }
    }
}

public sealed class MemorySinkIt : ICheckpointSink
{
    public Checkpoint? Last { get; private set; }

    public JobStart? Start { get; private set; }

    public void Save(Checkpoint checkpoint, bool durable) => Last = checkpoint;

    public void RecordStart(JobStart start) => Start = start;

    /// <summary>The job record a host would read back after dying (what the job store keeps).</summary>
    public JobRecord Record() => new(1, "p.nc", string.Empty, "manifest.json", StrategyKind.Chunk, "sim", Start?.FromLine, string.Empty, Last,
        DateTimeOffset.UnixEpoch, Start?.Preamble, Start is null ? "P501" : Start.LineProbeVariable);
}
