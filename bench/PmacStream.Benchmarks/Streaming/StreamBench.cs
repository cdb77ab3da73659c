using System.Diagnostics;
using System.Globalization;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Benchmarks.Streaming;

/// <summary>
/// Whole-run streaming benchmark (not BenchmarkDotNet: one long deterministic run per strategy).
/// <c>stream-bench cpu LINES [strategies]</c>: LINES blocks of 1 ms each (1000 blocks/s) through the splitter and
/// the simulator on a virtual clock, every controller round trip costing 2 ms of machine time (the simulated link);
/// reports underruns (simulator) and host CPU seconds spent in the session (the simulator's own work excluded).
/// <c>stream-bench memory MB</c>: streams a generated program of about MB megabytes into a null controller and
/// reports the peak working set.
/// </summary>
public static class StreamBench
{
    public static int Run(string[] args)
    {
        if (args.Length >= 2 && args[0] == "cpu")
        {
            var lines = int.Parse(args[1], CultureInfo.InvariantCulture);
            var kinds = args.Length > 2 ? args[2].Split(',').Select(StreamingStrategies.Parse).ToArray() : [StrategyKind.Chunk, StrategyKind.Pr, StrategyKind.Adaptive];
            return Cpu(lines, kinds);
        }

        if (args.Length >= 2 && args[0] == "memory")
        {
            return Memory(long.Parse(args[1], CultureInfo.InvariantCulture), splitOnly: args.Length > 2 && args[2] == "--split-only");
        }

        if (args.Length >= 2 && args[0] == "ticks")
        {
            var blockMs = args.Length > 2 ? int.Parse(args[2], CultureInfo.InvariantCulture) : 100;
            var kinds = args.Length > 3 ? args[3].Split(',').Select(StreamingStrategies.Parse).ToArray() : [StrategyKind.Chunk, StrategyKind.Adaptive];
            return TickBench.Run(int.Parse(args[1], CultureInfo.InvariantCulture), blockMs, kinds);
        }

        if (args.Length >= 2 && args[0] == "stream-only")
        {
            return StreamOnly(args[1]);
        }

        Console.Error.WriteLine("usage: stream-bench cpu LINES [chunk,pr,adaptive] | stream-bench ticks LINES [BLOCK_MS] [chunk,adaptive] | stream-bench memory MB");
        return 2;
    }

    private static string Folder(string tag)
    {
        var d = Path.Combine(Path.GetTempPath(), "pmacstream-bench", tag);
        if (Directory.Exists(d))
        {
            Directory.Delete(d, true);
        }

        Directory.CreateDirectory(d);
        return d;
    }

    /// <summary>Straight 0.1 mm segments at 6000 mm/min: exactly 1 ms a block (<paramref name="blockMs"/> ms at a feed that much slower).</summary>
    internal static void WriteProgram(string path, long lines, int blockMs = 1)
    {
        using var w = new StreamWriter(path, false, new UTF8Encoding(false), 1 << 16);
        w.Write($"%\nO3000\nG21 G17 G90\nG00 X0 Y0 Z0\nG01 F{(6000.0 / blockMs).ToString("0.###", CultureInfo.InvariantCulture)}\n");
        for (long i = 1; i <= lines; i++)
        {
            var x = (i % 1000) * 0.1;
            var y = (i / 1000) * 0.1;
            // Rows zig-zag so every segment is 0.1 long (the row step too).
            w.Write("G01 X");
            w.Write(((i / 1000) % 2 == 0 ? x : 100 - x).ToString("0.0", CultureInfo.InvariantCulture));
            w.Write(" Y");
            w.Write(y.ToString("0.0", CultureInfo.InvariantCulture));
            w.Write('\n');
        }

        w.Write("M30\n%\n");
    }

    private static int Cpu(int lines, StrategyKind[] kinds)
    {
        var dir = Folder("cpu");
        var src = Path.Combine(dir, "bench.nc");
        var sw = Stopwatch.StartNew();
        WriteProgram(src, lines);
        var split = Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(dir, "chunks") });
        Console.WriteLine($"program: {lines} blocks, split into {split.Manifest.Chunks.Count} chunks in {sw.Elapsed.TotalSeconds:0.0} s");
        sw.Restart();
        var times = MoveTimeTable.FromProgram(src);
        Console.WriteLine($"move times from the interpreter: {times?.Count} blocks, {times?.TotalSeconds:0.0} s of motion, built in {sw.Elapsed.TotalSeconds:0.0} s");
        Console.WriteLine("strategy  | underruns | host CPU s | % of a core | machine s | round trips | wall s");
        foreach (var kind in kinds)
        {
            var program = ChunkedProgram.Open(split.ManifestPath);
            using var sim = new PmacSimulator(new SimOptions { DefaultRotWords = 65536 });
            var port = new TimedPort(sim.OpenPort("bench"));
            var link = new DelayedConnection(new InProcessConnection(port, "sim+2ms"), sim, TimeSpan.FromMilliseconds(2));
            foreach (var l in Library)
            {
                link.GetResponseAsync(l).GetAwaiter().GetResult();
            }

            var options = new StreamingOptions { Strategy = kind, BufferWords = 16_000, DefineBuffer = true, PrTargetLines = 200 };
            var session = new StreamingSession(link, program, options, null, kind == StrategyKind.Adaptive ? times : null, new SimTimeProvider(sim));
            var wall = Stopwatch.StartNew();
            var busy = TimeSpan.Zero;
            port.Inside = TimeSpan.Zero;
            var inSession = TimeSpan.Zero;
            var t0 = Stopwatch.GetTimestamp();
            session.StartAsync().GetAwaiter().GetResult();
            inSession += Stopwatch.GetElapsedTime(t0);
            var tick = options.TickPeriod.TotalSeconds;
            var next = sim.Now + tick;
            while (session.State is SessionState.Running or SessionState.Held)
            {
                var t1 = Stopwatch.GetTimestamp();
                session.TickAsync().GetAwaiter().GetResult();
                inSession += Stopwatch.GetElapsedTime(t1);
                if (sim.Now < next)
                {
                    sim.Advance(TimeSpan.FromSeconds(next - sim.Now));
                }

                next += tick;
                if (wall.Elapsed > TimeSpan.FromMinutes(20))
                {
                    break;
                }
            }

            // Host time: everything the session did, minus the time spent inside the simulator's command handling.
            busy = inSession - port.Inside - link.SimAdvance;
            sim.RunUntilIdle(TimeSpan.FromHours(1));
            var machine = sim.Now;
            var counters = sim.Counters;
            var ok = session.State == SessionState.Completed ? string.Empty : $" ({session.State}: {session.Status.Message})";
            Console.WriteLine($"{kind,-9} | {counters.Underruns,9} | {busy.TotalSeconds,10:0.000} | {100 * busy.TotalSeconds / machine,10:0.00}% | {machine,9:0.0} | {link.RoundTrips,11} | {wall.Elapsed.TotalSeconds,6:0.0}{ok}");
            var executed = 0;
            var last = 0;
            foreach (var m in sim.ExecutedMoves)
            {
                if (m.SourceLine > 0 && m.SourceLine != last)
                {
                    executed++;
                    last = m.SourceLine;
                }
            }

            Console.WriteLine($"          executed {executed} of {program.Manifest.TotalMotionBlocks} blocks");
        }

