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
    public static Command Create()
    {
        var cmd = new Command("programs", "The program library of the store: import, list, show, export, rm.");
        var json = new Option<bool>("--json") { Description = "Print JSON.", Recursive = true };
        var store = StoreOptions.Option();
        store.Recursive = true;
        cmd.Options.Add(json);
        cmd.Options.Add(store);
        Task<int> List(ParseResult parse, CancellationToken ct) =>
            new ProgramsHandler().RunAsync(new ProgramListOptions(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(json)), CliConsole.Of(parse), ct);
        cmd.SetAction(List);

        var list = new Command("list", "List the program revisions, newest first.");
        list.SetAction(List);
        cmd.Subcommands.Add(list);

        var file = new Argument<string>("file") { Description = "G-code program to import." };
        var profile = CliProfiles.Option();
        var import = new Command("import", "Check and decode a program into the store; prints only its revision's id.");
        import.Arguments.Add(file);
        import.Options.Add(profile);
        import.SetAction((parse, ct) => new ProgramsHandler().RunAsync(
            new ProgramImportOptions(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(file)!, CliProfiles.Load(parse.GetValue(profile))), CliConsole.Of(parse), ct));
        cmd.Subcommands.Add(import);

        var showId = new Argument<long>("id") { Description = "Program revision id." };
        var show = new Command("show", "Show a revision: its check summary and diagnostics.");
        show.Arguments.Add(showId);
        show.SetAction((parse, ct) => new ProgramsHandler().RunAsync(new ProgramShowOptions(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(showId), parse.GetValue(json)), CliConsole.Of(parse), ct));
        cmd.Subcommands.Add(show);

        var exportId = new Argument<long>("id") { Description = "Program revision id." };
        var output = new Option<string?>("--out") { Description = "Write to this file instead of standard output." };
        var export = new Command("export", "Write a revision's exact source bytes.");
        export.Arguments.Add(exportId);
        export.Options.Add(output);
        export.SetAction((parse, ct) => new ProgramsHandler().RunAsync(new ProgramExportOptions(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(exportId), parse.GetValue(output)), CliConsole.Of(parse), ct));
        cmd.Subcommands.Add(export);

        var rmId = new Argument<long>("id") { Description = "Program revision id." };
        var rm = new Command("rm", "Remove a revision with its blocks, diagnostics and source.");
        rm.Arguments.Add(rmId);
        rm.SetAction((parse, ct) => new ProgramsHandler().RunAsync(new ProgramRemoveOptions(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(rmId)), CliConsole.Of(parse), ct));
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
}

/// <summary>What a <c>programs</c> or <c>programs list</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="Json">Print JSON.</param>
internal sealed record ProgramListOptions(StoreLocation Store, bool Json);

/// <summary>What a <c>programs import</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="File">The G-code program imported.</param>
/// <param name="Machine">The machine profile it is checked under.</param>
internal sealed record ProgramImportOptions(StoreLocation Store, string File, MachineProfile Machine);

/// <summary>What a <c>programs show</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="Id">The revision.</param>
/// <param name="Json">Print JSON.</param>
internal sealed record ProgramShowOptions(StoreLocation Store, long Id, bool Json);

/// <summary>What a <c>programs export</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="Id">The revision.</param>
/// <param name="Out">The file written, or null for standard output.</param>
internal sealed record ProgramExportOptions(StoreLocation Store, long Id, string? Out);

/// <summary>What a <c>programs rm</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="Id">The revision.</param>
internal sealed record ProgramRemoveOptions(StoreLocation Store, long Id);

/// <summary>
/// <c>pmacstream programs</c>: the store's program library: list, import (checked and decoded in one pass, only the
/// id printed), show, export (the exact source bytes), rm.
/// </summary>
internal sealed class ProgramsHandler
{
    /// <summary>Diagnostics <c>show</c> lists at most (the counts are exact).</summary>
    private const int ShownDiagnostics = 1000;

    /// <summary>Lists the revisions, newest first; returns the exit code.</summary>
    public Task<int> RunAsync(ProgramListOptions o, CliConsole console, CancellationToken ct) => Task.FromResult(List(o.Store, o.Json, console.Out));

    /// <summary>Imports the program; exit 0, or 1 when it has errors (stored with them).</summary>
    public Task<int> RunAsync(ProgramImportOptions o, CliConsole console, CancellationToken ct) =>
        Task.Run(() => Import(o.Store, o.File, o.Machine, console, ct), CancellationToken.None);

