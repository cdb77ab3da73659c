using System.CommandLine;
using PmacStream.Cli;
using PmacStream.Cli.Commands;

// Exit codes: 0 ok, 1 the input has errors or the job failed, 2 usage or I/O error.
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

return await CliGlobals.RunAsync(root, args).ConfigureAwait(false);