        Directory.Delete(dir, true);
        return 0;
    }

    /// <summary>Streams an existing split in a fresh process, so the peak working set is the streamer's alone.</summary>
    private static int StreamOnly(string manifestPath)
    {
        var program = ChunkedProgram.Open(manifestPath);
        var controller = new NullController();
        var conn = new InProcessConnection(controller, "null");

        // As `pmacstream stream` does: the interpreter's move times for the ETA and the adaptive lead (a thinned table
        // for a program this size), so their memory is part of the peak.
        var source = program.Manifest.SourcePath;
        MoveTimeTable? times = null;
        if (File.Exists(source))
        {
            var build = Stopwatch.StartNew();
            times = MoveTimeTable.FromProgram(source);
            Console.WriteLine($"move times: {times.BlockCount} blocks in {times.SampleCount} samples, {times.TotalSeconds / 3600:0.0} h of motion, built in {build.Elapsed.TotalSeconds:0.0} s");
        }

        foreach (var kind in new[] { StrategyKind.Chunk, StrategyKind.Adaptive })
        {
            controller.Reset();
            var session = new StreamingSession(conn, program, new StreamingOptions { Strategy = kind, BufferWords = 16_000 }, null, times);
            var sw = Stopwatch.StartNew();
            session.StartAsync().GetAwaiter().GetResult();
            while (session.State == SessionState.Running)
            {
                session.TickAsync().GetAwaiter().GetResult();
            }

            Console.WriteLine($"{kind,-9}: {session.Status.State}, {controller.Lines} lines streamed in {sw.Elapsed.TotalSeconds:0.0} s; process peak working set {Process.GetCurrentProcess().PeakWorkingSet64 / 1e6:0} MB");
        }

        return 0;
    }

    private static int Memory(long megabytes, bool splitOnly = false)
    {
        var dir = Folder("mem");
        var src = Path.Combine(dir, "big.nc");
        var lines = megabytes * 1_000_000 / 32;
        var sw = Stopwatch.StartNew();
        Generators.SurfacingGenerator.Write(src, lines);
        var size = new FileInfo(src).Length;
        var split = Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(dir, "chunks") });
        Console.WriteLine($"program: {size / 1e6:0} MB, {split.Manifest.TotalBlocks} blocks, {split.Manifest.Chunks.Count} chunks (generate+split {sw.Elapsed.TotalSeconds:0} s)");
        if (splitOnly)
        {
            // The source stays too: the streaming process builds its move times from it, as the CLI does.
            Console.WriteLine($"split kept: {split.ManifestPath}");
            return 0;
        }

        File.Delete(src);

        GC.Collect();
        var before = Process.GetCurrentProcess().WorkingSet64;
        var program = ChunkedProgram.Open(split.ManifestPath);
        var controller = new NullController();
        var conn = new InProcessConnection(controller, "null");
        foreach (var kind in new[] { StrategyKind.Chunk, StrategyKind.Adaptive })
        {
            controller.Reset();
            var session = new StreamingSession(conn, program, new StreamingOptions { Strategy = kind, BufferWords = 16_000 });
            sw.Restart();
            session.StartAsync().GetAwaiter().GetResult();
            var peak = 0L;
            var n = 0;
            while (session.State == SessionState.Running)
            {
                session.TickAsync().GetAwaiter().GetResult();
                if (++n % 200 == 0)
                {
                    peak = Math.Max(peak, Process.GetCurrentProcess().WorkingSet64);
                }
            }

            peak = Math.Max(peak, Process.GetCurrentProcess().WorkingSet64);
            Console.WriteLine($"{kind,-9}: {session.Status.State}, {controller.Lines} lines streamed in {sw.Elapsed.TotalSeconds:0.0} s; working set before {before / 1e6:0} MB, peak while streaming {peak / 1e6:0} MB (process peak {Process.GetCurrentProcess().PeakWorkingSet64 / 1e6:0} MB)");
        }

        Directory.Delete(dir, true);
        return 0;
    }

    internal static readonly string[] Library =
    [
        "OPEN PROG 1000 CLEAR", "N0 RAPID RET", "N1000 LINEAR RET", "N2000 CIRCLE1 RET", "N3000 CIRCLE2 RET",
        "N17000 NORMAL K-1 RET", "N21000 RET", "N90000 ABS RET", "N91000 INC RET", "CLOSE",
        "OPEN PROG 1001 CLEAR", "N30000 DWELL0 RET", "CLOSE",
    ];
}

