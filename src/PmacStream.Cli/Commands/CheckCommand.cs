using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream check`.</summary>
internal static class CheckCommand
{
    public static Command Create() => Pending.Create("check", "Check a G-code program and list every error and warning.", "issue 3");
}
