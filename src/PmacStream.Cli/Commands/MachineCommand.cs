using System.CommandLine;
using System.Text;
using PmacStream.Jobs;

namespace PmacStream.Cli.Commands;

/// <summary>
/// `pmacstream machine [--profile NAME|FILE] [--lines] [--out FILE]`: the machine's tables (work offsets, tool lengths,
/// reference positions, tool change position) of a profile and where the library keeps them on the controller; with
/// <c>--lines</c> the online assignments that download them (what <c>stream --load-library</c> sends after the library).
/// </summary>
internal static class MachineCommand
{
    public static Command Create()
    {
        var profile = CliProfiles.Option();
        var lines = new Option<bool>("--lines") { Description = "Write the tables as the PMAC online assignments that put them on the controller (one line each)." };
        var outFile = new Option<string?>("--out") { Description = "Write to this file (default: standard output)." };
        var cmd = new Command("machine", "Show the machine's work offsets, tool lengths, reference positions and tool change position, or write them for download.");
        cmd.Options.Add(profile);
        cmd.Options.Add(lines);
        cmd.Options.Add(outFile);
        cmd.SetAction((parse, ct) => new MachineHandler().RunAsync(new MachineOptions(parse.GetValue(profile), parse.GetValue(lines), parse.GetValue(outFile)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>machine</c> command line asks for.</summary>
/// <param name="Profile">The machine profile named, if any.</param>
/// <param name="Lines">Write the online assignments that download the tables.</param>
/// <param name="Out">Write to this file rather than standard output.</param>
internal sealed record MachineOptions(string? Profile, bool Lines, string? Out);

/// <summary><c>pmacstream machine</c>: a profile's machine tables, described or as the lines that download them.</summary>
internal sealed class MachineHandler
{
    /// <summary>Prints or writes the tables; returns the exit code.</summary>
    public Task<int> RunAsync(MachineOptions o, CliConsole console, CancellationToken ct)
    {
        var machine = CliProfiles.Load(o.Profile);
        var text = o.Lines
            ? string.Concat(ControllerLibrary.TableLines(machine).Select(l => l + "\n"))
            : ControllerLibrary.DescribeTables(machine);
        var path = o.Out;
        if (path == null)
        {
            console.Out.Write(text);
            return Task.FromResult(CliGlobals.Ok);
        }

        // Written beside the target and renamed, so a failed write leaves no half file.
        var full = Path.GetFullPath(path);
        File.WriteAllText(full + ".tmp", text, Encoding.ASCII);
        File.Move(full + ".tmp", full, overwrite: true);
        return Task.FromResult(CliGlobals.Ok);
    }
}
