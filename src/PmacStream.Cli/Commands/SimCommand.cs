using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream sim`.</summary>
internal static class SimCommand
{
    public static Command Create() => Pending.Create("sim", "Run the simulated Turbo PMAC as a server.", "issue 5");
}
