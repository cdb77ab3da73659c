using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream stream`.</summary>
internal static class StreamCommand
{
    public static Command Create() => Pending.Create("stream", "Stream a program to a controller or the simulator.", "issue 7");
}
