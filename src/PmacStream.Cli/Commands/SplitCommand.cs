using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream split`.</summary>
internal static class SplitCommand
{
    public static Command Create() => Pending.Create("split", "Split a program into rotary-buffer chunk files with line tracking.", "issue 4");
}
