using System.CommandLine;
using System.Text;
using PmacStream.Preparation;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream prog1000 [--profile NAME|FILE] [--out FILE]`: the PROG 1000/1001 G and M code library.</summary>
internal static class Prog1000Command
{
    public static Command Create()
    {
        var profile = CliProfiles.Option();
        var outFile = new Option<string?>("--out") { Description = "Write the library to this file (default: standard output)." };
        var noComments = new Option<bool>("--no-comments") { Description = "Leave out the ; comment lines." };
        var cmd = new Command("prog1000", "Write the PROG 1000/1001 G and M code library.");
        cmd.Options.Add(profile);
        cmd.Options.Add(outFile);
        cmd.Options.Add(noComments);
        cmd.SetAction((parse, ct) => new Prog1000Handler().RunAsync(new Prog1000CommandOptions(parse.GetValue(profile), parse.GetValue(outFile), parse.GetValue(noComments)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>prog1000</c> command line asks for.</summary>
/// <param name="Profile">The machine profile named, if any.</param>
/// <param name="Out">Write to this file rather than standard output.</param>
/// <param name="NoComments">Leave out the comment lines.</param>
internal sealed record Prog1000CommandOptions(string? Profile, string? Out, bool NoComments);

/// <summary><c>pmacstream prog1000</c>: the profile's PROG 1000/1001 library, printed or written to a file.</summary>
internal sealed class Prog1000Handler
{
    /// <summary>Prints or writes the library; returns the exit code.</summary>
    public Task<int> RunAsync(Prog1000CommandOptions o, CliConsole console, CancellationToken ct)
    {
        var machine = CliProfiles.Load(o.Profile);
        string text;
        try
        {
            text = Prog1000Library.Generate(machine, new Prog1000Options { Comments = !o.NoComments });
        }
        catch (InvalidDataException e)
        {
            throw new CliException(e.Message, CliGlobals.Failed);
        }

        var path = o.Out;
        if (path == null)
        {
            console.Out.Write(text);
            return Task.FromResult(CliGlobals.Ok);
        }

        // Written beside the target and renamed, so a failed write leaves no half file.
        var full = Path.GetFullPath(path);
        var temp = full + ".tmp";
        File.WriteAllText(temp, text, Encoding.ASCII);
        File.Move(temp, full, overwrite: true);
        var routines = Prog1000Library.Routines(machine);
        console.Out.WriteLine($"{routines.Count(r => r.Converted)} routines written to {full}; {routines.Count(r => !r.Converted)} codes of profile '{machine.Name}' are not run on the controller yet (no routine)");
        return Task.FromResult(CliGlobals.Ok);
    }
}
