using System.CommandLine;
using System.Globalization;
using System.Text.Json;
using PmacStream.Jobs;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>pmacstream jobs [list|show N] [--json] [--store URI]</c>: the job history of the store: which program revision
/// ran on which machine from which station, when, how it ended and how far it got.
/// </summary>
internal static class JobsCommand
{
    public static Command Create()
    {
        var cmd = new Command("jobs", "The job history: every job with its program, machine, station, start, end and outcome.");
        var json = new Option<bool>("--json") { Description = "Print JSON.", Recursive = true };
        var store = StoreOptions.Option();
        store.Recursive = true;
        var jobDb = new Option<string?>("--job-db") { Description = "The store as an SQLite file (the same as --store sqlite:PATH).", Recursive = true };
        cmd.Options.Add(json);
        cmd.Options.Add(store);
        cmd.Options.Add(jobDb);
        Task<int> Run(ParseResult parse, long? id, CancellationToken ct) =>
            new JobsHandler().RunAsync(new JobsOptions(StoreOptions.Resolve(parse.GetValue(store), parse.GetValue(jobDb)), parse.GetValue(json), id), CliConsole.Of(parse), ct);
        cmd.SetAction((parse, ct) => Run(parse, null, ct));

        var list = new Command("list", "List the jobs, newest first.");
        list.SetAction((parse, ct) => Run(parse, null, ct));
        cmd.Subcommands.Add(list);

        var id = new Argument<long>("id") { Description = "Job id." };
        var show = new Command("show", "Show one job with its checkpoint and settings.");
        show.Arguments.Add(id);
        show.SetAction((parse, ct) => Run(parse, parse.GetValue(id), ct));
        cmd.Subcommands.Add(show);
        return cmd;
    }
}

/// <summary>What a <c>jobs</c> command line asks for.</summary>
/// <param name="Store">The store whose history is shown.</param>
/// <param name="Json">Print JSON.</param>
/// <param name="Show">The one job to show (<c>jobs show ID</c>), or null for the list.</param>
internal sealed record JobsOptions(Preparation.Store.StoreLocation Store, bool Json, long? Show);

/// <summary><c>pmacstream jobs</c>: the store's job history, as a table or JSON, or one job in detail.</summary>
internal sealed class JobsHandler
{
    /// <summary>Prints the list or the job asked for; returns the exit code.</summary>
    public Task<int> RunAsync(JobsOptions options, CliConsole console, CancellationToken ct)
    {
        var service = new JobService(new JobServiceOptions { Store = options.Store });
        return Task.FromResult(options.Show is { } id ? Show(service, id, options.Json, console.Out) : List(service, options.Json, console.Out));
    }

    private static int List(JobService service, bool json, TextWriter o)
    {
        var jobs = service.ListJobs();
        if (json)
        {
            ProgramsCommand.WriteJson(o, w =>
            {
                w.WriteStartArray();
                foreach (var j in jobs)
                {
                    WriteJob(w, j, detail: false);
                }

                w.WriteEndArray();
            });
            return CliGlobals.Ok;
        }

        o.WriteLine($"{"id",5} {"program",-24} {"machine",-20} {"station",-14} {"started",-20} {"outcome",-11} {"blocks",-17}");
        foreach (var j in jobs)
        {
            var h = j.History;
            var program = (h.ProgramId is { } pid ? $"#{pid} " : string.Empty) + Path.GetFileName(j.ProgramPath);
            o.WriteLine(string.Create(CultureInfo.InvariantCulture,
                $"{j.Id,5} {Cut(program, 24),-24} {Cut(h.Machine ?? j.Connection, 20),-20} {Cut(h.Station ?? "-", 14),-14} {j.Created.UtcDateTime:yyyy-MM-dd HH:mm:ss}Z {j.Outcome,-11} {h.BlocksExecuted ?? 0}/{h.BlocksTotal?.ToString(CultureInfo.InvariantCulture) ?? "?"}"));
        }

        return CliGlobals.Ok;
    }

