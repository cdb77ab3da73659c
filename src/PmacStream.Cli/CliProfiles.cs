using System.CommandLine;
using PmacStream.GCode;

namespace PmacStream.Cli;

/// <summary>The <c>--profile NAME|FILE</c> option the commands share, and its resolution to a machine profile.</summary>
internal static class CliProfiles
{
    /// <summary>A fresh <c>--profile</c> option (one per command: an option belongs to one command).</summary>
    public static Option<string?> Option() => new("--profile")
    {
        Description = $"Machine profile: a built-in name ({string.Join(", ", MachineProfile.BuiltInNames)}) or a profile JSON file (default: {MachineProfile.DefaultName}; see 'pmacstream profiles').",
        HelpName = "NAME|FILE",
    };

    /// <summary>The profile named or read from a file; the default when <paramref name="nameOrPath"/> is null. Bad input is a usage error (exit 2).</summary>
    public static MachineProfile Load(string? nameOrPath)
    {
        try
        {
            return MachineProfile.Resolve(nameOrPath);
        }
        catch (InvalidDataException e)
        {
            throw new CliException(e.Message, CliGlobals.UsageOrIo);
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException)
        {
            throw new CliException($"{nameOrPath}: {e.Message}", CliGlobals.UsageOrIo);
        }
    }
}
