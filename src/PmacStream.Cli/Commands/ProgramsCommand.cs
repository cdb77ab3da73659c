using System.CommandLine;
using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>pmacstream programs [list|show ID|export ID|rm ID|import FILE] [--json] [--store URI]</c>: the store's program
/// library. <c>import</c> checks and decodes a program into the store as a revision (SHA-256 and profile) in one pass
/// and prints only its id; errors go to stderr as <c>FILE:LINE:COL: error CODE: message</c> and exit 1 (the revision
/// is stored with them).
/// </summary>
internal static class ProgramsCommand
{
    /// <summary>Diagnostics <c>show</c> lists at most (the counts are exact).</summary>
    private const int ShownDiagnostics = 1000;

    public static Command Create()
    {
        var cmd = new Command("programs", "The program library of the store: import, list, show, export, rm.");
        var json = new Option<bool>("--json") { Description = "Print JSON.", Recursive = true };
        var store = StoreOptions.Option();
        store.Recursive = true;
        cmd.Options.Add(json);
        cmd.Options.Add(store);
        cmd.SetAction(parse => List(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(json)));

        var list = new Command("list", "List the program revisions, newest first.");
        list.SetAction(parse => List(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(json)));
        cmd.Subcommands.Add(list);

        var file = new Argument<string>("file") { Description = "G-code program to import." };
        var profile = CliProfiles.Option();
        var import = new Command("import", "Check and decode a program into the store; prints only its revision's id.");
        import.Arguments.Add(file);
        import.Options.Add(profile);
        import.SetAction((parse, ct) =>
        {
            var location = StoreOptions.Resolve(parse.GetValue(store));
            var path = parse.GetValue(file)!;
            var machine = CliProfiles.Load(parse.GetValue(profile));
            return Task.Run(() => Import(location, path, machine, ct), CancellationToken.None);
        });
        cmd.Subcommands.Add(import);

        var showId = new Argument<long>("id") { Description = "Program revision id." };
        var show = new Command("show", "Show a revision: its check summary and diagnostics.");
        show.Arguments.Add(showId);
        show.SetAction(parse => Show(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(showId), parse.GetValue(json)));
        cmd.Subcommands.Add(show);

        var exportId = new Argument<long>("id") { Description = "Program revision id." };
        var output = new Option<string?>("--out") { Description = "Write to this file instead of standard output." };
        var export = new Command("export", "Write a revision's exact source bytes.");
        export.Arguments.Add(exportId);
        export.Options.Add(output);
        export.SetAction(parse => Export(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(exportId), parse.GetValue(output)));
        cmd.Subcommands.Add(export);

        var rmId = new Argument<long>("id") { Description = "Program revision id." };
        var rm = new Command("rm", "Remove a revision with its blocks, diagnostics and source.");
        rm.Arguments.Add(rmId);
        rm.SetAction(parse => Remove(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(rmId)));
        cmd.Subcommands.Add(rm);
        cmd.Subcommands.Add(ProgramStartCommand.Create(store));
        return cmd;
    }

    /// <summary>Opens the store's program library; a store that cannot be reached is a usage or I/O error naming it (never its password).</summary>
    internal static IProgramRevisions OpenStore(StoreLocation location)
    {
        try
        {
            return ProgramStores.Open(location);
        }
        catch (Exception e) when (e is Microsoft.Data.Sqlite.SqliteException or Npgsql.NpgsqlException or IOException or UnauthorizedAccessException or InvalidOperationException)
        {
            throw new CliException($"store {location.Display}: {StoreLocation.Redact(e.Message)}");
        }
    }

    private static int Import(StoreLocation location, string path, MachineProfile machine, CancellationToken ct)
    {
        if (Directory.Exists(path))
        {
            throw new CliException($"{path}: is a directory, expected a G-code file");
        }

        if (!File.Exists(path))
        {
            throw new CliException($"{path}: no such file");
        }

        using var store = OpenStore(location);
        var stderr = Console.Error;
        ProgramImport result;
        try
        {
            result = store.ImportRevision(path, machine, d => stderr.WriteLine(d.Format(path)), ct);
        }
        catch (Exception e) when (e is Microsoft.Data.Sqlite.SqliteException or Npgsql.NpgsqlException or IOException or UnauthorizedAccessException)
        {
            throw new CliException($"store {location.Display}: the import failed and was rolled back: {StoreLocation.Redact(e.Message)}");
        }

        Console.Out.WriteLine(result.Id.ToString(CultureInfo.InvariantCulture));
        return result.Summary.HasErrors ? CliGlobals.Failed : CliGlobals.Ok;
    }

    private static int List(StoreLocation location, bool json)
    {
        using var store = OpenStore(location);
        var programs = store.ListRevisions();
        if (json)
        {
            WriteJson(w =>
            {
                w.WriteStartArray();
                foreach (var p in programs)
                {
                    WriteProgram(w, p);
                }

                w.WriteEndArray();
            });
            return CliGlobals.Ok;
        }

        Console.Out.WriteLine($"{"id",6}  {"name",-28} {"profile",-12} {"blocks",10} {"errors",6} {"warnings",8}  {"imported",-20} sha256");
        foreach (var p in programs)
        {
            Console.Out.WriteLine(string.Create(CultureInfo.InvariantCulture,
                $"{p.Id,6}  {Cut(p.Name ?? Path.GetFileName(p.Path), 28),-28} {p.Profile,-12} {p.Blocks,10} {p.Errors,6} {p.Warnings,8}  {p.Created.UtcDateTime:yyyy-MM-dd HH:mm:ss}Z {p.Sha256[..12]}"));
        }

        return CliGlobals.Ok;
    }

