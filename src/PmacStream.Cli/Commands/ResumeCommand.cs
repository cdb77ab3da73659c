using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream resume`.</summary>
internal static class ResumeCommand
{
    public static Command Create() => Pending.Create("resume", "Resume an interrupted job from its checkpoint.", "issue 7");
}
