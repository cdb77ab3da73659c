using System.CommandLine;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream split`: a program into rotary-buffer chunk files and their manifest.</summary>
internal static class SplitCommand
{
    private const int MaxListed = 50;

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

        cmd.SetAction(async (parse, ct) =>
        {
            var path = parse.GetValue(file)!;
            var machine = CliProfiles.Load(parse.GetValue(profile));
            // The same way as stream: the settings file's shape (or the defaults), then the options given here.
            var run = RunSettingsFile.Load(parse.GetValue(settings));
            var options = (run with { Shape = shape.Apply(parse, run.Shape) }).ToSplitOptions(machine, parse.GetValue(outDir), parse.GetValue(force));
            CliGlobals.RequireFile(path, "a G-code file");

            // Without --force the checker runs in the splitter's own pass (one read of the program): any error
            // refuses the split and the half-made chunk set is deleted. With --force the check still runs, in a pass
            // of its own, so that what is written despite it is listed, not hidden.
            options = options with { CheckProfile = machine, MaxReportedErrors = MaxListed };
            var forced = options.AllowErrors ? await Task.Run(() => ListForcedErrors(path, machine, ct), ct).ConfigureAwait(false) : 0;

            SplitResult result;
            try
            {
                result = await CliProgress.RunAsync("split", report =>
                {
                    // One report per 0.1 %: a gigabyte program has ~30,000 chunks, and each report builds a string.
                    var last = -1;
                    return Task.Run(() => Splitter.Split(path, options, new SyncProgress<SplitProgress>(p =>
                    {
                        var permille = (int)(p.Fraction * 1000);
                        if (permille != last)
                        {
                            last = permille;
                            report(p.Fraction, $"{p.Chunks} chunks, {p.Blocks} blocks");
                        }
                    }), ct), ct);
                }).ConfigureAwait(false);
            }
            catch (OperationCanceledException) when (ct.IsCancellationRequested)
            {
                await Console.Error.WriteLineAsync($"pmacstream split: interrupted; the partial split was removed, {path} was not split").ConfigureAwait(false);
                return CliGlobals.Failed;
            }
            catch (SplitException e)
            {
                // Forcing goes past the check's findings only (not an empty program, or a block no chunk holds).
                Refusals.Print(Console.Error, "pmacstream split", e.FromChecker ? "split" : string.Empty, path, e.Diagnostics, e.ErrorCount,
                    e.FromChecker ? $"{path}: {e.ErrorCount} error(s) under profile '{machine.Name}'; not split" : e.Message);
                return CliGlobals.Failed;
            }

            var m = result.Manifest;
            Console.Out.WriteLine($"{m.Chunks.Count} chunks, {m.TotalBlocks} blocks, largest chunk {result.LargestChunkBytes} bytes");
            Console.Out.WriteLine($"{m.TotalMotionBlocks} motion blocks; written to {result.OutputDirectory}");
            if (result.Warnings > 0)
            {
                Console.Out.WriteLine($"{result.Warnings} warning(s); see pmacstream check");
            }

            if (result.NotYetCodes is { Count: > 0 } notYet)
            {
                // The chunks keep these codes; the manifest lists them so that a job gate refuses to stream the split.
                Console.Out.WriteLine($"not runnable on the controller yet under profile '{machine.Name}' (a job using this split is refused): " +
                    string.Join(", ", notYet.OrderBy(c => c.Value).Select(c => $"{c.Key} (line {c.Value})")));
            }

            if (forced > 0)
            {
                await Console.Error.WriteLineAsync($"pmacstream split: --force: {forced} error(s) listed above; the words they name are in the chunks as written (only text that is not G-code was dropped)").ConfigureAwait(false);
            }

            return CliGlobals.Ok;
        });
        return cmd;
    }

    /// <summary>The check's errors of a forced split, listed (the first <see cref="MaxListed"/>) and counted.</summary>
    private static int ListForcedErrors(string path, MachineProfile machine, CancellationToken ct)
    {
        var errors = 0;
        new Checker(machine).CheckFile(
            path,
            d =>
            {
                if (d.Severity == Severity.Error && ++errors <= MaxListed)
                {
                    Console.Error.WriteLine(d.Format(path));
                }
            },
            null,
            ct);
        if (errors > MaxListed)
        {
            Console.Error.WriteLine($"... and {errors - MaxListed} more");
        }

        return errors;
    }
}

/// <summary>Reports on the caller's thread (Progress&lt;T&gt; would post out of order to the pool).</summary>
internal sealed class SyncProgress<T>(Action<T> report) : IProgress<T>
{
    public void Report(T value) => report(value);
}