    private static int Show(JobService service, long id, bool json, TextWriter o)
    {
        var j = service.ListJobs().FirstOrDefault(x => x.Id == id) ?? throw new CliException($"no job {id} in {service.Store.Display}");
        if (json)
        {
            ProgramsCommand.WriteJson(o, w => WriteJob(w, j, detail: true));
            return CliGlobals.Ok;
        }

        var h = j.History;
        o.WriteLine($"job {j.Id}: {j.Outcome}");
        o.WriteLine($"  program   {(h.ProgramId is { } pid ? $"revision {pid}, " : string.Empty)}{j.ProgramPath} (sha256 {j.ProgramSha256})");
        o.WriteLine($"  machine   {h.Machine ?? j.Connection} ({j.Connection})");
        o.WriteLine($"  station   {h.Station ?? "-"}, user {h.User ?? "-"}");
        o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  started   {j.Created.UtcDateTime:yyyy-MM-dd HH:mm:ss}Z{(j.FromLine is { } f ? $" from line {f}" : string.Empty)}"));
        if (j.ToLine is { } to)
        {
            o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  range     selected blocks: lines {j.FromLine ?? 1}..{to} (the job ends after line {to})"));
        }

        o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  ended     {(h.Ended is { } e ? e.UtcDateTime.ToString("yyyy-MM-dd HH:mm:ss'Z'", CultureInfo.InvariantCulture) : "-")}"));
        o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  blocks    {h.BlocksExecuted ?? 0} of {h.BlocksTotal?.ToString(CultureInfo.InvariantCulture) ?? "?"} executed; stops {h.Stops}, alarms {h.Alarms}, resumes {h.Resumes}"));
        o.WriteLine($"  strategy  {j.Strategy.ToString().ToLowerInvariant()}, profile {j.Profile ?? "-"}");
        if (j.Checkpoint is { } cp)
        {
            o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  checkpoint {cp.State} at line {cp.LastExecutedLine}, chunk {cp.CurrentChunk}, {cp.TimeUtc.UtcDateTime:yyyy-MM-dd HH:mm:ss}Z"));
        }

        if (j.SourceLocation is { } origin)
        {
            o.WriteLine($"  source    {origin}");
        }

        if (j.Message.Length > 0)
        {
            o.WriteLine($"  message   {j.Message}");
        }

        return CliGlobals.Ok;
    }

    private static void WriteJob(Utf8JsonWriter w, JobRecord j, bool detail)
    {
        var h = j.History;
        w.WriteStartObject();
        w.WriteNumber("id", j.Id);
        if (h.ProgramId is { } pid)
        {
            w.WriteNumber("programId", pid);
        }
        else
        {
            w.WriteNull("programId");
        }

        w.WriteString("program", j.ProgramPath);
        w.WriteString("sha256", j.ProgramSha256);
        w.WriteString("station", h.Station);
        w.WriteString("machine", h.Machine ?? j.Connection);
        w.WriteString("connection", j.Connection);
        w.WriteString("user", h.User);
        w.WriteString("started", Iso(j.Created));
        if (h.Ended is { } ended)
        {
            w.WriteString("ended", Iso(ended));
        }
        else
        {
            w.WriteNull("ended");
        }

        w.WriteString("outcome", j.Outcome);
        w.WriteNumber("blocksExecuted", h.BlocksExecuted ?? 0);
        if (h.BlocksTotal is { } total)
        {
            w.WriteNumber("blocksTotal", total);
        }
        else
        {
            w.WriteNull("blocksTotal");
        }

        w.WriteNumber("stops", h.Stops);
        w.WriteNumber("alarms", h.Alarms);
        w.WriteNumber("resumes", h.Resumes);
        w.WriteString("strategy", j.Strategy.ToString().ToLowerInvariant());
        w.WriteString("profile", j.Profile);
        if (j.FromLine is { } from)
        {
            w.WriteNumber("fromLine", from);
        }

        if (j.ToLine is { } toLine)
        {
            w.WriteNumber("toLine", toLine); // selected blocks: the job's last line
        }

        w.WriteNumber("lastLine", j.Checkpoint?.LastExecutedLine ?? 0);
        w.WriteString("sourceLocation", j.SourceLocation); // an expanded program's: where lastLine came from
        if (detail)
        {
            w.WriteString("message", j.Message);
            w.WriteString("checkpointState", j.Checkpoint?.State.ToString());
            w.WriteString("settings", j.Settings);
        }

        w.WriteEndObject();
    }

    private static string Iso(DateTimeOffset t) => t.UtcDateTime.ToString("yyyy-MM-dd'T'HH:mm:ss.fff'Z'", CultureInfo.InvariantCulture);

    private static string Cut(string s, int n) => s.Length <= n ? s : s[..(n - 1)] + "~";
}
