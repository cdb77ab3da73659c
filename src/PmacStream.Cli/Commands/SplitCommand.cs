using System.CommandLine;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream split`: a program into rotary-buffer chunk files and their manifest.</summary>
internal static class SplitCommand
{
    public static Command Create()
    {
        var file = new Argument<string>("file") { Description = "The G-code program to split." };
        var outDir = new Option<string?>("--out") { Description = "Output folder (default: <name>_chunks beside the source). Replaced only if it holds a previous split." };
        var settings = new Option<string?>("--settings") { Description = "Run settings file (JSON) whose chunk shape the split takes (blocksPerChunk, chunkWords, ...), as stream does; default $PMACSTREAM_SETTINGS or ~/.pmacstream/settings.json when it exists. The options below override it." };
        var profile = CliProfiles.Option();
        var force = new Option<bool>("--force") { Description = "Split even if the check finds errors: they are listed, text that is not G-code is dropped, and every other word is written as it is (a code or letter the profile does not know included: the controller may refuse or misread it)." };

        var cmd = new Command("split", "Split a program into rotary-buffer chunk files with line tracking.");
        cmd.Arguments.Add(file);
        foreach (var o in new Option[] { outDir, settings, profile, force })
        {
            cmd.Options.Add(o);
        }

        var shape = ChunkShapeOptions.AddTo(cmd);

        cmd.SetAction((parse, ct) =>
        {
            var path = parse.GetValue(file)!;
            var machine = CliProfiles.Load(parse.GetValue(profile));
            // The same way as stream: the settings file's shape (or the defaults), then the options given here.
            var run = RunSettingsFile.Load(parse.GetValue(settings));
            var options = (run with { Shape = shape.Apply(parse, run.Shape) }).ToSplitOptions(machine, parse.GetValue(outDir), parse.GetValue(force));
            return new SplitHandler().RunAsync(new SplitCommandOptions(path, options, machine), CliConsole.Of(parse), ct);
        });
        return cmd;
    }
}

/// <summary>What a <c>split</c> command line asks for: the settings file's chunk shape and the options given over it.</summary>
/// <param name="File">The program.</param>
/// <param name="Options">The split's options.</param>
/// <param name="Machine">The machine profile it is checked and split under.</param>
internal sealed record SplitCommandOptions(string File, SplitOptions Options, MachineProfile Machine);

/// <summary><c>pmacstream split</c>: the program into rotary-buffer chunk files and their manifest, refused on errors unless forced.</summary>
internal sealed class SplitHandler
{
    private const int MaxListed = 50;

    /// <summary>Splits the program; returns the exit code.</summary>
    /// <exception cref="CliException">Bad options, or no such file.</exception>
    public Task<int> RunAsync(SplitCommandOptions o, CliConsole console, CancellationToken ct) => RunAsync(o.File, o.Options, o.Machine, console, ct);

    private static async Task<int> RunAsync(string path, SplitOptions options, MachineProfile machine, CliConsole console, CancellationToken ct)
    {
        try
        {
            options.Validate();
        }
        catch (ArgumentException e)
        {
            throw new CliException(e.Message, CliGlobals.UsageOrIo);
        }

        CliGlobals.RequireFile(path, "a G-code file");

        // Without --force the checker runs in the splitter's own pass (one read of the program): any error
        // refuses the split and the half-made chunk set is deleted. With --force the check still runs, in a pass
        // of its own, so that what is written despite it is listed, not hidden.
        options = options with { CheckProfile = machine, MaxReportedErrors = MaxListed };
        var forced = options.AllowErrors ? await Task.Run(() => ListForcedErrors(path, machine, console.Error, ct), ct).ConfigureAwait(false) : 0;

        SplitResult result;
        try
        {
            result = await CliProgress.RunAsync("split", console, report => Task.Run(() => Splitter.Split(path, options, Reporter(report), ct), ct)).ConfigureAwait(false);
        }
        catch (OperationCanceledException) when (ct.IsCancellationRequested)
        {
            await console.Error.WriteLineAsync($"pmacstream split: interrupted; the partial split was removed, {path} was not split").ConfigureAwait(false);
            return CliGlobals.Failed;
        }
        catch (SplitException e)
        {
            // Forcing goes past the check's findings only (not an empty program, or a block no chunk holds).
            Refusals.Print(console.Error, "pmacstream split", e.FromChecker ? "split" : string.Empty, path, e.Diagnostics, e.ErrorCount,
                e.FromChecker ? $"{path}: {e.ErrorCount} error(s) under profile '{machine.Name}'; not split" : e.Message);
            return CliGlobals.Failed;
        }

        PrintResult(result, machine, console.Out);
        if (forced > 0)
        {
            await console.Error.WriteLineAsync($"pmacstream split: --force: {forced} error(s) listed above; the words they name are in the chunks as written (only text that is not G-code was dropped)").ConfigureAwait(false);
        }

        return CliGlobals.Ok;
    }

    /// <summary>The splitter's progress as one report per 0.1 %: a gigabyte program has ~30,000 chunks, and each report builds a string.</summary>
    private static SyncProgress<SplitProgress> Reporter(Action<double, string> report)
    {
        var last = -1;
        return new SyncProgress<SplitProgress>(p =>
        {
            var permille = (int)(p.Fraction * 1000);
            if (permille != last)
            {
                last = permille;
                report(p.Fraction, $"{p.Chunks} chunks, {p.Blocks} blocks");
            }
        });
    }

    /// <summary>What the split wrote, its warnings, and the codes that keep a job from running it.</summary>
    private static void PrintResult(SplitResult result, MachineProfile machine, TextWriter o)
    {
        var m = result.Manifest;
        o.WriteLine($"{m.Chunks.Count} chunks, {m.TotalBlocks} blocks, largest chunk {result.LargestChunkBytes} bytes");
        o.WriteLine($"{m.TotalMotionBlocks} motion blocks; written to {result.OutputDirectory}");
        if (result.Warnings > 0)
        {
            o.WriteLine($"{result.Warnings} warning(s); see pmacstream check");
        }

        if (result.NotYetCodes is { Count: > 0 } notYet)
        {
            // The chunks keep these codes; the manifest lists them so that a job gate refuses to stream the split.
            o.WriteLine($"not runnable on the controller yet under profile '{machine.Name}' (a job using this split is refused): " +
                string.Join(", ", notYet.OrderBy(c => c.Value).Select(c => $"{c.Key} (line {c.Value})")));
        }
    }

    /// <summary>The check's errors of a forced split, listed (the first <see cref="MaxListed"/>) and counted.</summary>
    private static int ListForcedErrors(string path, MachineProfile machine, TextWriter error, CancellationToken ct)
    {
        var errors = 0;
        new Checker(machine).CheckFile(
            path,
            d =>
            {
                if (d.Severity == Severity.Error && ++errors <= MaxListed)
                {
                    error.WriteLine(d.Format(path));
                }
            },
            null,
            ct);
        if (errors > MaxListed)
        {
            error.WriteLine($"... and {errors - MaxListed} more");
        }

        return errors;
    }
}

/// <summary>Reports on the caller's thread (Progress&lt;T&gt; would post out of order to the pool).</summary>
internal sealed class SyncProgress<T>(Action<T> report) : IProgress<T>
{
    public void Report(T value) => report(value);
}