    private static int Show(StoreLocation location, long id, bool json)
    {
        using var store = OpenStore(location);
        var p = store.GetProgram(id) ?? throw new CliException($"no program {id} in {location.Display}");
        var diagnostics = store.GetDiagnostics(id);
        var name = p.Name ?? Path.GetFileName(p.Path);
        if (json)
        {
            WriteJson(w =>
            {
                WriteProgram(w, p, end: false);
                w.WriteStartArray("diagnostics");
                foreach (var d in diagnostics.Take(ShownDiagnostics))
                {
                    w.WriteStartObject();
                    w.WriteString("severity", d.Severity == Severity.Error ? "error" : "warning");
                    w.WriteString("code", d.Code);
                    w.WriteNumber("line", d.Line);
                    w.WriteNumber("column", d.Column);
                    w.WriteString("message", d.Message);
                    w.WriteEndObject();
                }

                w.WriteEndArray();
                w.WriteEndObject();
            });
            return CliGlobals.Ok;
        }

        var o = Console.Out;
        o.WriteLine($"program {p.Id}: {name}");
        o.WriteLine($"  imported from {p.Path}");
        o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  imported  {p.Created.UtcDateTime:yyyy-MM-dd HH:mm:ss}Z"));
        o.WriteLine($"  profile   {p.Profile}");
        o.WriteLine($"  sha256    {p.Sha256}");
        o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  size      {p.Size} bytes, {p.Lines} lines"));
        o.WriteLine($"  check     {p.CheckSummary}, estimated {TimeSpan.FromSeconds(Math.Round(p.EstimatedSeconds)):c}");
        if (store.ReadExpansionMap(id) is { } map)
        {
            // Its blocks are numbered by expanded line (as M0== counts them); the map says where each came from.
            var files = string.Join(", ", map.Files.Select(Path.GetFileName));
            o.WriteLine(string.Create(CultureInfo.InvariantCulture, $"  expanded  {map.Lines} lines from {files}; e.g. expanded line {map.Lines} is {map.Describe(map.Lines)} (start at a source line with programs start {id} --from-line N --call K --file NAME)"));
        }
        foreach (var d in diagnostics.Take(ShownDiagnostics))
        {
            o.WriteLine("  " + d.Format(name));
        }

        if (diagnostics.Count > ShownDiagnostics)
        {
            o.WriteLine($"  ... and {diagnostics.Count - ShownDiagnostics} more");
        }

        return CliGlobals.Ok;
    }

    private static int Export(StoreLocation location, long id, string? outFile)
    {
        using var store = OpenStore(location);
        if (store.GetProgram(id) is null)
        {
            throw new CliException($"no program {id} in {location.Display}");
        }

        if (outFile is null)
        {
            using var stdout = Console.OpenStandardOutput();
            return store.ExportSource(id, stdout) ? CliGlobals.Ok : throw new CliException($"program {id} was stored by check --db, without its source");
        }

        // Written beside the target and renamed when complete: nothing half-written.
        var full = Path.GetFullPath(outFile);
        var temp = full + $".{Environment.ProcessId}.exporting";
        try
        {
            bool ok;
            using (var f = new FileStream(temp, FileMode.CreateNew, FileAccess.Write))
            {
                ok = store.ExportSource(id, f);
            }

            if (!ok)
            {
                throw new CliException($"program {id} was stored by check --db, without its source");
            }

            File.Move(temp, full, overwrite: true);
        }
        finally
        {
            File.Delete(temp);
        }

        return CliGlobals.Ok;
    }

    private static int Remove(StoreLocation location, long id)
    {
        using var store = OpenStore(location);
        if (store.GetProgram(id) is null)
        {
            throw new CliException($"no program {id} in {location.Display}");
        }

        store.DeleteProgram(id);
        Console.Out.WriteLine($"removed program {id}");
        return CliGlobals.Ok;
    }

    private static void WriteProgram(Utf8JsonWriter w, ProgramInfo p, bool end = true)
    {
        w.WriteStartObject();
        w.WriteNumber("id", p.Id);
        w.WriteString("name", p.Name ?? Path.GetFileName(p.Path));
        w.WriteString("path", p.Path);
        w.WriteString("sha256", p.Sha256);
        w.WriteString("profile", p.Profile);
        w.WriteNumber("size", p.Size);
        w.WriteNumber("lines", p.Lines);
        w.WriteNumber("blocks", p.Blocks);
        w.WriteNumber("errors", p.Errors);
        w.WriteNumber("warnings", p.Warnings);
        w.WriteNumber("estimatedSeconds", Math.Round(p.EstimatedSeconds, 3));
        w.WriteString("check", p.CheckSummary);
        w.WriteString("imported", p.Created.UtcDateTime.ToString("yyyy-MM-dd'T'HH:mm:ss.fff'Z'", CultureInfo.InvariantCulture));
        if (end)
        {
            w.WriteEndObject();
        }
    }

    /// <summary>Writes one JSON document to standard output.</summary>
    internal static void WriteJson(Action<Utf8JsonWriter> write) => WriteJson(Console.Out, write);

    /// <summary>Writes indented JSON (non-ASCII as is) to <paramref name="output"/>.</summary>
    internal static void WriteJson(TextWriter output, Action<Utf8JsonWriter> write)
    {
        var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Indented = true, Encoder = System.Text.Encodings.Web.JavaScriptEncoder.UnsafeRelaxedJsonEscaping }))
        {
            write(w);
        }

        output.WriteLine(Encoding.UTF8.GetString(buffer.GetBuffer(), 0, (int)buffer.Length));
    }

    private static string Cut(string s, int n) => s.Length <= n ? s : s[..(n - 1)] + "~";
}
