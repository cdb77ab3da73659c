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
        cmd.SetAction((parse, ct) => new MdiHandler().RunAsync(new MdiOptions(parse.GetValue(blocks)!, options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What an <c>mdi</c> command line asks for.</summary>
/// <param name="Blocks">The G-code blocks, one per argument.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record MdiOptions(string[] Blocks, ConsoleArgs Console);

/// <summary><c>pmacstream mdi</c>: leases the machine and runs the blocks through the operator's console.</summary>
internal sealed class MdiHandler
{
    /// <summary>Runs the blocks; exit 0 when they ran and the axes are in position, 1 when the console refused.</summary>
    public async Task<int> RunAsync(MdiOptions o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.Console.OpenAsync(ct, lease: true).ConfigureAwait(false);
        return ConsoleOptions.Finish(await session.Console.MdiAsync(o.Blocks, ct).ConfigureAwait(false), console);
    }
}
