using System.CommandLine;
using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.Machine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream alarms [--json] [--history]` and `pmacstream alarms clear`.</summary>
internal static class AlarmsCommand
{
    public static Command Create()
    {
        var json = new Option<bool>("--json") { Description = "JSON: {\"alarms\": [{code, motor, axis, text}]}, with --history {\"history\": [{code, motor, axis, text, raised, jobId, cleared}]} from the store's alarm history." };
        var history = new Option<bool>("--history") { Description = "Every alarm seen (raised and cleared), newest first, not only the active ones." };
        var cmd = new Command("alarms", "Show the controller's active alarms (limits, fatal following error, amplifier fault, killed motors), or their history.");
        cmd.Options.Add(json);
        cmd.Options.Add(history);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction((parse, ct) => new AlarmsHandler().RunAsync(new AlarmsOptions(parse.GetValue(json), parse.GetValue(history), options.Bind(parse)), CliConsole.Of(parse), ct));

        var clear = new Command("clear", "Clear the alarms a clear can end (re-enable killed motors: fatal following error, amplifier fault); a hardware limit stays until the axis is jogged off it.");
        var clearOptions = ConsoleOptions.AddTo(clear);
        clear.SetAction((parse, ct) => new AlarmsClearHandler().RunAsync(clearOptions.Bind(parse), CliConsole.Of(parse), ct));
        cmd.Subcommands.Add(clear);
        return cmd;
    }

    /// <summary>Writes a list of alarms as <c>[{code, motor, axis, text}]</c>.</summary>
    internal static void WriteAlarms(Utf8JsonWriter w, string name, IReadOnlyList<MachineAlarm> alarms)
    {
        w.WriteStartArray(name);
        foreach (var a in alarms)
        {
            w.WriteStartObject();
            w.WriteString("code", a.Code);
            w.WriteNumber("motor", a.Motor);
            w.WriteString("axis", a.Axis);
            w.WriteString("text", a.Text);
            w.WriteString("severity", a.Severity.ToString().ToLowerInvariant());
            w.WriteEndObject();
        }

        w.WriteEndArray();
    }

    internal static string AlarmsJson(IReadOnlyList<MachineAlarm> alarms) => Write(w =>
    {
        w.WriteStartObject();
        WriteAlarms(w, "alarms", alarms);
        w.WriteEndObject();
    });

    internal static string HistoryJson(IReadOnlyList<AlarmRecord> records) => Write(w =>
    {
        w.WriteStartObject();
        w.WriteStartArray("history");
        foreach (var r in records)
        {
            w.WriteStartObject();
            w.WriteString("code", r.Code);
            w.WriteNumber("motor", r.Motor);
            w.WriteString("axis", r.Axis);
            w.WriteString("text", r.Text);
            w.WriteString("raised", r.Raised.ToString("O", CultureInfo.InvariantCulture));
            if (r.JobId is { } job)
            {
                w.WriteNumber("jobId", job);
            }
            else
            {
                w.WriteNull("jobId");
            }

            if (r.Cleared is { } c)
            {
                w.WriteString("cleared", c.ToString("O", CultureInfo.InvariantCulture));
            }
            else
            {
                w.WriteNull("cleared");
            }

            w.WriteEndObject();
        }

        w.WriteEndArray();
        w.WriteEndObject();
    });

    internal static string AlarmsText(IReadOnlyList<MachineAlarm> alarms) =>
        alarms.Count == 0 ? "no active alarm\n" : string.Concat(alarms.Select(a => $"{a.Code} ({a.Axis}, motor {a.Motor}): {a.Text}\n"));

    internal static string HistoryText(IReadOnlyList<AlarmRecord> records)
    {
        var t = new StringBuilder(records.Count == 0 ? "no alarms recorded\n" : string.Empty);
        foreach (var r in records)
        {
            t.Append(CultureInfo.InvariantCulture, $"{r.Raised.ToLocalTime():yyyy-MM-dd HH:mm:ss}  {(r.Cleared is { } c ? c.ToString("HH:mm:ss", CultureInfo.InvariantCulture) : "active"),-8}  {r.Code} ({r.Axis}, motor {r.Motor}): {r.Text}\n");
        }

        return t.ToString();
    }

    private static string Write(Action<Utf8JsonWriter> write)
    {
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Encoder = System.Text.Encodings.Web.JavaScriptEncoder.UnsafeRelaxedJsonEscaping }))
        {
            write(w);
        }

        return Encoding.UTF8.GetString(buffer.ToArray());
    }
}

/// <summary>What an <c>alarms</c> command line asks for.</summary>
/// <param name="Json">Print JSON.</param>
/// <param name="History">Every alarm seen (the store's history), not only the active ones.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record AlarmsOptions(bool Json, bool History, ConsoleArgs Console);

/// <summary><c>pmacstream alarms</c>: the controller's active alarms, or the store's alarm history, as text or JSON.</summary>
internal sealed class AlarmsHandler
{
    /// <summary>Prints the alarms; returns the exit code.</summary>
    public async Task<int> RunAsync(AlarmsOptions o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        var state = await session.Console.ReadStateAsync(ct).ConfigureAwait(false); // also brings the history up to date
        if (o.History)
        {
            var records = session.Console.Options.History?.List() ?? [];
            console.Out.Write(o.Json ? AlarmsCommand.HistoryJson(records) + "\n" : AlarmsCommand.HistoryText(records));
            return CliGlobals.Ok;
        }

        console.Out.Write(o.Json ? AlarmsCommand.AlarmsJson(state.Alarms) + "\n" : AlarmsCommand.AlarmsText(state.Alarms));
        return CliGlobals.Ok;
    }
}

/// <summary><c>pmacstream alarms clear</c>: clears the alarms a clear can end through the operator's console.</summary>
internal sealed class AlarmsClearHandler
{
    /// <summary>Clears; exit 0 when done, 1 when the console refused.</summary>
    public async Task<int> RunAsync(ConsoleArgs o, CliConsole console, CancellationToken ct)
    {
        await using var session = await o.OpenAsync(ct).ConfigureAwait(false);
        return ConsoleOptions.Finish(await session.Console.ClearAlarmsAsync(ct).ConfigureAwait(false), console);
    }
}
