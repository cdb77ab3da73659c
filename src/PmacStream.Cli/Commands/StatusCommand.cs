using System.CommandLine;
using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.Machine;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream status [--watch] [--json] (--sim | --tcp HOST[:PORT] | --serial DEV[,BAUD])`: the machine's DRO, homed axes, feed and alarms.</summary>
internal static class StatusCommand
{
    public static Command Create()
    {
        var watch = new Option<bool>("--watch") { Description = "Sample again every --interval until Ctrl-C (without it: one sample and exit)." };
        var json = new Option<bool>("--json") { Description = "One JSON object per line per sample: state, homed, alarms, axes (machine, work, toGo in mm), the feeds and override, spindle {programmed, actual} (rpm)." };
        var interval = new Option<double>("--interval") { Description = "Seconds between samples with --watch.", DefaultValueFactory = _ => 0.5 };
        var cmd = new Command("status", "Show the machine: axes in machine and work coordinates and distance to go, homed axes, feed, alarms.");
        cmd.Options.Add(watch);
        cmd.Options.Add(json);
        cmd.Options.Add(interval);
        var options = ConsoleOptions.AddTo(cmd);
        cmd.SetAction((parse, ct) => new StatusHandler().RunAsync(
            new StatusOptions(parse.GetValue(watch), parse.GetValue(json), parse.GetValue(interval), options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }

    /// <summary>One sample as a JSON object on one line.</summary>
    internal static string Json(MachineState s)
    {
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Encoder = System.Text.Encodings.Web.JavaScriptEncoder.UnsafeRelaxedJsonEscaping }))
        {
            w.WriteStartObject();
            w.WriteString("state", s.ModeName);
            w.WriteStartObject("homed");
            foreach (var a in s.Axes)
            {
                w.WriteBoolean(a.Name, a.Homed);
            }

            w.WriteEndObject();
            AlarmsCommand.WriteAlarms(w, "alarms", s.Alarms);
            w.WriteStartArray("axes");
            foreach (var a in s.Axes)
            {
                w.WriteStartObject();
                w.WriteString("name", a.Name);
                w.WriteNumber("machine", a.Machine);
                w.WriteNumber("work", a.Work);
                w.WriteNumber("toGo", a.ToGo);
                w.WriteEndObject();
            }

            w.WriteEndArray();
            w.WriteString("workOffset", s.WorkOffset);
            w.WriteNumber("feedOverride", s.FeedOverride);
            if (s.ProgrammedFeed is { } f)
            {
                w.WriteNumber("programmedFeed", f);
            }

            w.WriteNumber("actualFeed", s.ActualFeed);
            if (s.Spindle is { } sp)
            {
                w.WriteStartObject("spindle");
                w.WriteNumber("programmed", sp.Programmed);
                w.WriteNumber("actual", sp.Actual);
                w.WriteBoolean("on", sp.On);
                w.WriteString("direction", sp.On ? (sp.Reverse ? "ccw" : "cw") : "off");
                w.WriteEndObject();
            }

            w.WriteNumber("line", s.ExecutingLine);
            if (s.Job is { } job)
            {
                w.WriteString("job", job);
            }

            w.WriteEndObject();
        }

        return Encoding.UTF8.GetString(buffer.ToArray());
    }

    /// <summary>One sample as a readable DRO table.</summary>
    internal static string Table(MachineState s)
    {
        var t = new StringBuilder();
        t.Append(CultureInfo.InvariantCulture, $"state {s.ModeName}   work offset {s.WorkOffset}   feed {s.ActualFeed:0.#} mm/min");
        t.Append(s.ProgrammedFeed is { } f ? string.Create(CultureInfo.InvariantCulture, $" (programmed {f:0.#})") : string.Empty);
        t.Append(CultureInfo.InvariantCulture, $"   override {s.FeedOverride:0.#}%");
        t.Append(s.Spindle is { } sp ? string.Create(CultureInfo.InvariantCulture, $"   spindle {sp.Actual:0.#} rpm (programmed {sp.Programmed:0.#}{(sp.On ? sp.Reverse ? ", ccw" : ", cw" : ", off")})") : string.Empty);
        t.Append(CultureInfo.InvariantCulture, $"   line {s.ExecutingLine}{(s.Job is { } j ? "   " + j : string.Empty)}\n");
        t.Append("axis  homed     machine        work       to go\n");
        foreach (var a in s.Axes)
        {
            t.Append(CultureInfo.InvariantCulture, $"{a.Name,-4}  {(a.Homed ? "yes" : "NO"),-5} {a.Machine,11:0.0000} {a.Work,11:0.0000} {a.ToGo,11:0.0000}\n");
        }

        t.Append(s.Alarms.Count == 0 ? "alarms: none\n" : "alarms:\n");
        foreach (var a in s.Alarms)
        {
            t.Append(CultureInfo.InvariantCulture, $"  {a.Code} ({a.Axis}, motor {a.Motor}): {a.Text}\n");
        }

        return t.ToString();
    }
}

/// <summary>What a <c>status</c> command line asks for.</summary>
/// <param name="Watch">Sample again every <paramref name="Interval"/> until Ctrl-C.</param>
/// <param name="Json">One JSON object per line per sample.</param>
/// <param name="Interval">Seconds between samples with <paramref name="Watch"/>.</param>
/// <param name="Console">The controller and console settings.</param>
internal sealed record StatusOptions(bool Watch, bool Json, double Interval, ConsoleArgs Console);

/// <summary><c>pmacstream status</c>: one sample of the machine (or one every interval until Ctrl-C), as a DRO table or JSON lines.</summary>
internal sealed class StatusHandler
{
    /// <summary>Prints the samples; returns the exit code.</summary>
    public async Task<int> RunAsync(StatusOptions o, CliConsole console, CancellationToken ct)
    {
        var every = o.Interval;
        if (every is < 0.05 or > 3600)
        {
            throw new CliException("--interval must be between 0.05 and 3600 seconds");
        }

        await using var session = await o.Console.OpenAsync(ct).ConfigureAwait(false);
        do
        {
            var state = await session.Console.ReadStateAsync(ct).ConfigureAwait(false);
            console.Out.Write(o.Json ? StatusCommand.Json(state) + "\n" : StatusCommand.Table(state));
            await console.Out.FlushAsync(ct).ConfigureAwait(false);
            if (!o.Watch)
            {
                break;
            }

            try
            {
                await Task.Delay(TimeSpan.FromSeconds(every), ct).ConfigureAwait(false);
            }
            catch (OperationCanceledException)
            {
                break;
            }
        }
        while (!ct.IsCancellationRequested);
        return CliGlobals.Ok;
    }
}