/// <summary>Measures wall time spent inside the simulator's command handling (subtracted from host CPU).</summary>
internal sealed class TimedPort(IPmacPortEndpoint inner) : IPmacPortEndpoint
{
    public TimeSpan Inside { get; set; }

    public long InsideBytes { get; set; }

    public byte[] Execute(string commandLine)
    {
        var b = GC.GetAllocatedBytesForCurrentThread();
        var t = Stopwatch.GetTimestamp();
        var r = inner.Execute(commandLine);
        Inside += Stopwatch.GetElapsedTime(t);
        InsideBytes += GC.GetAllocatedBytesForCurrentThread() - b;
        return r;
    }

    public void Flush() => inner.Flush();

    public byte[] Control(char control) => inner.Control(control);
}

/// <summary>
/// A link with a fixed round-trip delay in machine time: every command, and every 1024-byte WRITEBUFFER packet of a
/// download, lets the simulator run on by the delay (the controller keeps moving while the host waits).
/// </summary>
internal sealed class DelayedConnection(IPmacConnection inner, PmacSimulator sim, TimeSpan delay) : IPmacConnection
{
    public long RoundTrips { get; private set; }

    public TimeSpan SimAdvance { get; private set; }

    public string Description => inner.Description;

    public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        Wait(1);
        return await inner.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
    }

    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        var bytes = 0L;
        foreach (var l in lines)
        {
            bytes += l.Length + 1;
        }

        Wait((int)Math.Max(1, (bytes + 1023) / 1024));
        await inner.DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
    }

    public Task FlushAsync(CancellationToken cancellationToken = default) => inner.FlushAsync(cancellationToken);

    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => inner.ControlAsync(control, cancellationToken);

    public ValueTask DisposeAsync() => inner.DisposeAsync();

    private void Wait(int packets)
    {
        RoundTrips += packets;
        var t = Stopwatch.GetTimestamp();
        sim.Advance(delay * packets);
        SimAdvance += Stopwatch.GetElapsedTime(t);
    }
}

/// <summary>A controller that accepts everything and executes instantly: M0 follows the last marker received.</summary>
internal sealed class NullController : IPmacPortEndpoint
{
    private static readonly byte[] Ack = [0x06];
    private bool _open;
    private int _m0;

    public long Lines { get; private set; }

    public void Reset()
    {
        _m0 = 0;
        Lines = 0;
    }

    public byte[] Execute(string commandLine)
    {
        if (commandLine == "CLOSE")
        {
            _open = false;
            return Ack;
        }

        if (commandLine == "OPEN ROT")
        {
            _open = true;
            return Ack;
        }

        if (_open)
        {
            Lines++;
            var i = commandLine.IndexOf("M0==", StringComparison.Ordinal);
            if (i >= 0)
            {
                var j = i + 4;
                var v = 0;
                while (j < commandLine.Length && char.IsAsciiDigit(commandLine[j]))
                {
                    v = (v * 10) + (commandLine[j++] - '0');
                }

                _m0 = v;
            }

            return Ack;
        }

        return commandLine switch
        {
            "M0" => Encoding.ASCII.GetBytes($"{_m0}\r\u0006"),
            "PR" => Encoding.ASCII.GetBytes("0\r\u0006"),
            _ => Ack,
        };
    }

    public void Flush()
    {
    }

    public byte[] Control(char control) => [];
}
