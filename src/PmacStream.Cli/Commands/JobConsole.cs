using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>What stream, resume and demo print: the start plan and its confirmation, progress, and the final count.</summary>
internal static class JobConsole
{
    /// <summary>Shows a start plan's preamble and asks for confirmation (<c>--yes</c> answers); false when refused.</summary>
    public static bool Confirm(StartPlan plan, bool yes)
    {
        var start = plan.Start;
        Console.WriteLine(string.Create(CultureInfo.InvariantCulture, $"start at line {plan.Line} from X{start.X:0.###} Y{start.Y:0.###} Z{start.Z:0.###}; preamble:"));
        foreach (var g in plan.GCode)
        {
            Console.WriteLine("  " + g);
        }

        if (yes)
        {
            return true;
        }

        if (Console.IsInputRedirected)
        {
            Console.Error.WriteLine("pmacstream: confirm the start with --yes (input is not a terminal)");
            return false;
        }

        Console.Write("Run this preamble and start there? [y/N] ");
        var answer = Console.ReadLine();
        return answer is not null && answer.Trim().StartsWith('y');
    }

    /// <summary>
    /// Starts the job when <paramref name="start"/> (a resumed job already runs), follows it with progress until it
    /// ends, and reports: with the simulator, the count from its executed-move log (exit 1 when a block was skipped,
    /// repeated or reordered); else the count from M0. Ctrl-C stops sending and leaves the job resumable.
    /// <paramref name="countFrom"/> is the first line counted (a start from a line), null for the whole program.
    /// </summary>
    public static async Task<int> RunAsync(Job job, CliSimulator sim, bool start, int? countFrom, CancellationToken ct, string title = "stream", bool showUnderruns = true)
    {
        var program = job.Program;
        var expected = program.TrackedLines().Where(l => countFrom is null || l >= countFrom).ToList();
        job.EventRaised += (_, e) =>
        {
            if (e.Kind is StreamingEventKind.ChunkDownloadedLate or StreamingEventKind.Fault or StreamingEventKind.Underrun)
            {
                Console.Error.WriteLine($"  {e.Message}");
            }
        };

        if (start)
        {
            try
            {
                await job.StartAsync(ct).ConfigureAwait(false);
            }
            catch (InvalidOperationException e)
            {
                throw new CliException(e.Message, CliGlobals.Failed);
            }
            catch (Exception e) when (e is PmacLinkException or PmacErrorException)
            {
                Console.Error.WriteLine($"pmacstream: {job.Status.Message}");
                Console.Error.WriteLine(job.Id is { } id ? $"resume with: pmacstream resume --job {id}" : string.Empty);
                return CliGlobals.Failed;
            }
        }

        var outcome = await CliProgress.RunAsync(title, report => job.RunAsync(s => report(s.Percent / 100.0, Describe(s)), ct)).ConfigureAwait(false);
        var status = job.Status;
        if (outcome == JobOutcome.Interrupted)
        {
            Console.Error.WriteLine($"interrupted at line {status.CurrentLine}; the controller keeps the lines it holds. Resume with: pmacstream resume --job {job.Id}");
            return CliGlobals.Failed;
        }

        if (outcome != JobOutcome.Completed)
        {
            Console.Error.WriteLine($"pmacstream: {status.Message}");
            if (job.Id is { } id)
            {
                Console.Error.WriteLine($"the job is resumable: pmacstream resume --job {id}");
            }

            return CliGlobals.Failed;
        }

        if (job.Controller.IsSimulator && sim.Sim is { } simulator)
        {
            simulator.RunUntilIdle(TimeSpan.FromHours(24));
            return Report(simulator, expected, program.Manifest.TotalMotionBlocks, countFrom, showUnderruns);
        }

        Console.WriteLine($"executed {status.ExecutedBlocks} of {program.Manifest.TotalMotionBlocks} blocks, {status.Underruns} underruns (from M0 and PR)");
        return status.ExecutedBlocks == program.Manifest.TotalMotionBlocks || countFrom is not null ? CliGlobals.Ok : CliGlobals.Failed;
    }

    private static string Describe(StreamingStatus s)
    {
        var eta = s.Eta is { } e ? $" ETA {e:hh\\:mm\\:ss}" : string.Empty;
        var feed = s.Feed is { } f ? $" override {f:0.#}%" : string.Empty;
        return $"chunk {s.CurrentChunk}/{s.TotalChunks} line {s.CurrentLine} ({s.ExecutedBlocks}/{s.TotalBlocks}){feed}{eta}";
    }

    /// <summary>
    /// Counts executed blocks from the simulator's executed-move log: distinct source lines in order (a block may make
    /// several moves; tracked 0 is the preamble). Exit 1 when a block was skipped, repeated or reordered.
    /// </summary>
    private static int Report(PmacSimulator sim, IReadOnlyList<int> expected, int total, int? fromLine, bool showUnderruns)
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
