using System.CommandLine;
using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.Machine;

namespace PmacStream.Cli.Commands;

/// <summary>
/// `pmacstream offsets [--json]`, `pmacstream offsets set G55 X100 Y50 Z-10`, `pmacstream offsets set G54 --touch X0`,
/// `pmacstream offsets restore [--yes]`.
/// </summary>
internal static class OffsetsCommand
{
    public static Command Create()
    {
        var json = new Option<bool>("--json") { Description = "JSON: active, offsets [{name, x, y, z}], g52, g92, external, toolLength, h." };
        var all = new Option<bool>("--all") { Description = "List G54.1 P1-P48 too (by default only those set)." };
        var cmd = new Command("offsets", "Show the work offsets on the controller (G54-G59, G59.1-G59.3, G54.1 P1-P48) and the G52/G92 shifts.");
        cmd.Options.Add(json);
        cmd.Options.Add(all);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction((parse, ct) => new OffsetsHandler().RunAsync(new OffsetsOptions(parse.GetValue(json), parse.GetValue(all), options.Bind(parse)), CliConsole.Of(parse), ct));
        cmd.Subcommands.Add(SetCommand());
        cmd.Subcommands.Add(RestoreCommand());
        return cmd;
    }

    private static Command SetCommand()
    {
        var name = new Argument<string>("offset") { Description = "G54-G59, G59.1-G59.3 or G54.1P1-G54.1P48." };
        var values = new Argument<string[]>("values") { Description = "Axis values such as X100 Y50 Z-10 (axes not named stay as they are).", Arity = ArgumentArity.ZeroOrMore };
        var touch = new Option<string?>("--touch") { Description = "Touch-off: AXISVALUE such as X0 sets that axis of the offset so the current position reads VALUE.", HelpName = "AXISVALUE" };
        var cmd = new Command("set", "Set a work offset on the controller and in the host's copy.");
        cmd.Arguments.Add(name);
        cmd.Arguments.Add(values);
        cmd.Options.Add(touch);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction((parse, ct) => new OffsetsSetHandler().RunAsync(
            new OffsetsSetOptions(parse.GetValue(name)!, parse.GetValue(values)!, parse.GetValue(touch), options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }

    private static Command RestoreCommand()
    {
        var yes = new Option<bool>("--yes", "-y") { Description = "Write the host's copy to the controller (without it: only show the differences)." };
        var cmd = new Command("restore", "Show the differences between the controller's tables (offsets and tools) and the host's copy; with --yes write the host's copy (after a controller power cycle).");
        cmd.Options.Add(yes);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction((parse, ct) => new OffsetsRestoreHandler().RunAsync(new OffsetsRestoreOptions(parse.GetValue(yes), options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }

    /// <summary>An axis word such as <c>X100</c> or <c>Z-10.5</c>.</summary>
    internal static (string Axis, double Value) Word(string text)
    {
        var t = text.Trim().ToUpperInvariant();
        return t.Length >= 2 && char.IsLetter(t[0])
            ? (t[..1], ConsoleOptions.Number(t[1..], $"'{text}'"))
            : throw new CliException($"'{text}': expected an axis and a value such as X100");
    }

    internal static string Text(IReadOnlyList<WorkOffsetEntry> offsets, WorkShifts s)
    {
        var t = new StringBuilder($"active {s.Active}\noffset           X           Y           Z\n");
        foreach (var o in offsets)
        {
            t.Append(CultureInfo.InvariantCulture, $"{o.Name,-9}{(o.Name == s.Active ? '*' : ' ')} {o.X,11:0.0000} {o.Y,11:0.0000} {o.Z,11:0.0000}\n");
        }

        t.Append(CultureInfo.InvariantCulture, $"G52        {s.G52[0],11:0.0000} {s.G52[1],11:0.0000} {s.G52[2],11:0.0000}\n");
        t.Append(CultureInfo.InvariantCulture, $"G92        {s.G92[0],11:0.0000} {s.G92[1],11:0.0000} {s.G92[2],11:0.0000}\n");
        t.Append(CultureInfo.InvariantCulture, $"tool length applied {s.ToolLength:0.0000} (H{s.H})\n");
        return t.ToString();
    }

    internal static string Json(IReadOnlyList<WorkOffsetEntry> offsets, WorkShifts s)
    {
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer))
        {
            w.WriteStartObject();
            w.WriteString("active", s.Active);
            w.WriteStartArray("offsets");
            foreach (var o in offsets)
            {
                w.WriteStartObject();
                w.WriteString("name", o.Name);
                w.WriteNumber("x", o.X);
                w.WriteNumber("y", o.Y);
                w.WriteNumber("z", o.Z);
                w.WriteEndObject();
            }

            w.WriteEndArray();
            foreach (var (key, v) in new[] { ("g52", s.G52), ("g92", s.G92), ("external", s.External) })
            {
                w.WriteStartArray(key);
                foreach (var x in v)
                {
                    w.WriteNumberValue(x);
                }

                w.WriteEndArray();
            }

            w.WriteNumber("toolLength", s.ToolLength);
            w.WriteNumber("h", s.H);
            w.WriteEndObject();
        }

        return Encoding.UTF8.GetString(buffer.ToArray());
    }
}

/// <summary>What an <c>offsets</c> command line asks for.</summary>
/// <param name="Json">Print JSON.</param>
/// <param name="All">List G54.1 P1-P48 too, not only those set.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record OffsetsOptions(bool Json, bool All, ConsoleArgs Console);

/// <summary><c>pmacstream offsets</c>: the work offsets on the controller and the G52/G92 shifts, as text or JSON.</summary>
internal sealed class OffsetsHandler
{
    /// <summary>Prints the offsets; returns the exit code.</summary>
    public async Task<int> RunAsync(OffsetsOptions o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        var tables = await session.Console.ReadTablesAsync(ct).ConfigureAwait(false);
        var shifts = await session.Console.ReadShiftsAsync(ct).ConfigureAwait(false);
        var shown = tables.Offsets.Where(w => o.All || w.Index <= 9 || w is not { X: 0, Y: 0, Z: 0 }).ToList();
        console.Out.Write(o.Json ? OffsetsCommand.Json(shown, shifts) + "\n" : OffsetsCommand.Text(shown, shifts));
        return CliGlobals.Ok;
    }
}

/// <summary>What an <c>offsets set</c> command line asks for.</summary>
/// <param name="Offset">G54-G59, G59.1-G59.3, G54.1P1-G54.1P48 (or G54.1 with P n as the first value).</param>
/// <param name="Values">Axis values such as X100 Y50 Z-10.</param>
/// <param name="Touch">A touch-off AXISVALUE such as X0, or null.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record OffsetsSetOptions(string Offset, string[] Values, string? Touch, ConsoleArgs Console);

/// <summary><c>pmacstream offsets set</c>: sets a work offset (or touches one axis off) on the controller and in the host's copy.</summary>
internal sealed class OffsetsSetHandler
{
    /// <summary>Sets the offset; exit 0 when set, 1 when the console refused, 2 for values it cannot read.</summary>
    public async Task<int> RunAsync(OffsetsSetOptions o, CliConsole console, CancellationToken ct)
    {
        var words = o.Values.ToList();
        var table = o.Offset;
        if (words.Count > 0 && words[0].StartsWith('P') && table.Equals("G54.1", StringComparison.OrdinalIgnoreCase))
        {
            table += words[0]; // G54.1 P3
            words.RemoveAt(0);
        }

        var parsed = words.Select(OffsetsCommand.Word).ToList();
        if (o.Touch is { } t)
        {
            if (parsed.Count > 0)
            {
                throw new CliException("--touch sets one axis: give no other values with it");
            }

            var (axis, value) = OffsetsCommand.Word(t);
            await using var s = await o.Console.OpenAsync(ct).ConfigureAwait(false);
            return ConsoleOptions.Finish(await s.Console.TouchOffAsync(table, axis, value, ct).ConfigureAwait(false), console);
        }

        if (parsed.Count == 0 || parsed.Any(p => p.Axis is not ("X" or "Y" or "Z")) || parsed.Select(p => p.Axis).Distinct().Count() != parsed.Count)
        {
            throw new CliException($"offsets set {table}: give X, Y and/or Z values once each (X100 Y50 Z-10), or --touch X0");
        }

        double? Of(string a) => parsed.FirstOrDefault(p => p.Axis == a) is { Axis: not null } p ? p.Value : null;
        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        return ConsoleOptions.Finish(await session.Console.SetWorkOffsetAsync(table, Of("X"), Of("Y"), Of("Z"), ct).ConfigureAwait(false), console);
    }
}

/// <summary>What an <c>offsets restore</c> command line asks for.</summary>
/// <param name="Yes">Write the host's copy to the controller (without it: only show the differences).</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record OffsetsRestoreOptions(bool Yes, ConsoleArgs Console);

/// <summary><c>pmacstream offsets restore</c>: the differences between the controller's tables and the host's copy; with --yes, the copy written.</summary>
internal sealed class OffsetsRestoreHandler
{
    /// <summary>Compares (and restores); returns the exit code.</summary>
    public async Task<int> RunAsync(OffsetsRestoreOptions o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        var differences = await session.Console.CompareTablesAsync(ct).ConfigureAwait(false);
        foreach (var d in differences)
        {
            console.Out.WriteLine(d);
        }

        if (differences.Count == 0)
        {
            console.Out.WriteLine("the controller's tables match the host's copy");
            return CliGlobals.Ok;
        }

        return o.Yes ? ConsoleOptions.Finish(await session.Console.RestoreTablesAsync(ct).ConfigureAwait(false), console) : CliGlobals.Ok;
    }
}
