using System.CommandLine;
using System.Globalization;
using System.Security.Cryptography;
using PmacStream.Pmac;
using PmacStream.Program;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream stream FILE (--sim | --tcp HOST[:PORT] | --serial DEV[,BAUD]) [--strategy ...] [--from-line N] [--yes] [--job-db PATH]`.</summary>
internal static class StreamCommand
{
    public static Command Create()
    {
        var file = new Argument<string>("file") { Description = "G-code program to run." };
        var strategy = new Option<string>("--strategy") { Description = "chunk (the paper's method), pr (poll PR, top up line by line) or adaptive (time-based lead).", DefaultValueFactory = _ => "chunk" };
        var fromLine = new Option<int?>("--from-line") { Description = "Start at the block of this source line, with a preamble restoring modal state and a safe approach." };
        var chunkLines = new Option<int>("--lines") { Description = "Source lines per chunk when splitting.", DefaultValueFactory = _ => 1000 };
        var cmd = new Command("stream", "Stream a program to a controller or the simulator.");
        cmd.Arguments.Add(file);
        cmd.Options.Add(strategy);
        cmd.Options.Add(fromLine);
        cmd.Options.Add(chunkLines);
        var common = StreamRunner.AddCommonOptions(cmd);
        cmd.SetAction(async (parse, ct) =>
        {
            var target = common.Target(parse) ?? throw new CliException("say where to stream: --sim, --tcp HOST[:PORT] or --serial DEV[,BAUD]");
            StrategyKind kind;
            try
            {
                kind = StreamingStrategies.Parse(parse.GetValue(strategy)!);
            }
            catch (ArgumentException e)
            {
                throw new CliException(e.Message);
            }

            return await StreamRunner.StreamAsync(
                parse.GetValue(file)!,
                target,
                kind,
                parse.GetValue(fromLine),
                parse.GetValue(chunkLines),
                common.Settings(parse),
                ct).ConfigureAwait(false);
        });
        return cmd;
    }
}

/// <summary>Options shared by stream, resume and demo.</summary>
internal sealed class CommonStreamOptions
{
    public required Option<bool> Sim { get; init; }

    public required Option<string?> Tcp { get; init; }

    public required Option<string?> Serial { get; init; }

    public required Option<bool> Yes { get; init; }

    public required Option<string?> JobDb { get; init; }

    public required Option<string> SimSpeed { get; init; }

    public required Option<int> BufferWords { get; init; }

    public required Option<int> TickMs { get; init; }

    public required Option<bool> SingleBlock { get; init; }

    public required Option<double> SafeZ { get; init; }

    public required Option<string> SafeZMode { get; init; }

    public required Option<double> Clearance { get; init; }

    /// <summary>The connection spec chosen (<c>sim</c>, <c>tcp://..</c>, <c>serial:..</c>), or null.</summary>
    public string? Target(ParseResult parse)
    {
        var chosen = new List<string>();
        if (parse.GetValue(Sim))
        {
            chosen.Add("sim");
        }

        if (parse.GetValue(Tcp) is { Length: > 0 } tcp)
        {
            chosen.Add(tcp.Contains("://", StringComparison.Ordinal) ? tcp : "tcp://" + tcp);
        }

        if (parse.GetValue(Serial) is { Length: > 0 } serial)
        {
            var comma = serial.IndexOf(',');
            chosen.Add(comma < 0 ? "serial:" + serial : $"serial:{serial[..comma]}@{serial[(comma + 1)..]}");
        }

        return chosen.Count switch
        {
            0 => null,
            1 => chosen[0],
            _ => throw new CliException("choose one of --sim, --tcp and --serial"),
        };
    }

    public RunSettings Settings(ParseResult parse)
    {
        SimSpeed speed;
        try
        {
            speed = PmacStream.Sim.SimSpeed.Parse(parse.GetValue(SimSpeed)!);
        }
        catch (FormatException e)
        {
            throw new CliException(e.Message);
        }

        var tick = parse.GetValue(TickMs);
        if (tick is < 5 or > 10_000)
        {
            throw new CliException("--tick-ms must be between 5 and 10000");
        }

        var mode = parse.GetValue(SafeZMode)?.Trim().ToLowerInvariant() switch
        {
            null or "" or "fixed" => Streaming.SafeZMode.Fixed, // demo has no start-from-line options
            "highest" => Streaming.SafeZMode.HighestSoFar,
            var other => throw new CliException($"--safe-z-mode: expected fixed or highest, got '{other}'"),
        };
        var plan = new StartPlanOptions { SafeZMode = mode, SafeZ = parse.GetValue(SafeZ), Clearance = parse.GetValue(Clearance) };
        return new RunSettings(parse.GetValue(Yes), parse.GetValue(JobDb), speed, parse.GetValue(BufferWords), TimeSpan.FromMilliseconds(tick), parse.GetValue(SingleBlock), plan);
    }
}

/// <summary>Settings of one run.</summary>
internal sealed record RunSettings(bool Yes, string? JobDb, SimSpeed SimSpeed, int BufferWords, TimeSpan Tick, bool SingleBlock, StartPlanOptions StartPlan);

/// <summary>The controller a job talks to: the in-process simulator or a real link.</summary>
internal sealed class StreamTarget : IAsyncDisposable
{
    private StreamTarget(string spec, IPmacConnection connection, PmacSimulator? sim, double simFactor)
    {
        Spec = spec;
        Connection = connection;
        Sim = sim;
        SimFactor = simFactor;
    }

    public string Spec { get; }

    public IPmacConnection Connection { get; }

    public PmacSimulator? Sim { get; }

    /// <summary>Virtual seconds per real second when the simulator is stepped by the tick loop.</summary>
    public double SimFactor { get; }

    public static async Task<StreamTarget> OpenAsync(string spec, SimSpeed speed, CancellationToken ct)
    {
        if (spec == "sim")
        {
            var sim = new PmacSimulator(new SimOptions { Speed = speed });
            var conn = new InProcessConnection(sim.OpenPort("stream"), "sim");
            // Line by line: a library routine the simulator cannot run (e.g. cutter compensation CC0/CC1) is left out
            // with a warning instead of stopping the job; the other routines are stored.
            foreach (var line in SimLibrary.Lines())
            {
                try
                {
                    await conn.GetResponseAsync(line, ct).ConfigureAwait(false);
                }
                catch (PmacErrorException e)
                {
                    Serilog.Log.Warning("simulator refused library line '{Line}' (ERR{Number:000}); that routine is left out", line, e.Number);
                }
            }

            // The tick loop steps the virtual clock itself (deterministic); "instant" means as fast as sensible.
            return new StreamTarget(spec, conn, sim, speed.IsInstant ? 1000 : speed.Multiplier);
        }

        IPmacConnection c;
        try
        {
            c = PmacConnections.Create(spec);
        }
        catch (FormatException e)
        {
            throw new CliException(e.Message);
        }

        try
        {
            await c.GetResponseAsync("VERSION", ct).ConfigureAwait(false);
        }
        catch (PmacLinkException e)
        {
            await c.DisposeAsync().ConfigureAwait(false);
            throw new CliException($"cannot reach the controller at {spec}: {e.Message}", CliGlobals.Failed);
        }

        return new StreamTarget(spec, c, null, 1);
    }

    public async ValueTask DisposeAsync()
    {
        await Connection.DisposeAsync().ConfigureAwait(false);
        Sim?.Dispose();
    }
}

/// <summary>The PROG 1000/1001 G and M code library the simulator needs (the splitter's generator, default profile).</summary>
internal static class SimLibrary
{
    public static IReadOnlyList<string> Lines() =>
        Prog1000Library.Generate(GCode.MachineProfile.Default, new Prog1000Options { Comments = false })
            .Split('\n', StringSplitOptions.RemoveEmptyEntries | StringSplitOptions.TrimEntries)
            .Where(l => l.Length > 0 && l[0] != ';')
            .ToList();
}

/// <summary>What stream, resume and demo share: preparing the split, the tick loop, progress and the final count.</summary>
internal static class StreamRunner
{
    public static CommonStreamOptions AddCommonOptions(Command cmd, bool forDemo = false)
    {
        var o = new CommonStreamOptions
        {
            Sim = new Option<bool>("--sim") { Description = "Stream into the built-in simulator." },
            Tcp = new Option<string?>("--tcp") { Description = "Stream to a controller over Ethernet: HOST[:PORT] (port 1025 by default)." },
            Serial = new Option<string?>("--serial") { Description = "Stream over RS-232: DEV[,BAUD] (38400 by default)." },
            Yes = new Option<bool>("--yes", "-y") { Description = "Confirm a start from a line / restart without asking." },
            JobDb = new Option<string?>("--job-db") { Description = "Job database (SQLite) for crash-safe resume; default $PMACSTREAM_JOB_DB or ~/.pmacstream/jobs.db." },
            SimSpeed = new Option<string>("--sim-speed") { Description = "Simulator clock: realtime, Nx (e.g. 20x) or instant.", DefaultValueFactory = _ => forDemo ? "60x" : "20x" },
            BufferWords = new Option<int>("--buffer-words") { Description = "Rotary buffer size in words (the simulator's is defined to this).", DefaultValueFactory = _ => 16_000 },
            TickMs = new Option<int>("--tick-ms") { Description = "Timer period (the paper's timer1 interval), milliseconds.", DefaultValueFactory = _ => 50 },
            SingleBlock = new Option<bool>("--single-block") { Description = "Single-block mode (HMI only: each block needs a start)." },
            SafeZ = new Option<double>("--safe-z") { Description = "Safe Z (work coordinates) for the approach when starting from a line (--safe-z-mode fixed, and the fallback of highest).", DefaultValueFactory = _ => 10.0 },
            SafeZMode = new Option<string>("--safe-z-mode") { Description = "Safe Z when starting from a line: fixed (--safe-z) or highest (the highest Z reached so far plus --clearance). The HMI plans the same way.", DefaultValueFactory = _ => "fixed" },
            Clearance = new Option<double>("--clearance") { Description = "Added to the highest Z so far with --safe-z-mode highest.", DefaultValueFactory = _ => 5.0 },
        };
        if (!forDemo)
        {
            cmd.Options.Add(o.Sim);
            cmd.Options.Add(o.Tcp);
            cmd.Options.Add(o.Serial);
            cmd.Options.Add(o.Yes);
            cmd.Options.Add(o.JobDb);
            cmd.Options.Add(o.SafeZ);
            cmd.Options.Add(o.SafeZMode);
            cmd.Options.Add(o.Clearance);
        }

        cmd.Options.Add(o.SimSpeed);
        cmd.Options.Add(o.BufferWords);
        cmd.Options.Add(o.TickMs);
        return o;
    }

    public static string Sha256Of(string path)
    {
        using var s = File.OpenRead(path);
        return Convert.ToHexStringLower(SHA256.HashData(s));
    }

    /// <summary>Splits the source into <paramref name="outDir"/>, reusing an earlier split of the same bytes.</summary>
    public static ChunkedProgram Prepare(string source, string outDir, int linesPerChunk)
    {
        var manifestPath = Path.Combine(outDir, ChunkManifest.FileName);
        if (File.Exists(manifestPath))
        {
            try
            {
                var m = ChunkManifest.Load(manifestPath);
                if (string.Equals(m.SourceSha256, Sha256Of(source), StringComparison.OrdinalIgnoreCase)
                    && m.Chunks.All(c => File.Exists(Path.Combine(outDir, c.FileName))))
                {
                    return ChunkedProgram.Open(manifestPath);
                }
            }
            catch (System.Text.Json.JsonException)
            {
                // A damaged manifest: split again.
            }
        }

        try
        {
            var result = Splitter.Split(source, new SplitOptions { LinesPerChunk = linesPerChunk, OutDir = outDir });
            return ChunkedProgram.Open(result.ManifestPath);
        }
        catch (SplitException e)
        {
            foreach (var d in e.Diagnostics.Take(20))
            {
                Console.Error.WriteLine(d.ToString());
            }

            throw new CliException(e.Message, CliGlobals.Failed);
        }
        catch (ArgumentException e)
        {
            throw new CliException(e.Message);
        }
    }

    public static async Task<int> StreamAsync(string file, string spec, StrategyKind strategy, int? fromLine, int linesPerChunk, RunSettings settings, CancellationToken ct)
    {
        if (!File.Exists(file))
        {
            throw new CliException($"{file}: no such file");
        }

        if (fromLine is < 1)
        {
            throw new CliException("--from-line must be 1 or more");
        }

        var program = Prepare(file, Splitter.DefaultOutDir(file), linesPerChunk);
        StartPlan? plan = null;
        if (fromLine is { } line)
        {
            plan = PlanStart(file, program, line, settings);
            if (plan is null)
            {
                return CliGlobals.UsageOrIo;
            }
        }

        using var jobs = JobStore.Open(settings.JobDb ?? JobStore.DefaultPath);
        var jobId = jobs.CreateJob(file, program.Manifest.SourceSha256, Path.Combine(program.Folder, ChunkManifest.FileName), strategy, spec, plan?.Line);
        await using var target = await StreamTarget.OpenAsync(spec, settings.SimSpeed, ct).ConfigureAwait(false);
        Console.WriteLine($"job {jobId}: {Path.GetFileName(file)}, {program.TotalChunks} chunks, {program.Manifest.TotalMotionBlocks} blocks, strategy {strategy.ToString().ToLowerInvariant()}, {target.Connection.Description}");
        var session = NewSession(target, program, strategy, settings, jobs.SinkFor(jobId), file);
        return await RunAsync(session, target, jobs, jobId, plan?.Line, async s => await s.StartAsync(plan?.Line, plan?.PmacLines, ct).ConfigureAwait(false), ct).ConfigureAwait(false);
    }

    public static StreamingSession NewSession(StreamTarget target, ChunkedProgram program, StrategyKind strategy, RunSettings settings, ICheckpointSink? sink, string? source)
    {
        var options = new StreamingOptions
        {
            Strategy = strategy,
            BufferWords = settings.BufferWords,
            DefineBuffer = target.Sim is not null,
            // The session reasons in machine time: with the simulator, one real tick is Tick x speed of virtual time.
            TickPeriod = settings.Tick * target.SimFactor,
            SingleBlock = settings.SingleBlock,
        };
        IMoveTimes? times = source is not null && File.Exists(source) ? StartFromLine.MoveTimes(source) : null;
        TimeProvider? time = target.Sim is { } sim ? new SimTimeProvider(sim) : null;
        // Chunk files go through the PComm-style facade, as the paper calls it: Download(0, file, true, true, true, true).
        var devices = new PmacDevices();
        devices.Add(options.PmacNumber, target.Connection);
        return new StreamingSession(devices, program, options, sink, times, time);
    }

    /// <summary>Plans a start from a line, shows the preamble and asks for confirmation; null when refused.</summary>
    public static StartPlan? PlanStart(string source, ChunkedProgram program, int line, RunSettings settings)
    {
        StartPlan plan;
        try
        {
            // The one planner the HMI uses too: same options, same preamble.
            plan = StartFromLine.Plan(source, line, StartPlanOptions.For(program.Manifest, settings.StartPlan));
        }
        catch (ArgumentOutOfRangeException e)
        {
            throw new CliException(e.Message.Split(Environment.NewLine)[0]);
        }

        if (program.PositionOfBlock(plan.Line) is null)
        {
            throw new CliException($"line {line}: no block to start at after it");
        }

        Console.WriteLine($"start at line {plan.Line} from X{plan.Start.X.ToString("0.###", CultureInfo.InvariantCulture)} Y{plan.Start.Y.ToString("0.###", CultureInfo.InvariantCulture)} Z{plan.Start.Z.ToString("0.###", CultureInfo.InvariantCulture)}; preamble:");
        foreach (var g in plan.GCode)
        {
            Console.WriteLine("  " + g);
        }

        if (settings.Yes)
        {
            return plan;
        }

        if (Console.IsInputRedirected)
        {
            Console.Error.WriteLine("pmacstream: confirm the start with --yes (input is not a terminal)");
            return null;
        }

        Console.Write("Run this preamble and start there? [y/N] ");
        var answer = Console.ReadLine();
        return answer is not null && answer.Trim().StartsWith('y') ? plan : null;
    }

    /// <summary>
    /// The timer loop (the paper's timer1_Tick): tick, show progress, advance the simulator's clock when it is ours;
    /// ends with the count of executed blocks. Ctrl-C stops sending and leaves the job resumable.
    /// </summary>
    public static async Task<int> RunAsync(StreamingSession session, StreamTarget target, JobStore? jobs, long jobId, int? fromLine, Func<StreamingSession, Task> start, CancellationToken ct, string title = "stream", bool showUnderruns = true)
    {
        var program = session.Program;
        var expected = program.TrackedLines().Where(l => fromLine is null || l >= fromLine).ToList();
        session.EventRaised += (_, e) =>
        {
            if (e.Kind is StreamingEventKind.ChunkDownloadedLate or StreamingEventKind.Fault or StreamingEventKind.Underrun)
            {
                Console.Error.WriteLine($"  {e.Message}");
            }
        };

        try
        {
            await start(session).ConfigureAwait(false);
        }
        catch (InvalidOperationException e)
        {
            throw new CliException(e.Message, CliGlobals.Failed);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            jobs?.SetMessage(jobId, session.Status.Message);
            Console.Error.WriteLine($"pmacstream: {session.Status.Message}");
            Console.Error.WriteLine(jobs is null ? string.Empty : $"resume with: pmacstream resume --job {jobId}");
            return CliGlobals.Failed;
        }

        var interrupted = false;
        await CliProgress.RunAsync(title, async report =>
        {
            var period = session.Options.TickPeriod / target.SimFactor;
            while (true)
            {
                await session.TickAsync(CancellationToken.None).ConfigureAwait(false);
                var s = session.Status;
                report(s.Percent / 100.0, Describe(s));
                if (s.State is SessionState.Completed or SessionState.Faulted or SessionState.Aborted)
                {
                    break;
                }

                if (ct.IsCancellationRequested)
                {
                    interrupted = true;
                    break;
                }

                try
                {
                    await Task.Delay(period, ct).ConfigureAwait(false);
                }
                catch (OperationCanceledException)
                {
                    interrupted = true;
                    break;
                }

                target.Sim?.Advance(session.Options.TickPeriod);
            }

            return 0;
        }).ConfigureAwait(false);

        var status = session.Status;
        jobs?.SetMessage(jobId, status.Message);
        if (interrupted)
        {
            Console.Error.WriteLine($"interrupted at line {status.CurrentLine}; the controller keeps the lines it holds. Resume with: pmacstream resume --job {jobId}");
            return CliGlobals.Failed;
        }

        if (status.State != SessionState.Completed)
        {
            Console.Error.WriteLine($"pmacstream: {status.Message}");
            if (jobs is not null)
            {
                Console.Error.WriteLine($"the job is resumable: pmacstream resume --job {jobId}");
            }

            return CliGlobals.Failed;
        }

        if (target.Sim is { } sim)
        {
            sim.RunUntilIdle(TimeSpan.FromHours(24));
            return Report(sim, expected, program.Manifest.TotalMotionBlocks, fromLine, showUnderruns);
        }

        Console.WriteLine($"executed {status.ExecutedBlocks} of {program.Manifest.TotalMotionBlocks} blocks, {status.Underruns} underruns (from M0 and PR)");
        return status.ExecutedBlocks == program.Manifest.TotalMotionBlocks || fromLine is not null ? CliGlobals.Ok : CliGlobals.Failed;
    }

    private static string Describe(StreamingStatus s)
    {
        var eta = s.Eta is { } e ? $" ETA {e:hh\\:mm\\:ss}" : string.Empty;
        var feed = s.Feed is { } f ? $" feed {f:0.#}" : string.Empty;
        return $"chunk {s.CurrentChunk}/{s.TotalChunks} line {s.CurrentLine} ({s.ExecutedBlocks}/{s.TotalBlocks}){feed}{eta}";
    }

    /// <summary>
    /// Counts executed blocks from the simulator's executed-move log: distinct source lines in order (a block may make
    /// several moves; tracked 0 is the preamble). Exit 1 when a block was skipped, repeated or reordered.
    /// </summary>
    public static int Report(PmacSimulator sim, IReadOnlyList<int> expected, int total, int? fromLine, bool showUnderruns = true)
    {
        var executed = new List<int>();
        foreach (var m in sim.ExecutedMoves)
        {
            if (m.SourceLine > 0 && (executed.Count == 0 || executed[^1] != m.SourceLine))
            {
                executed.Add(m.SourceLine);
            }
        }

        if (fromLine is not null)
        {
            executed.RemoveAll(l => l < fromLine);
        }

        var n = fromLine is null ? total : expected.Count;
        var underruns = sim.Counters.Underruns;
        Console.WriteLine(showUnderruns ? $"executed {executed.Count} of {n} blocks, {underruns} underruns" : $"executed {executed.Count} of {n} blocks");
        for (var i = 0; i < Math.Min(executed.Count, expected.Count); i++)
        {
            if (executed[i] != expected[i])
            {
                Console.Error.WriteLine($"pmacstream: block order broken at block {i + 1}: expected line {expected[i]}, executed line {executed[i]}");
                return CliGlobals.Failed;
            }
        }

        if (executed.Count != n || expected.Count != n)
        {
            Console.Error.WriteLine($"pmacstream: {n - executed.Count} blocks missing (or extra) against the manifest");
            return CliGlobals.Failed;
        }

        return CliGlobals.Ok;
    }
}
