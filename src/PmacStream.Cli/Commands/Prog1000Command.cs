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
        cmd.SetAction((parse, _) =>
        {
            var machine = CliProfiles.Load(parse.GetValue(profile));
            string text;
            try
            {
                text = Prog1000Library.Generate(machine, new Prog1000Options { Comments = !parse.GetValue(noComments) });
            }
            catch (InvalidDataException e)
            {
                throw new CliException(e.Message, CliGlobals.Failed);
            }

            var path = parse.GetValue(outFile);
            if (path == null)
            {
                Console.Out.Write(text);
                return Task.FromResult(CliGlobals.Ok);
            }

            // Written beside the target and renamed, so a failed write leaves no half file.
            var full = Path.GetFullPath(path);
            var temp = full + ".tmp";
            File.WriteAllText(temp, text, Encoding.ASCII);
            File.Move(temp, full, overwrite: true);
            var routines = Prog1000Library.Routines(machine);
            Console.Out.WriteLine($"{routines.Count(r => r.Converted)} routines written to {full}; {routines.Count(r => !r.Converted)} codes of profile '{machine.Name}' are not run on the controller yet (no routine)");
            return Task.FromResult(CliGlobals.Ok);
        });
        return cmd;
    }
}
