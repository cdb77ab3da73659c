using System.Globalization;
using System.Net;
using BenchmarkDotNet.Attributes;
using BenchmarkDotNet.Configs;
using BenchmarkDotNet.Engines;
using BenchmarkDotNet.Jobs;
using BenchmarkDotNet.Toolchains.InProcess.Emit;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Sim.Servers;

namespace PmacStream.Benchmarks.Transport;

/// <summary>
/// Download of a 1,000,000-line program over TCP loopback to the simulator's VR_PMAC server: WRITEBUFFER batching
/// (<see cref="EthernetConnection.DownloadAsync(IReadOnlyList{string}, CancellationToken)"/>) against one GETRESPONSE per line. Both report the time per line
/// (OperationsPerInvoke), so lines/s = 1 / Mean and the Ratio column is the speed-up. Line-at-a-time sends the first
/// 100,000 lines only: each line is one independent round trip, so its per-line time does not depend on the length,
/// and 1,000,000 round trips take minutes per iteration on a shared machine.
/// Goal (issue 6): batching at least 10x faster and at least 100,000 lines/s.
/// </summary>
[Config(typeof(DownloadBenchmarkConfig))]
public class DownloadBenchmark
{
    private string[] _lines = [];
    private PmacTcpServer? _server;
    private EthernetConnection? _connection;
    private string[] _prepare = [];
    private IDisposable? _engine;

    /// <summary>Program length.</summary>
    public const int Lines = 1_000_000;

    /// <summary>Lines sent by the line-at-a-time method.</summary>
    public const int LineAtATimeLines = 100_000;

    /// <summary>
    /// What answers behind the server: "fast" = a minimal endpoint (transport cost only); "sim" = the simulator engine
    /// in instant mode, storing the program in PROG 1 (program buffers have no size limit in the simulator).
    /// </summary>
    [Params("fast", "sim")]
    public string Engine { get; set; } = "fast";

    [GlobalSetup]
    public void Setup()
    {
        _lines = BenchmarkPrograms.SurfacingLines(Lines);
        Func<IPmacPortEndpoint> ports;
        (ports, _prepare, _engine) = BenchmarkEngines.Create(Engine);
        _server = new PmacTcpServer(ports, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        _server.Start();
        _connection = new EthernetConnection(new EthernetOptions { Port = _server.Port, Timeout = TimeSpan.FromSeconds(10) });
    }

    [IterationSetup]
    public void Reset()
    {
        foreach (var command in _prepare)
        {
            _connection!.GetResponseAsync(command).GetAwaiter().GetResult();
        }
    }

    [GlobalCleanup]
    public void Cleanup()
    {
        _connection?.DisposeAsync().AsTask().GetAwaiter().GetResult();
        _server?.DisposeAsync().AsTask().GetAwaiter().GetResult();
        _engine?.Dispose();
    }

    /// <summary>WRITEBUFFER: as many NUL-terminated lines as fit in 1024 bytes per packet.</summary>
    [Benchmark(Baseline = true, OperationsPerInvoke = Lines)]
    public Task WriteBufferBatches() => _connection!.DownloadAsync(_lines);

    /// <summary>The naive way: one GETRESPONSE round trip per line.</summary>
    [Benchmark(OperationsPerInvoke = LineAtATimeLines)]
    public async Task LineAtATime()
    {
        for (var i = 0; i < LineAtATimeLines; i++)
        {
            await _connection!.GetResponseAsync(_lines[i]).ConfigureAwait(false);
        }
    }
}

/// <summary>Programs for transport benchmarks.</summary>
internal static class BenchmarkPrograms
{
    /// <summary>Raster surfacing lines as the splitter emits them: a tracking assignment and a 3-axis move (~35 bytes).</summary>
    public static string[] SurfacingLines(int count)
    {
        var lines = new string[count];
        for (var i = 0; i < count; i++)
        {
            var row = i / 200;
            var col = i % 200;
            var x = (row % 2 == 0 ? col : 199 - col) * 0.5;
            lines[i] = string.Create(CultureInfo.InvariantCulture, $"M0=={i + 1} X{x:0.###} Y{row * 0.25:0.###} Z{-0.001 * (i % 7):0.###}");
        }

        return lines;
    }
}

/// <summary>Engines behind the benchmark server.</summary>
internal static class BenchmarkEngines
{
    public static (Func<IPmacPortEndpoint> Ports, string[] Prepare, IDisposable? Engine) Create(string engine)
    {
        switch (engine)
        {
            case "fast":
                return (() => new FastEndpoint(), [], null);
            case "sim":
                {
                    var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Instant });
                    sim.StartClock();
                    return (() => sim.OpenPort("bench"), ["CLOSE", "OPEN PROG 1 CLEAR"], sim);
                }

            default:
                throw new ArgumentException($"unknown engine '{engine}'", nameof(engine));
        }
    }

    /// <summary>Answers every line with ACK after a token parse: measures the transport, not a controller.</summary>
    private sealed class FastEndpoint : IPmacPortEndpoint
    {
        private static readonly byte[] Ack = [ReplyParser.Ack];
        private long _lines;

        public byte[] Execute(string commandLine)
        {
            _lines += commandLine.Length > 0 ? 1 : 0;
            return Ack;
        }

        public void Flush()
        {
        }

        public byte[] Control(char control) => [];
    }
}

/// <summary>One in-process job: 1 warm-up and 3 measured runs of the whole download (minutes, not hours).</summary>
internal sealed class DownloadBenchmarkConfig : ManualConfig
{
    public DownloadBenchmarkConfig()
    {
        Add(DefaultConfig.Instance);
        AddJob(Job.Default
            .WithStrategy(RunStrategy.Monitoring)
            .WithLaunchCount(1)
            .WithWarmupCount(1)
            .WithIterationCount(3)
            .WithToolchain(new InProcessEmitToolchain(TimeSpan.FromMinutes(20), logOutput: true)));
    }
}
