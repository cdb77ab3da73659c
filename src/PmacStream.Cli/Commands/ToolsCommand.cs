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
        cmd.SetAction((parse, ct) => new ToolsHandler().RunAsync(new ToolsOptions(parse.GetValue(json), options.Bind(parse)), CliConsole.Of(parse), ct));
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
        cmd.SetAction((parse, ct) => new ToolsSetHandler().RunAsync(
            new ToolsSetOptions(parse.GetValue(number), parse.GetValue(length), parse.GetValue(radius), parse.GetValue(lengthWear), parse.GetValue(radiusWear), parse.GetValue(touch), options.Bind(parse)),
            CliConsole.Of(parse),
            ct));
        return cmd;
    }

    internal static string Text(IReadOnlyList<ToolEntry> tools)
    {
        var t = new StringBuilder(tools.Count == 0 ? "no tool set (every H and D reads 0)\n" : "tool      length      radius   len. wear   rad. wear\n");
        foreach (var x in tools)
        {
            t.Append(CultureInfo.InvariantCulture, $"T{x.Number,-4}{x.Length,11:0.0000} {x.Radius,11:0.0000} {x.LengthWear,11:0.0000} {x.RadiusWear,11:0.0000}\n");
        }

        return t.ToString();
    }

    internal static string Json(IReadOnlyList<ToolEntry> tools)
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

/// <summary>What a <c>tools</c> command line asks for.</summary>
/// <param name="Json">Print JSON.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record ToolsOptions(bool Json, ConsoleArgs Console);

/// <summary><c>pmacstream tools</c>: the tool table on the controller, as text or JSON.</summary>
internal sealed class ToolsHandler
{
    /// <summary>Prints the tool table; returns the exit code.</summary>
    public async Task<int> RunAsync(ToolsOptions o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        var tables = await session.Console.ReadTablesAsync(ct).ConfigureAwait(false);
        console.Out.Write(o.Json ? ToolsCommand.Json(tables.Tools) + "\n" : ToolsCommand.Text(tables.Tools));
        return CliGlobals.Ok;
    }
}

/// <summary>What a <c>tools set</c> command line asks for (null: not given, the tool's value stays).</summary>
/// <param name="Tool">The tool (offset) number.</param>
/// <param name="Length">Tool length, mm.</param>
/// <param name="Radius">Cutter radius, mm.</param>
/// <param name="LengthWear">Length wear, mm.</param>
/// <param name="RadiusWear">Radius wear, mm.</param>
/// <param name="Touch">A Z touch (ZVALUE such as Z0) the length is measured from, or null.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record ToolsSetOptions(int Tool, double? Length, double? Radius, double? LengthWear, double? RadiusWear, string? Touch, ConsoleArgs Console);

/// <summary><c>pmacstream tools set</c>: sets a tool's values (or measures its length from a Z touch) on the controller and in the host's copy.</summary>
internal sealed class ToolsSetHandler
{
    /// <summary>Sets the tool; exit 0 when set, 1 when the console refused, 2 for values it cannot read.</summary>
    public async Task<int> RunAsync(ToolsSetOptions o, CliConsole console, CancellationToken ct)
    {
        var n = o.Tool;
        if (o.Touch is { } t)
        {
            var (axis, value) = OffsetsCommand.Word(t);
            if (axis != "Z" || o.Length is not null)
            {
                throw new CliException("--touch measures the length from Z: give Z and a value (Z0), without --length");
            }

            await using var s = await o.Console.OpenAsync(ct).ConfigureAwait(false);
            return ConsoleOptions.Finish(await s.Console.MeasureToolLengthAsync(n, value, ct).ConfigureAwait(false), console);
        }

        if (o.Length is null && o.Radius is null && o.LengthWear is null && o.RadiusWear is null)
        {
            throw new CliException($"tools set {n}: give --length, --radius, --length-wear and/or --radius-wear (or --touch Z0)");
        }

        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        return ConsoleOptions.Finish(await session.Console.SetToolAsync(n, o.Length, o.Radius, o.LengthWear, o.RadiusWear, ct).ConfigureAwait(false), console);
    }
}
