using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>Shared shape for commands whose implementation has not landed yet: they say so and exit 2.</summary>
internal static class Pending
{
    public static Command Create(string name, string description, string issue)
    {
        var cmd = new Command(name, description);
        cmd.SetAction(parse =>
        {
            CliConsole.Of(parse).Error.WriteLine($"pmacstream {name}: not available in this build yet ({issue}).");
            return CliGlobals.UsageOrIo;
        });
        return cmd;
    }
}
