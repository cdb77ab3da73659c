using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream demo`.</summary>
internal static class DemoCommand
{
    public static Command Create() => Pending.Create("demo", "Stream the sample program into the built-in simulator, with progress.", "issue 2");
}
