using System.CommandLine;
using PmacStream.Cli.Commands;

namespace PmacStream.Cli;

/// <summary>
/// The <c>pmacstream</c> command line: its commands, and the two ways to run it: as the process (logging set up,
/// Ctrl-C and SIGTERM handled) or in a test's process, writing to a given console.
/// </summary>
internal static class CliApp
{
    // Built once: a parse leaves the commands as they are, so in-process runs share one tree (and the options every
    // command shares are not added to a new root each time).
    private static readonly Lazy<RootCommand> Shared = new(Create);

    /// <summary>The root command with every subcommand.</summary>
    public static RootCommand Create()
    {
        var root = new RootCommand("PmacStream: run G-code programs of any size on a Delta Tau Turbo PMAC.");
        root.Options.Add(CliGlobals.Verbose);
        root.Options.Add(CliGlobals.LogFile);
        root.Subcommands.Add(DemoCommand.Create());
        root.Subcommands.Add(CheckCommand.Create());
        root.Subcommands.Add(SplitCommand.Create());
        root.Subcommands.Add(StreamCommand.Create());
        root.Subcommands.Add(ResumeCommand.Create());
        root.Subcommands.Add(SimCommand.Create());
        root.Subcommands.Add(Prog1000Command.Create());
        root.Subcommands.Add(MachineCommand.Create());
        root.Subcommands.Add(PlcCommand.Create());
        root.Subcommands.Add(PreviewCommand.Create());
        root.Subcommands.Add(StatusCommand.Create());
        root.Subcommands.Add(HomeCommand.Create());
        root.Subcommands.Add(JogCommand.Create());
        root.Subcommands.Add(MdiCommand.Create());
        root.Subcommands.Add(OffsetsCommand.Create());
        root.Subcommands.Add(ToolsCommand.Create());
        root.Subcommands.Add(AlarmsCommand.Create());
        BuildInfo.Apply(root);
        root.Subcommands.Add(ProfilesCommand.Create());
        root.Subcommands.Add(ProgramsCommand.Create());
        root.Subcommands.Add(JobsCommand.Create());
        root.Subcommands.Add(ShopCommand.Create());
        root.Subcommands.Add(StoreCommand.Create());
        return root;
    }

    /// <summary>The process: <c>pmacstream ARGS</c> with logging and signal handling; returns the exit code.</summary>
    public static Task<int> RunAsync(string[] args) => CliGlobals.RunAsync(Create(), args);

    /// <summary>
    /// <c>pmacstream ARGS</c> in the caller's process, through the same parser, handlers and exit-code convention,
    /// writing to <paramref name="console"/>. Logging is left as it is and no signal is hooked: <paramref name="ct"/>
    /// is the Ctrl-C.
    /// </summary>
    public static Task<int> InvokeAsync(string[] args, CliConsole console, CancellationToken ct) =>
        CliGlobals.InvokeAsync(Shared.Value.Parse(args), console, null, ct);
}
