using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream mdi "BLOCK" ["BLOCK" ...]`: run blocks at the machine through the same check, conversion and library as a program.</summary>
internal static class MdiCommand
{
    public static Command Create()
    {
        var blocks = new Argument<string[]>("blocks") { Description = "G-code blocks, one per argument (\"G0 X10 Y10\").", Arity = ArgumentArity.OneOrMore };
        var cmd = new Command("mdi", "Run G-code blocks at the machine (MDI): checked under the profile, converted and run as a program; the modal state carries on to the next mdi. Returns when they ran and the axes are in position.");
        cmd.Arguments.Add(blocks);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction(async (parse, ct) =>
        {
            await using var session = await options.OpenAsync(parse, ct, lease: true).ConfigureAwait(false);
            return ConsoleOptions.Finish(await session.Console.MdiAsync(parse.GetValue(blocks)!, ct).ConfigureAwait(false));
        });
        return cmd;
    }
}
