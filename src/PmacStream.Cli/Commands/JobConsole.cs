using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>What stream, resume and demo print: the start plan and its confirmation, progress, and the final count.</summary>
internal static class JobConsole
{
    /// <summary>With <c>--force</c>: says which codes of the program the controller will skip (a forced run does not hide them).</summary>
    public static void WarnForced(Preparation.ChunkManifest manifest, GCode.MachineProfile profile, bool forced, CliConsole console)
    {
        if (forced && manifest.NotYetCodes is { Count: > 0 } codes)
        {
            console.Error.WriteLine($"pmacstream: --force: the controller cannot run {ProgramGate.Describe(codes)} yet under profile '{profile.Name}': it skips each of them and runs the rest of its block");
        }
    }

    /// <summary>Shows a start plan's preamble and asks for confirmation (<c>--yes</c> answers); false when refused.</summary>
    public static bool Confirm(StartPlan plan, bool yes, CliConsole console)
    {
        var start = plan.Start;
        console.Out.WriteLine(string.Create(CultureInfo.InvariantCulture, $"start at line {plan.Line} from X{start.X:0.###} Y{start.Y:0.###} Z{start.Z:0.###}; preamble:"));
        foreach (var g in plan.GCode)
        {
            console.Out.WriteLine("  " + g);
        }

        if (yes)
        {
            return true;
        }

        if (console.InputRedirected)
        {
            console.Error.WriteLine("pmacstream: confirm the start with --yes (input is not a terminal)");
            return false;
        }

        console.Out.Write("Run this preamble and start there? [y/N] ");
        var answer = console.In.ReadLine();
        return answer is not null && answer.Trim().StartsWith('y');
    }

    /// <summary>
    /// Starts the job when <paramref name="start"/> (a resumed job already runs), follows it with progress until it
    /// ends, and reports: with the simulator, the count from its executed-move log (exit 1 when a block was skipped,
    /// repeated or reordered); else the count from M0. Ctrl-C stops sending and leaves the job resumable.
    /// <paramref name="countFrom"/> is the first line counted (a start from a line), null for the whole program.
    /// </summary>
    public static async Task<int> RunAsync(Job job, CliSimulator sim, bool start, int? countFrom, CliConsole console, CancellationToken ct, string title = "stream", bool showUnderruns = true,
        bool continueAtStops = true)
    {
        var program = job.Program;
        job.ContinueAtStops = continueAtStops;
        job.EventRaised += (_, e) =>
        {
            if (e.Kind == StreamingEventKind.ProgramStop)
            {
                console.Out.WriteLine(continueAtStops ? $"{e.Message}; continuing (--stops continue)" : $"{e.Message}: press Enter to continue (Ctrl-C leaves the job resumable)");
            }
        };

        if (!continueAtStops)
        {
            // Enter continues from a stop; the tick loop gives the run command. A line typed while the job runs is ignored.
            _ = Task.Run(() => ReadEnters(job, console.In), CancellationToken.None);
        }

        // Counted as the moves finish, against the program read lazily: nothing grows with the program.
        var check = job.Controller.IsSimulator && sim.Sim is { } counted
            ? new ExecutedLineCheck(program.TrackedLines().Where(l => countFrom is null || l >= countFrom), countFrom, program.ExpandedBlocks()).Attach(counted)
            : null;
        job.EventRaised += (_, e) =>
        {
            if (e.Kind is StreamingEventKind.ChunkDownloadedLate or StreamingEventKind.Fault or StreamingEventKind.Underrun)
            {
                console.Error.WriteLine($"  {e.Message}");
            }
        };

        if (start && await StartAsync(job, console, ct).ConfigureAwait(false) is { } failed)
        {
            return failed;
        }

        // An expanded program (subprograms, macros, o-words) tracks expanded lines: its map names their source lines and calls.
        var origins = CliExpansion.Map(program.Folder);
        var outcome = await CliProgress.RunAsync(title, console, report => job.RunAsync(s => report(s.Percent / 100.0, CliExpansion.Describe(Describe(s), s.CurrentLine, origins)), ct)).ConfigureAwait(false);
        var status = job.Status;
        if (outcome == JobOutcome.Interrupted)
        {
            console.Error.WriteLine($"interrupted at line {status.CurrentLine}{CliExpansion.Where(status.CurrentLine, origins)}: sending stopped; the controller keeps the lines it holds. {Resumable(job)}");
            return CliGlobals.Failed;
        }

        if (outcome != JobOutcome.Completed)
        {
            console.Error.WriteLine($"pmacstream: {status.Message}");
            if (job.Id is { } id)
            {
                console.Error.WriteLine($"the job is resumable: pmacstream resume --job {id}");
            }

            return CliGlobals.Failed;
        }

        if (!double.IsPositiveInfinity(job.Session.WorstLeadSeconds))
        {
            console.Out.WriteLine(string.Create(System.Globalization.CultureInfo.InvariantCulture, $"worst lead {job.Session.WorstLeadSeconds:0.000} s of motion ahead while sending ({job.Session.Strategy.Name})"));
        }

        if (check is not null && sim.Sim is { } simulator)
        {
            simulator.RunUntilIdle(TimeSpan.FromHours(24));
            return Report(check.Finish(), simulator.Counters.Underruns, program.Manifest.TotalMotionBlocks, countFrom, showUnderruns, console);
        }

        console.Out.WriteLine($"executed {status.ExecutedBlocks} of {program.Manifest.TotalMotionBlocks} blocks, {status.Underruns} underruns (from M0 and PR)");
        return status.ExecutedBlocks == program.Manifest.TotalMotionBlocks || countFrom is not null ? CliGlobals.Ok : CliGlobals.Failed;
    }

