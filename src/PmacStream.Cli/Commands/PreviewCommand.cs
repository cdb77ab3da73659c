using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream preview`.</summary>
internal static class PreviewCommand
{
    public static Command Create() => Pending.Create("preview", "Draw the toolpath of a program to a PNG.", "issue 10");
}
