using System.CommandLine;
using System.Text;
using PmacStream.Plc;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream plc RUNGS-FILE [--plc N] [--out FILE]`: ladder rungs to a downloadable PMAC PLC program.</summary>
internal static class PlcCommand
{
    public static Command Create()
    {
        var file = new Argument<string>("RUNGS-FILE") { Description = "Ladder file: declarations and one rung per line (see docs/plc.md)." };
        var plc = new Option<int?>("--plc") { Description = "PLC program number 0..31 (overrides the file's 'plc N'; default 1)." };
        var output = new Option<string?>("--out", "-o") { Description = "Write the PLC program here instead of standard output." };
        var cmd = new Command("plc", "Generate a PMAC PLC program from ladder rungs (input image, boolean rungs, output image).");
        cmd.Arguments.Add(file);
        cmd.Options.Add(plc);
        cmd.Options.Add(output);
        cmd.SetAction((parse, ct) => new PlcHandler().RunAsync(new PlcOptions(parse.GetValue(file)!, parse.GetValue(plc), parse.GetValue(output)), CliConsole.Of(parse), ct));
        return cmd;
    }

    /// <summary>The command's work, with the streams injectable for tests. Returns the exit code.</summary>
    internal static async Task<int> RunAsync(string path, int? plcNumber, string? outPath, TextWriter stdout, TextWriter stderr, CancellationToken ct)
    {
        if (plcNumber is < 0 or > 31)
        {
            throw new CliException($"--plc {plcNumber}: a PLC program number is 0..31", CliGlobals.UsageOrIo);
        }

        if (!File.Exists(path))
        {
            throw new CliException($"{path}: no such file", CliGlobals.UsageOrIo);
        }

        string text;
        try
        {
            text = await File.ReadAllTextAsync(path, ct).ConfigureAwait(false);
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException)
        {
            throw new CliException($"{path}: {e.Message}", CliGlobals.UsageOrIo);
        }

        var program = LadderParser.TryParse(text, out var diagnostics);
        if (program is null)
        {
            foreach (var d in diagnostics)
            {
                await stderr.WriteLineAsync(d.Format(path)).ConfigureAwait(false);
            }

            await stderr.WriteLineAsync($"pmacstream plc: {diagnostics.Count} error(s); no program written.").ConfigureAwait(false);
            return CliGlobals.Failed;
        }

        GeneratedPlc generated;
        try
        {
            generated = PlcGenerator.Generate(program, new PlcGeneratorOptions { PlcNumber = plcNumber, SourceName = Path.GetFileName(path) });
        }
        catch (PlcGenerationException e)
        {
            await stderr.WriteLineAsync($"{path}: error: {e.Message}").ConfigureAwait(false);
            return CliGlobals.Failed;
        }

        if (outPath is null)
        {
            await stdout.WriteAsync(generated.Text).ConfigureAwait(false);
            return CliGlobals.Ok;
        }

        // Write next to the target and move into place, so a failed write never leaves half a program behind.
        var full = Path.GetFullPath(outPath);
        var temp = full + ".tmp-" + Environment.ProcessId;
        try
        {
            await File.WriteAllTextAsync(temp, generated.Text, new UTF8Encoding(false), ct).ConfigureAwait(false);
            File.Move(temp, full, overwrite: true);
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException)
        {
            throw new CliException($"{outPath}: cannot write: {e.Message}", CliGlobals.UsageOrIo);
        }
        finally
        {
            if (File.Exists(temp))
            {
                File.Delete(temp);
            }
        }

        await stderr.WriteLineAsync($"PLC {generated.PlcNumber}: {generated.Statements.Count} rungs, {generated.DownloadLines.Count} lines -> {outPath}").ConfigureAwait(false);
        return CliGlobals.Ok;
    }
}

/// <summary>What a <c>plc</c> command line asks for.</summary>
/// <param name="File">The ladder file.</param>
/// <param name="Plc">The PLC program number, if given (over the file's).</param>
/// <param name="Out">Write the program here rather than standard output.</param>
internal sealed record PlcOptions(string File, int? Plc, string? Out);

/// <summary><c>pmacstream plc</c>: ladder rungs to a downloadable PMAC PLC program.</summary>
internal sealed class PlcHandler
{
    /// <summary>Generates the PLC program; returns the exit code.</summary>
    public Task<int> RunAsync(PlcOptions o, CliConsole console, CancellationToken ct) => PlcCommand.RunAsync(o.File, o.Plc, o.Out, console.Out, console.Error, ct);
}
