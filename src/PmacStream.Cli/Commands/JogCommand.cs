using System.CommandLine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream jog AXIS +DIST|-DIST [--feed MM_PER_MIN]` (incremental) or `pmacstream jog AXIS +|- --for SECONDS` (continuous).</summary>
internal static class JogCommand
{
    public static Command Create()
    {
        var axis = new Argument<string>("axis") { Description = "The axis letter (X, Y, Z)." };
        var move = new Argument<string>("move") { Description = "+DIST or -DIST (mm, from the commanded position), or + or - with --for." };
        var feed = new Option<double?>("--feed") { Description = "Jog speed, mm/min (default 1000; set as the motor's jog speed Ixx22 for the move, then restored)." };
        var seconds = new Option<double?>("--for") { Description = "Continuous jog: run in the direction + or - for this many seconds, then stop." };
        var cmd = new Command("jog", "Jog an axis by a distance, or continuously for a time; returns when it is in position. Refused while a program runs or an alarm is active (jogging off a hardware limit, away from it, is always allowed).");
        cmd.Arguments.Add(axis);
        cmd.Arguments.Add(move);
        cmd.Options.Add(feed);
        cmd.Options.Add(seconds);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction((parse, ct) => new JogHandler().RunAsync(
            new JogOptions(parse.GetValue(axis)!, parse.GetValue(move)!, parse.GetValue(feed), parse.GetValue(seconds), options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>jog</c> command line asks for.</summary>
/// <param name="Axis">The axis letter.</param>
/// <param name="Move">+DIST or -DIST, or + or - with <paramref name="Seconds"/>.</param>
/// <param name="Feed">The jog speed, mm/min, if given.</param>
/// <param name="Seconds">A continuous jog's time, if given.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record JogOptions(string Axis, string Move, double? Feed, double? Seconds, ConsoleArgs Console);

/// <summary><c>pmacstream jog</c>: leases the machine and jogs an axis by a distance or for a time through the operator's console.</summary>
internal sealed class JogHandler
{
    /// <summary>Jogs; exit 0 when in position, 1 when the console refused, 2 for a move it cannot read.</summary>
    public async Task<int> RunAsync(JogOptions o, CliConsole console, CancellationToken ct)
    {
        var text = o.Move.Trim();
        var name = o.Axis;
        var continuous = o.Seconds;
        if (continuous is { } s)
        {
            if (text is not ("+" or "-"))
            {
                throw new CliException($"jog {name} {text} --for: give the direction alone, + or -");
            }

            await using var c = await o.Console.OpenAsync(ct, lease: true).ConfigureAwait(false);
            return ConsoleOptions.Finish(await c.Console.JogForAsync(name, text == "+" ? 1 : -1, TimeSpan.FromSeconds(s), o.Feed, ct).ConfigureAwait(false), console);
        }

        if (text.Length < 2 || text[0] is not ('+' or '-'))
        {
            throw new CliException($"jog {name} {text}: give +DIST or -DIST in mm (or + / - with --for SECONDS)");
        }

        var distance = ConsoleOptions.Number(text, "jog distance");
        await using var session = await o.Console.OpenAsync(ct, lease: true).ConfigureAwait(false);
        return ConsoleOptions.Finish(await session.Console.JogAsync(name, distance, o.Feed, ct).ConfigureAwait(false), console);
    }
}