    /// <summary>Shows a revision; returns the exit code.</summary>
    public Task<int> RunAsync(ProgramShowOptions o, CliConsole console, CancellationToken ct) => Task.FromResult(Show(o.Store, o.Id, o.Json, console.Out));

    /// <summary>Exports a revision's source; returns the exit code.</summary>
    public Task<int> RunAsync(ProgramExportOptions o, CliConsole console, CancellationToken ct) => Task.FromResult(Export(o.Store, o.Id, o.Out, console));

    /// <summary>Removes a revision; returns the exit code.</summary>
    public Task<int> RunAsync(ProgramRemoveOptions o, CliConsole console, CancellationToken ct) => Task.FromResult(Remove(o.Store, o.Id, console.Out));

    private static int Import(StoreLocation location, string path, MachineProfile machine, CliConsole console, CancellationToken ct)
    {
        if (Directory.Exists(path))
        {
            throw new CliException($"{path}: is a directory, expected a G-code file");
        }

        if (!File.Exists(path))
        {
            throw new CliException($"{path}: no such file");
        }

        using var store = ProgramsCommand.OpenStore(location);
        var stderr = console.Error;
        ProgramImport result;
        try
        {
            result = store.ImportRevision(path, machine, d => stderr.WriteLine(d.Format(path)), ct);
        }
        catch (Exception e) when (e is Microsoft.Data.Sqlite.SqliteException or Npgsql.NpgsqlException or IOException or UnauthorizedAccessException)
        {
            throw new CliException($"store {location.Display}: the import failed and was rolled back: {StoreLocation.Redact(e.Message)}");
        }

        console.Out.WriteLine(result.Id.ToString(CultureInfo.InvariantCulture));
        return result.Summary.HasErrors ? CliGlobals.Failed : CliGlobals.Ok;
    }

    private static int List(StoreLocation location, bool json, TextWriter output)
    {
        using var store = ProgramsCommand.OpenStore(location);
        var programs = store.ListRevisions();
        if (json)
        {
            ProgramsCommand.WriteJson(output, w =>
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

        output.WriteLine($"{"id",6}  {"name",-28} {"profile",-12} {"blocks",10} {"errors",6} {"warnings",8}  {"imported",-20} sha256");
        foreach (var p in programs)
        {
            output.WriteLine(string.Create(CultureInfo.InvariantCulture,
                $"{p.Id,6}  {Cut(p.Name ?? Path.GetFileName(p.Path), 28),-28} {p.Profile,-12} {p.Blocks,10} {p.Errors,6} {p.Warnings,8}  {p.Created.UtcDateTime:yyyy-MM-dd HH:mm:ss}Z {p.Sha256[..12]}"));
        }

        return CliGlobals.Ok;
    }

    private static int Show(StoreLocation location, long id, bool json, TextWriter output)
    {
        using var store = ProgramsCommand.OpenStore(location);
        var p = store.GetProgram(id) ?? throw new CliException($"no program {id} in {location.Display}");
        var diagnostics = store.GetDiagnostics(id);
        var name = p.Name ?? Path.GetFileName(p.Path);
        if (json)
        {
            ProgramsCommand.WriteJson(output, w =>
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

        var o = output;
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

    private static int Export(StoreLocation location, long id, string? outFile, CliConsole console)
    {
        using var store = ProgramsCommand.OpenStore(location);
        if (store.GetProgram(id) is null)
        {
            throw new CliException($"no program {id} in {location.Display}");
        }

        if (outFile is null)
        {
            return ExportToOutput(store, id, console) ? CliGlobals.Ok : throw new CliException($"program {id} was stored by check --db, without its source");
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

    private static int Remove(StoreLocation location, long id, TextWriter output)
    {
        using var store = ProgramsCommand.OpenStore(location);
        if (store.GetProgram(id) is null)
        {
            throw new CliException($"no program {id} in {location.Display}");
        }

        store.DeleteProgram(id);
        output.WriteLine($"removed program {id}");
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

    private static string Cut(string s, int n) => s.Length <= n ? s : s[..(n - 1)] + "~";

    /// <summary>
    /// The source bytes to standard output as they are; a test's console is a text writer, so in process they are
    /// written as UTF-8 text.
    /// </summary>
    private static bool ExportToOutput(IProgramRevisions store, long id, CliConsole console)
    {
        if (console.IsProcessOutput)
        {
            using var stdout = Console.OpenStandardOutput();
            return store.ExportSource(id, stdout);
        }

        using var buffer = new MemoryStream();
        var ok = store.ExportSource(id, buffer);
        console.Out.Write(Encoding.UTF8.GetString(buffer.GetBuffer(), 0, (int)buffer.Length));
        return ok;
    }
}
