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
        cmd.SetAction((parse, ct) => new HomeHandler().RunAsync(new HomeOptions(parse.GetValue(axes), options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>home</c> command line asks for.</summary>
/// <param name="Axes">The axes to home (letters), or null or all for every axis.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record HomeOptions(string? Axes, ConsoleArgs Console);

/// <summary><c>pmacstream home</c>: leases the machine and homes the axes through the operator's console.</summary>
internal sealed class HomeHandler
{
    /// <summary>Homes the axes; exit 0 when homed, 1 when the console refused.</summary>
    public async Task<int> RunAsync(HomeOptions o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.Console.OpenAsync(ct, lease: true).ConfigureAwait(false);
        return ConsoleOptions.Finish(await session.Console.HomeAsync(o.Axes, ct).ConfigureAwait(false), console);
    }
}
