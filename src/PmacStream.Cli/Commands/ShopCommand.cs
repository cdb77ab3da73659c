using System.CommandLine;
using System.Globalization;
using System.Text.Json;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>pmacstream shop [--json] [--store URI]</c>: every machine the store knows, the station that holds its lease
/// (pid, job, since, last heartbeat, expired or not), the job running there, its program and how far it got (the
/// line and blocks of the job's latest checkpoint). On SQLite it is one PC's shop.
/// </summary>
internal static class ShopCommand
{
    public static Command Create()
    {
        var cmd = new Command("shop", "The shop: each machine, the station leasing it, the job and program it runs and the current line.");
        var json = new Option<bool>("--json") { Description = "Print a JSON array: machine, station, pid, jobId, programId, program, line, blocksExecuted, blocksTotal, outcome, state, since, heartbeat, expired." };
        var store = StoreOptions.Option();
        var settings = new Option<string?>("--settings") { Description = "Settings file (its \"store\"); default $PMACSTREAM_SETTINGS or ~/.pmacstream/settings.json when it exists." };
        cmd.Options.Add(json);
        cmd.Options.Add(store);
        cmd.Options.Add(settings);
        cmd.SetAction((parse, ct) => new ShopHandler().RunAsync(
            new ShopOptions(StoreOptions.Resolve(parse.GetValue(store), null, parse.GetValue(settings)), parse.GetValue(json)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>shop</c> command line asks for.</summary>
/// <param name="Store">The store whose machines are listed.</param>
/// <param name="Json">Print JSON.</param>
internal sealed record ShopOptions(StoreLocation Store, bool Json);

/// <summary><c>pmacstream shop</c>: each machine, its lease, and the job and line running there.</summary>
internal sealed class ShopHandler
{
    /// <summary>Prints the shop as a table or JSON; returns the exit code.</summary>
    public Task<int> RunAsync(ShopOptions options, CliConsole console, CancellationToken ct) => Task.FromResult(List(options.Store, options.Json, console));

    private static int List(StoreLocation location, bool json, CliConsole console)
    {
        var machines = new JobService(new JobServiceOptions { Store = location }).Shop();
        if (json)
        {
            ProgramsCommand.WriteJson(console.Out, w =>
            {
                w.WriteStartArray();
                foreach (var m in machines)
                {
                    Write(w, m);
                }

                w.WriteEndArray();
            });
            return CliGlobals.Ok;
        }

        if (machines.Count == 0)
        {
            console.Out.WriteLine($"no machines in {location.Display} yet (a machine appears when a station leases it or runs a job on it)");
            return CliGlobals.Ok;
        }

        console.Out.WriteLine($"{"machine",-22} {"station",-14} {"pid",7} {"job",5} {"program",-24} {"line",8} {"blocks",-17} {"outcome",-11} {"lease",-26}");
        foreach (var m in machines)
        {
            var j = m.Job;
            var l = m.Lease;
            var program = j is null ? "-" : (j.History.ProgramId is { } pid ? $"#{pid} " : string.Empty) + Path.GetFileName(j.ProgramPath);
            var lease = l is null ? "free" : $"{(l.Expired ? "expired" : "held")}, beat {l.Heartbeat.ToLocalTime():HH:mm:ss}";
            console.Out.WriteLine(string.Create(CultureInfo.InvariantCulture,
                $"{Cut(m.Machine, 22),-22} {Cut(l?.Station ?? "-", 14),-14} {(l is null ? "-" : l.Pid.ToString(CultureInfo.InvariantCulture)),7} {(j is null ? "-" : j.Id.ToString(CultureInfo.InvariantCulture)),5} {Cut(program, 24),-24} {j?.Checkpoint?.LastExecutedLine ?? 0,8} {Blocks(j),-17} {j?.Outcome ?? "-",-11} {lease,-26}"));
        }

        return CliGlobals.Ok;
    }

    private static string Blocks(JobRecord? j) => j is null
        ? "-"
        : string.Create(CultureInfo.InvariantCulture, $"{j.History.BlocksExecuted ?? 0}/{j.History.BlocksTotal?.ToString(CultureInfo.InvariantCulture) ?? "?"}");

    private static void Write(Utf8JsonWriter w, ShopMachine m)
    {
        var j = m.Job;
        var l = m.Lease;
        w.WriteStartObject();
        w.WriteString("machine", m.Machine);
        w.WriteString("station", l?.Station);
        Number(w, "pid", l?.Pid);
        Number(w, "jobId", j?.Id);
        Number(w, "programId", j?.History.ProgramId);
        w.WriteString("program", j is null ? null : Path.GetFileName(j.ProgramPath));
        Number(w, "line", j?.Checkpoint?.LastExecutedLine);
        Number(w, "blocksExecuted", j is null ? null : j.History.BlocksExecuted ?? 0);
        Number(w, "blocksTotal", j?.History.BlocksTotal);
        w.WriteString("outcome", j?.Outcome);
        w.WriteString("state", l is null ? "free" : l.Expired ? "expired" : "leased");
        w.WriteString("since", l is null ? null : Iso(l.Since));
        w.WriteString("heartbeat", l is null ? null : Iso(l.Heartbeat));
        if (l is null)
        {
            w.WriteNull("expired");
        }
        else
        {
            w.WriteBoolean("expired", l.Expired);
        }

        w.WriteEndObject();
    }

    private static void Number(Utf8JsonWriter w, string name, long? value)
    {
        if (value is { } v)
        {
            w.WriteNumber(name, v);
        }
        else
        {
            w.WriteNull(name);
        }
    }

    private static string Iso(DateTimeOffset t) => t.UtcDateTime.ToString("yyyy-MM-dd'T'HH:mm:ss.fff'Z'", CultureInfo.InvariantCulture);

    private static string Cut(string s, int n) => s.Length <= n ? s : s[..(n - 1)] + "~";
}