    /// <summary>Starts the job; null when it runs, else the exit code of a start that was interrupted or lost the link (said on stderr).</summary>
    private static async Task<int?> StartAsync(Job job, CliConsole console, CancellationToken ct)
    {
        try
        {
            await job.StartAsync(ct).ConfigureAwait(false);
            return null;
        }
        catch (InvalidOperationException e)
        {
            throw new CliException(e.Message, CliGlobals.Failed);
        }
        catch (OperationCanceledException) when (ct.IsCancellationRequested)
        {
            console.Error.WriteLine($"pmacstream: interrupted while starting the job; {Resumable(job)}");
            return CliGlobals.Failed;
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            console.Error.WriteLine($"pmacstream: {job.Status.Message}");
            console.Error.WriteLine(job.Id is { } id ? $"resume with: pmacstream resume --job {id}" : string.Empty);
            return CliGlobals.Failed;
        }
    }

    private static void ReadEnters(Job job, TextReader input)
    {
        try
        {
            while (input.ReadLine() is not null)
            {
                job.ContinueFromStop();
            }
        }
        catch (Exception e) when (e is IOException or ObjectDisposedException)
        {
            // Input went away: the job waits at its next stop until Ctrl-C.
        }
    }

    private static string Resumable(Job job) =>
        job.Id is { } id ? $"The job is resumable: pmacstream resume --job {id}" : "This run is not recorded as a job (nothing to resume).";

    private static string Describe(StreamingStatus s)
    {
        var eta = s.Eta is { } e ? $" ETA {e:hh\\:mm\\:ss}" : string.Empty;
        var feed = s.Feed is { } f ? $" override {f:0.#}%" : string.Empty;
        return $"chunk {s.CurrentChunk}/{s.TotalChunks} line {s.CurrentLine} ({s.ExecutedBlocks}/{s.TotalBlocks}){feed}{eta}";
    }

    /// <summary>
    /// Reports the blocks the simulator executed: distinct source lines in order (a block may make several moves;
    /// tracked 0 is the preamble). Exit 1 when a block was skipped, repeated or reordered.
    /// </summary>
    private static int Report(ExecutedLineResult result, long underruns, int total, int? fromLine, bool showUnderruns, CliConsole console)
    {
        var n = fromLine is null ? total : result.Expected;
        console.Out.WriteLine(showUnderruns ? $"executed {result.Executed} of {n} blocks, {underruns} underruns" : $"executed {result.Executed} of {n} blocks");
        if (result.FirstBreak is { } broken)
        {
            console.Error.WriteLine($"pmacstream: {broken}");
            return CliGlobals.Failed;
        }

        if (result.Executed != n || result.Expected != n)
        {
            console.Error.WriteLine($"pmacstream: {n - result.Executed} blocks missing (or extra) against the manifest");
            return CliGlobals.Failed;
        }

        return CliGlobals.Ok;
    }
}
