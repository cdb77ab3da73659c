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
        cmd.SetAction(async (parse, ct) =>
        {
            await using var session = await options.OpenAsync(parse, ct).ConfigureAwait(false);
            var state = await session.Console.ReadStateAsync(ct).ConfigureAwait(false); // also brings the history up to date
            if (parse.GetValue(history))
            {
                var records = session.Console.Options.History?.List() ?? [];
                Console.Out.Write(parse.GetValue(json) ? HistoryJson(records) + "\n" : HistoryText(records));
                return CliGlobals.Ok;
            }

            Console.Out.Write(parse.GetValue(json) ? AlarmsJson(state.Alarms) + "\n" : AlarmsText(state.Alarms));
            return CliGlobals.Ok;
        });

        var clear = new Command("clear", "Clear the alarms a clear can end (re-enable killed motors: fatal following error, amplifier fault); a hardware limit stays until the axis is jogged off it.");
        var clearOptions = ConsoleOptions.AddTo(clear);
        clear.SetAction(async (parse, ct) =>
        {
            await using var session = await clearOptions.OpenAsync(parse, ct).ConfigureAwait(false);
            return ConsoleOptions.Finish(await session.Console.ClearAlarmsAsync(ct).ConfigureAwait(false));
        });
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

    private static string AlarmsJson(IReadOnlyList<MachineAlarm> alarms) => Write(w =>
    {
        w.WriteStartObject();
        WriteAlarms(w, "alarms", alarms);
        w.WriteEndObject();
    });

    private static string HistoryJson(IReadOnlyList<AlarmRecord> records) => Write(w =>
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

    private static string AlarmsText(IReadOnlyList<MachineAlarm> alarms) =>
        alarms.Count == 0 ? "no active alarm\n" : string.Concat(alarms.Select(a => $"{a.Code} ({a.Axis}, motor {a.Motor}): {a.Text}\n"));

    private static string HistoryText(IReadOnlyList<AlarmRecord> records)
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
