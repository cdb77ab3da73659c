using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream plc`.</summary>
internal static class PlcCommand
{
    public static Command Create() => Pending.Create("plc", "Generate a PMAC PLC program from ladder rungs.", "issue 9");
}
