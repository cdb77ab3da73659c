using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream prog1000`.</summary>
internal static class Prog1000Command
{
    public static Command Create() => Pending.Create("prog1000", "Write the PROG 1000/1001 G and M code library.", "issue 4");
}
