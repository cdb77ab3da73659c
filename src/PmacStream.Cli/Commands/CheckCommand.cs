using System.CommandLine;
using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// `pmacstream check FILE [--profile NAME|FILE] [--json] [--db PATH] [--lang en|zh-CN]`: one streamed pass that lists
/// every diagnostic (<c>FILE:LINE:COL: error E104: ...</c>) and a summary line, optionally storing every block.
/// Exit 0 without errors, 1 with errors, 2 for usage or I/O problems.
/// </summary>
internal static class CheckCommand
{
    /// <summary>JSON output keeps at most this many diagnostics (the counts stay exact) so memory stays bounded.</summary>
    internal const int JsonDiagnosticLimit = 100_000;

    public static Command Create()
    {
        var file = new Argument<string>("file") { Description = "G-code program to check." };
        var profile = CliProfiles.Option();
        var json = new Option<bool>("--json") { Description = "Print one JSON object instead of text lines." };
        var db = new Option<string?>("--db") { Description = "Store every interpreted block and diagnostic in this SQLite file." };
        var lang = new Option<string?>("--lang") { Description = "Message language: en or zh-CN (default: the UI culture)." };
        var cmd = new Command("check", "Check a G-code program and list every error and warning.");
        cmd.Arguments.Add(file);
        cmd.Options.Add(profile);
        cmd.Options.Add(json);
        cmd.Options.Add(db);
        cmd.Options.Add(lang);
        cmd.SetAction((parse, ct) => new CheckHandler().RunAsync(
            new CheckOptions(parse.GetValue(file)!, parse.GetValue(profile), parse.GetValue(json), parse.GetValue(db), parse.GetValue(lang)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>check</c> command line asks for.</summary>
/// <param name="File">The program.</param>
/// <param name="Profile">The machine profile named, if any.</param>
/// <param name="Json">Print one JSON object.</param>
/// <param name="Db">Store every block and diagnostic in this SQLite file.</param>
/// <param name="Lang">The language of the messages, if given.</param>
internal sealed record CheckOptions(string File, string? Profile, bool Json, string? Db, string? Lang);

/// <summary><c>pmacstream check</c>: one streamed pass that lists every diagnostic and a summary line.</summary>
internal sealed class CheckHandler
{
    /// <summary>Checks the program; exit 0 without errors, 1 with errors.</summary>
    public Task<int> RunAsync(CheckOptions o, CliConsole console, CancellationToken ct) =>
        // On the pool: System.CommandLine registers its Ctrl-C/SIGTERM handling once the action returns its task, so a
        // check that ran on the calling thread could only be killed, not stopped.
        Task.Run(() => Run(o.File, o.Profile, o.Json, o.Db, o.Lang, console, ct), CancellationToken.None);

    private static int Run(string file, string? profilePath, bool json, string? dbPath, string? lang, CliConsole console, CancellationToken ct)
    {
        if (lang != null)
        {
            DiagnosticText.Culture = CliGlobals.ParseLanguage(lang);
        }

        if (Directory.Exists(file))
        {
            throw new CliException($"{file}: is a directory, expected a G-code file");
        }

        if (!File.Exists(file))
        {
            throw new CliException($"{file}: no such file");
        }

        // The tool table at the machine (the host's copy) over the profile's: G41 D1 reads tool 1's radius as set there.
        var machine = Machine.ToolTableProfile.Apply(CliProfiles.Load(profilePath), Machine.MachineTables.Load(Machine.MachineTables.DefaultPath()));

        // Buffered: a program with an error on every line must not cost a write call per line.
        using var buffered = console.IsProcessOutput ? new StreamWriter(Console.OpenStandardOutput(), new UTF8Encoding(false), 1 << 16) { AutoFlush = false } : null;
        var stdout = buffered ?? console.Out;
        var kept = new List<Diagnostic>();
        var dropped = 0;
        Action<Diagnostic> onDiagnostic = json
            ? d =>
            {
                if (kept.Count < CheckCommand.JsonDiagnosticLimit)
                {
                    kept.Add(d);
                }
                else
                {
                    dropped++;
                }
            }
            : d => stdout.WriteLine(d.Format(file));

        CheckSummary summary;
        if (dbPath != null)
        {
            summary = CheckIntoStore(file, dbPath, machine, onDiagnostic, ct);
        }
        else
        {
            summary = new Checker(machine).CheckFile(file, onDiagnostic, null, ct);
        }

        if (json)
        {
            WriteJson(stdout, file, summary, kept, dropped);
        }
        else
        {
            stdout.WriteLine(summary.ToLocalizedString());
        }

        stdout.Flush();
        return summary.HasErrors ? CliGlobals.Failed : CliGlobals.Ok;
    }

    private static CheckSummary CheckIntoStore(string file, string dbPath, MachineProfile machine, Action<Diagnostic> onDiagnostic, CancellationToken ct)
    {
        if (Directory.Exists(dbPath))
        {
            throw new CliException($"--db {dbPath}: is a directory, expected a database file");
        }

        try
        {
            if (!File.Exists(dbPath))
            {
                // A new database: built under a temporary name without a write-ahead log and renamed when complete,
                // so a failed or cancelled import leaves no file behind.
                return ProgramStore.ImportToNewFile(dbPath, file, machine, onDiagnostic, ct).Summary;
            }

            using var store = ProgramStore.Open(dbPath);
            return store.Import(file, machine, onDiagnostic, ct).Summary;
        }
        catch (Exception e) when (e is Microsoft.Data.Sqlite.SqliteException or IOException or UnauthorizedAccessException)
        {
            // The import rolled back (an existing store keeps its other programs).
            throw new CliException($"--db {dbPath}: {e.Message}");
        }
    }

    private static void WriteJson(TextWriter output, string file, CheckSummary summary, List<Diagnostic> diagnostics, int dropped)
    {
        var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Encoder = System.Text.Encodings.Web.JavaScriptEncoder.UnsafeRelaxedJsonEscaping }))
        {
            w.WriteStartObject();
            w.WriteString("file", file);
            w.WriteNumber("blocks", summary.Blocks);
            w.WriteNumber("errors", summary.Errors);
            w.WriteNumber("warnings", summary.Warnings);
            w.WriteStartArray("diagnostics");
            foreach (var d in diagnostics)
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
            if (dropped > 0)
            {
                w.WriteNumber("diagnosticsOmitted", dropped);
            }

            // The codes a job gate refuses (the controller cannot run them yet), with their first line.
            w.WriteStartObject("notYetCodes");
            foreach (var (code, line) in summary.NotYetCodes)
            {
                w.WriteNumber(code, line);
            }

            w.WriteEndObject();

            w.WriteEndObject();
        }

        output.WriteLine(Encoding.UTF8.GetString(buffer.GetBuffer(), 0, (int)buffer.Length));
    }
}
