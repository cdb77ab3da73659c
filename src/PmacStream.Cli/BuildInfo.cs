using System.CommandLine;
using System.CommandLine.Invocation;
using System.Reflection;

namespace PmacStream.Cli;

/// <summary>
/// The version of this build and the source commit it was made from. The SDK writes the commit into the assembly's
/// informational version (<c>0.9.0+SHA</c>) when the source is a git checkout; a build from a plain source copy has
/// none and says so.
/// </summary>
internal static class BuildInfo
{
    private static readonly string Informational =
        typeof(BuildInfo).Assembly.GetCustomAttribute<AssemblyInformationalVersionAttribute>()?.InformationalVersion ?? "0.0.0";

    /// <summary>The product version, e.g. 0.9.0.</summary>
    public static string Version => Informational.Split('+')[0];

    /// <summary>The full git commit id, or null when the build had no git checkout.</summary>
    public static string? Commit => Informational.Split('+') is [_, var sha, ..] && sha.Length > 0 ? sha : null;

    /// <summary>What <c>pmacstream --version</c> prints.</summary>
    public static string Describe() =>
        $"pmacstream {Version} (commit {Commit ?? "unknown: built without git"}, .NET {Environment.Version}, {System.Runtime.InteropServices.RuntimeInformation.RuntimeIdentifier})";

    /// <summary>Makes the root command's <c>--version</c> print <see cref="Describe"/>.</summary>
    public static void Apply(RootCommand root)
    {
        foreach (var option in root.Options.OfType<VersionOption>())
        {
            option.Action = new PrintVersion();
        }
    }

    private sealed class PrintVersion : SynchronousCommandLineAction
    {
        public override int Invoke(ParseResult parseResult)
        {
            parseResult.InvocationConfiguration.Output.WriteLine(Describe());
            return CliGlobals.Ok;
        }
    }
}
