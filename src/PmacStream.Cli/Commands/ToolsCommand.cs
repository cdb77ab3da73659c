using System.CommandLine;
using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.Machine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream tools [--json]`, `pmacstream tools set N --length L --radius R [--length-wear W] [--radius-wear W]`, `pmacstream tools set N --touch Z0`.</summary>
internal static class ToolsCommand
{
    public static Command Create()
    {
        var json = new Option<bool>("--json") { Description = "JSON: tools [{number, length, radius, lengthWear, radiusWear}]." };
        var cmd = new Command("tools", "Show the tool table on the controller (length, radius and their wear per tool; H n and D n read tool n).");
        cmd.Options.Add(json);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction(async (parse, ct) =>
        {
            await using var session = await options.OpenAsync(parse, ct).ConfigureAwait(false);
            var tables = await session.Console.ReadTablesAsync(ct).ConfigureAwait(false);
            Console.Out.Write(parse.GetValue(json) ? Json(tables.Tools) + "\n" : Text(tables.Tools));
            return CliGlobals.Ok;
        });
        cmd.Subcommands.Add(SetCommand());
        return cmd;
    }

    private static Command SetCommand()
    {
        var number = new Argument<int>("tool") { Description = "Tool (offset) number, 1-199: H n and D n read it." };
        var length = new Option<double?>("--length") { Description = "Tool length, mm (what G43 H n applies, with the length wear)." };
        var radius = new Option<double?>("--radius") { Description = "Cutter radius, mm (what G41/G42 D n use, with the radius wear)." };
        var lengthWear = new Option<double?>("--length-wear") { Description = "Length wear, mm (added to the length)." };
        var radiusWear = new Option<double?>("--radius-wear") { Description = "Radius wear, mm (added to the radius)." };
        var touch = new Option<string?>("--touch") { Description = "Measure the length from a Z touch: Z0 means the tool tip stands on a surface at work Z 0 (no tool length applied).", HelpName = "ZVALUE" };
        var cmd = new Command("set", "Set a tool's values (those given; the others stay) on the controller and in the host's copy.");
        cmd.Arguments.Add(number);
        foreach (var o in new Option[] { length, radius, lengthWear, radiusWear, touch })
        {
            cmd.Options.Add(o);
        }

        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction(async (parse, ct) =>
        {
            var n = parse.GetValue(number);
            if (parse.GetValue(touch) is { } t)
            {
                var (axis, value) = OffsetsCommand.Word(t);
                if (axis != "Z" || parse.GetValue(length) is not null)
                {
                    throw new CliException("--touch measures the length from Z: give Z and a value (Z0), without --length");
                }

                await using var s = await options.OpenAsync(parse, ct).ConfigureAwait(false);
                return ConsoleOptions.Finish(await s.Console.MeasureToolLengthAsync(n, value, ct).ConfigureAwait(false));
            }

            if (parse.GetValue(length) is null && parse.GetValue(radius) is null && parse.GetValue(lengthWear) is null && parse.GetValue(radiusWear) is null)
            {
                throw new CliException($"tools set {n}: give --length, --radius, --length-wear and/or --radius-wear (or --touch Z0)");
            }

            await using var session = await options.OpenAsync(parse, ct).ConfigureAwait(false);
            return ConsoleOptions.Finish(await session.Console.SetToolAsync(n, parse.GetValue(length), parse.GetValue(radius), parse.GetValue(lengthWear), parse.GetValue(radiusWear), ct).ConfigureAwait(false));
        });
        return cmd;
    }

    private static string Text(IReadOnlyList<ToolEntry> tools)
    {
        var t = new StringBuilder(tools.Count == 0 ? "no tool set (every H and D reads 0)\n" : "tool      length      radius   len. wear   rad. wear\n");
        foreach (var x in tools)
        {
            t.Append(CultureInfo.InvariantCulture, $"T{x.Number,-4}{x.Length,11:0.0000} {x.Radius,11:0.0000} {x.LengthWear,11:0.0000} {x.RadiusWear,11:0.0000}\n");
        }

        return t.ToString();
    }

    private static string Json(IReadOnlyList<ToolEntry> tools)
    {
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer))
        {
            w.WriteStartObject();
            w.WriteStartArray("tools");
            foreach (var x in tools)
            {
                w.WriteStartObject();
                w.WriteNumber("number", x.Number);
                w.WriteNumber("length", x.Length);
                w.WriteNumber("radius", x.Radius);
                w.WriteNumber("lengthWear", x.LengthWear);
                w.WriteNumber("radiusWear", x.RadiusWear);
                w.WriteEndObject();
            }

            w.WriteEndArray();
            w.WriteEndObject();
        }

        return Encoding.UTF8.GetString(buffer.ToArray());
    }
}
