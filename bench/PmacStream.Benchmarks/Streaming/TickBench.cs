using System.Diagnostics;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Benchmarks.Streaming;

/// <summary>
/// What one timer tick of a running job costs (<c>stream-bench ticks LINES [BLOCK_MS] [strategies]</c>): LINES blocks of
/// BLOCK_MS ms each (default 20,000 of 100 ms, so M0 stands on a block for a tick or more, as on a real machine)
/// streamed into the in-process simulator on its virtual clock, the session ticking every 50 ms of machine time with a
/// status subscriber (as the HMI and the CLI have) and checkpoints going to a real SQLite job store. Reports per tick:
/// controller round trips by command, checkpoint writes, bytes allocated and host CPU (the simulator's own command
/// handling excluded from both), and host CPU per block.
/// </summary>
public static class TickBench
{
    public static int Run(int lines, int blockMs, StrategyKind[] kinds)
    {
        var dir = Path.Combine(Path.GetTempPath(), "pmacstream-bench", "ticks");
        if (Directory.Exists(dir))
        {
            Directory.Delete(dir, true);
        }

        Directory.CreateDirectory(dir);
        var src = Path.Combine(dir, "bench.nc");
        StreamBench.WriteProgram(src, lines, blockMs);
        var split = Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(dir, "chunks") });
        var times = MoveTimeTable.FromProgram(src);
        Console.WriteLine($"program: {lines} blocks of {blockMs} ms, {split.Manifest.Chunks.Count} chunks; ticks every 50 ms of machine time");
        Console.WriteLine("strategy  | ticks  | M0/tick | status/tick | PR/tick | feed/tick | other/tick | checkpoints/tick (durable) | bytes/tick | host us/tick | host us/block | executed");
        foreach (var kind in kinds)
        {
            var program = ChunkedProgram.Open(split.ManifestPath);
            using var sim = new PmacSimulator(new SimOptions { DefaultRotWords = 65536 });
            var port = new TimedPort(sim.OpenPort("bench"));
            var counting = new CountingConnection(new InProcessConnection(port, "sim"));
            foreach (var l in StreamBench.Library)
            {
                counting.GetResponseAsync(l).GetAwaiter().GetResult();
            }

            using var store = JobStore.Open(Path.Combine(dir, $"jobs-{kind}.db"));
            var job = store.CreateJob(src, "bench", split.ManifestPath, kind, "sim", null);
            var sink = new CountingSink(store.SinkFor(job));
            var options = new StreamingOptions { Strategy = kind, BufferWords = 16_000, DefineBuffer = true };
            var session = new StreamingSession(counting, program, options, sink, times, new SimTimeProvider(sim));
            var statuses = 0L;
            session.StatusChanged += (_, s) => statuses += s.ExecutedBlocks;
            session.StartAsync().GetAwaiter().GetResult();
            counting.Reset();
            sink.Reset();
            port.Inside = TimeSpan.Zero;
            port.InsideBytes = 0;
            var tick = options.TickPeriod.TotalSeconds;
            var next = sim.Now + tick;
            var ticks = 0L;
            var host = TimeSpan.Zero;
            var bytes = 0L;
            while (session.State is SessionState.Running or SessionState.Held)
            {
                var b0 = GC.GetAllocatedBytesForCurrentThread();
                var t0 = Stopwatch.GetTimestamp();
                session.TickAsync().GetAwaiter().GetResult();
                host += Stopwatch.GetElapsedTime(t0);
                bytes += GC.GetAllocatedBytesForCurrentThread() - b0;
                ticks++;
                if (sim.Now < next)
                {
                    sim.Advance(TimeSpan.FromSeconds(next - sim.Now));
                }

                next += tick;
            }

            host -= port.Inside;
            bytes -= port.InsideBytes;
            sim.RunUntilIdle(TimeSpan.FromHours(1)); // the session completes while the last move still runs
            var executed = 0;
            var last = 0;
            var inOrder = true;
            foreach (var m in sim.ExecutedMoves)
            {
                if (m.SourceLine > 0 && m.SourceLine != last)
                {
                    inOrder &= m.SourceLine > last;
                    executed++;
                    last = m.SourceLine;
                }
            }

            double Per(long n) => (double)n / ticks;
            var ok = session.State == SessionState.Completed ? string.Empty : $" ({session.State}: {session.Status.Message})";
            Console.WriteLine(
                $"{kind,-9} | {ticks,6} | {Per(counting.M0),7:0.000} | {Per(counting.Status),11:0.000} | {Per(counting.Pr),7:0.000} | {Per(counting.Feed),9:0.000} | {Per(counting.Other),10:0.000} | " +
                $"{Per(sink.Writes),10:0.000} ({Per(sink.Durable):0.0000}) | {Per(bytes),10:0} | {1e6 * host.TotalSeconds / ticks,12:0.0} | {1e6 * host.TotalSeconds / lines,13:0.0} | {executed}/{program.Manifest.TotalMotionBlocks}{(inOrder ? string.Empty : " OUT OF ORDER")}{ok}");
        }

        Directory.Delete(dir, true);
        return 0;
    }
}

/// <summary>Counts the commands a session sends, by kind.</summary>
internal sealed class CountingConnection(IPmacConnection inner) : IPmacConnection
{
    public long M0 { get; private set; }

    public long Status { get; private set; }

    public long Pr { get; private set; }

    public long Feed { get; private set; }

    public long Other { get; private set; }

    public string Description => inner.Description;

    public void Reset() => M0 = Status = Pr = Feed = Other = 0;

    public Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        switch (command)
        {
            case "M0": M0++; break;
            case "PR": Pr++; break;
            case "P500": Feed++; break;
            default:
                if (command.EndsWith("??", StringComparison.Ordinal))
                {
                    Status++;
                }
                else
                {
                    Other++;
                }

                break;
        }

        return inner.GetResponseAsync(command, cancellationToken);
    }

    public Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        Other++;
        return inner.DownloadAsync(lines, cancellationToken);
    }

    public Task FlushAsync(CancellationToken cancellationToken = default) => inner.FlushAsync(cancellationToken);

    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => inner.ControlAsync(control, cancellationToken);

    public ValueTask DisposeAsync() => inner.DisposeAsync();
}

/// <summary>Counts checkpoint writes on their way to the job store.</summary>
internal sealed class CountingSink(ICheckpointSink inner) : ICheckpointSink
{
    public long Writes { get; private set; }

    public long Durable { get; private set; }

    public void Reset() => Writes = Durable = 0;

    public void Save(Checkpoint checkpoint, bool durable)
    {
        Writes++;
        Durable += durable ? 1 : 0;
        inner.Save(checkpoint, durable);
    }

    public void RecordStart(JobStart start) => inner.RecordStart(start);
}
