using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream home [AXES|all]`: home the axes named (XY, Z; none or all: every axis, Z first).</summary>
internal static class HomeCommand
{
    public static Command Create()
    {
        var axes = new Argument<string?>("axes") { Description = "Axes to home: letters such as XY or Z, or all (the default).", Arity = ArgumentArity.ZeroOrOne };
        var cmd = new Command("home", "Home axes (the motor's HM: homing speed and direction Ixx23, home offset Ixx26); returns when they are homed and in position.");
        cmd.Arguments.Add(axes);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction(async (parse, ct) =>
        {
            await using var session = await options.OpenAsync(parse, ct, lease: true).ConfigureAwait(false);
            return ConsoleOptions.Finish(await session.Console.HomeAsync(parse.GetValue(axes), ct).ConfigureAwait(false));
        });
        return cmd;
    }
}
