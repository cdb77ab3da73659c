using System.CommandLine;
using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preview;

namespace PmacStream.Cli.Commands;

/// <summary>The options of <c>pmacstream preview</c>, bound.</summary>
/// <param name="File">The G-code program.</param>
/// <param name="Png">The PNG file written.</param>
/// <param name="Size">WIDTHxHEIGHT.</param>
/// <param name="View">xy, xz, yz or iso.</param>
/// <param name="Executed">The simulator's executed-move log, or null.</param>
/// <param name="Lang">Legend language, null: the UI culture.</param>
/// <param name="Profile">Machine profile name or file, null: the default.</param>
/// <param name="Force">Draw a program with errors.</param>
/// <param name="ProgramId">A stored revision to draw from its stored blocks instead of a file (<c>--program ID</c>).</param>
/// <param name="Store">The store of <paramref name="ProgramId"/> (<c>--store URI</c>; null: the default).</param>
internal sealed record PreviewArgs(string? File, string Png, string Size, string View, string? Executed, string? Lang, string? Profile, bool Force,
    long? ProgramId = null, string? Store = null);

/// <summary>
/// `pmacstream preview FILE|--program ID [--store URI] --png OUT.png [--size 1200x900] [--view xy|xz|yz|iso] [--executed LOG] [--lang en|zh-CN] [--profile NAME|FILE] [--force]`:
/// draws the toolpath (two streaming passes, bounded memory; a stored revision from its stored decoded blocks, the file
/// neither read nor interpreted again) and, with a simulator executed-move log, overlays what
/// ran and lists the lines that ran zero or several times. A program with errors under the profile is refused as every
/// command refuses it (each error listed, nothing written) unless <c>--force</c>, which draws what can be read.
/// Exit 0 when drawn (and, with a log, every move ran exactly once), 1 when the program has errors (refused) or the log
/// shows gaps or repeats, 2 for usage and I/O errors.
/// </summary>
internal static class PreviewCommand
{
    private const int MaxListed = 20;

    public static Command Create()
    {
        var file = new Argument<string?>("file") { Description = "G-code program to draw (or --program ID).", Arity = ArgumentArity.ZeroOrOne };
        var programId = new Option<long?>("--program") { Description = "Draw a stored revision from its stored decoded blocks (pmacstream programs list), not a file.", HelpName = "ID" };
        var store = StoreOptions.Option();
        var png = new Option<string>("--png") { Description = "PNG file to write (replaced atomically).", Required = true, HelpName = "OUT.png" };
        var size = new Option<string>("--size") { Description = "Image size WIDTHxHEIGHT, each 16..8192.", HelpName = "WxH", DefaultValueFactory = _ => "1200x900" };
        var view = new Option<string>("--view") { Description = "View: xy, xz, yz or iso.", DefaultValueFactory = _ => "xy" };
        view.AcceptOnlyFromAmong("xy", "xz", "yz", "iso");
        var executed = new Option<string?>("--executed") { Description = "Simulator executed-move log (CSV: sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block; older logs without block, or without a,b,c, are read too) to overlay; lists lines run zero or several times.", HelpName = "LOG.csv" };
        var lang = new Option<string?>("--lang") { Description = "Legend language: en or zh-CN (default: the UI culture). Chinese needs a font with Chinese glyphs, e.g. fonts-noto-cjk." };
        var profile = CliProfiles.Option();
        var force = new Option<bool>("--force") { Description = "Draw a program that has errors under the machine profile: the blocks that cannot be read are listed and left out." };

        var cmd = new Command("preview", "Draw the toolpath of a program to a PNG (rapids dashed, feeds solid, arcs as arcs). A program with errors is refused (--force draws what can be read); exit 1 too when the executed log shows moves run zero or several times.");
        cmd.Arguments.Add(file);
        cmd.Options.Add(png);
        cmd.Options.Add(size);
        cmd.Options.Add(view);
        cmd.Options.Add(executed);
        cmd.Options.Add(lang);
        cmd.Options.Add(profile);
        cmd.Options.Add(force);
        cmd.Options.Add(programId);
        cmd.Options.Add(store);
        cmd.SetAction((parse, ct) => RunAsync(
            new PreviewArgs(parse.GetValue(file), parse.GetValue(png)!, parse.GetValue(size)!, parse.GetValue(view)!, parse.GetValue(executed), parse.GetValue(lang), parse.GetValue(profile),
                parse.GetValue(force), parse.GetValue(programId), parse.GetValue(store)),
            CliConsole.Of(parse),
            ct));
        return cmd;
    }

    /// <summary>Draws the preview of <paramref name="args"/>; returns the exit code.</summary>
    /// <exception cref="CliException">Usage and I/O errors, a log that cannot be read, no drawing library.</exception>
    internal static async Task<int> RunAsync(PreviewArgs args, CliConsole console, CancellationToken ct)
    {
        var machine = CliProfiles.Load(args.Profile);
        var output = args.Png;
        var (width, height) = ParseSize(args.Size);
        var culture = args.Lang is { } l ? CliGlobals.ParseLanguage(l) : CultureInfo.CurrentUICulture;
        if (args.Executed is { } log)
        {
            CliGlobals.RequireFile(log, "an executed-move log (--executed)");
        }

        var outDir = Path.GetDirectoryName(Path.GetFullPath(output));
        if (outDir is not null && !Directory.Exists(outDir))
        {
            throw new CliException($"{output}: the folder {outDir} does not exist");
        }

        using var drawing = Open(args, machine);
        var (source, path) = (drawing.Source, drawing.Shown);
        var options = new PreviewOptions { Width = width, Height = height, View = ParseView(args.View), Culture = culture, DrawIf = args.Force ? null : () => drawing.Issues.IssueCount == 0 };
        if (await RenderAsync(drawing, options, args, machine, console, ct).ConfigureAwait(false) is not { } picture)
        {
            return CliGlobals.Failed;
        }

        using var drawn = picture;
        var x = picture.Extents;
        if (x.IsEmpty)
        {
            // An empty picture is no preview: nothing is written, and the caller learns it from the exit code.
            foreach (var issue in drawing.Issues.Issues.Take(MaxListed))
            {
                console.Error.WriteLine(issue.Format(path));
            }

            console.Error.WriteLine($"{path}: error: no moves to draw ({(drawing.Issues.IssueCount > 0 ? "none could be interpreted" : "an empty program")}); {output} not written");
            return CliGlobals.Failed;
        }

        drawn.WritePng(output);
        foreach (var warning in drawn.Warnings)
        {
            console.Error.WriteLine($"{output}: warning: {warning}");
        }

        if (source is DecodedBlockToolpathSource { CyclesWithoutHoles: > 0 } stored)
        {
            console.Error.WriteLine($"{path}: warning: {stored.CyclesWithoutHoles} cycle block(s) not drawn: the revision was imported before the store kept cycle holes (schema 9); import it again to draw them");
        }

        return Report(args, drawing, picture, width, height, console);
    }

    /// <summary>What is drawn: the file (read and interpreted), or a stored revision's decoded blocks (the store held open while drawing).</summary>
    private sealed class Drawing(IToolpathSource source, IToolpathIssues issues, string shown, string profile, IDisposable? store = null) : IDisposable
    {
        /// <summary>The profile the blocks were interpreted under (a stored revision's is its import's).</summary>
        public string Profile { get; } = profile;

        public IToolpathSource Source { get; } = source;

        public IToolpathIssues Issues { get; } = issues;

        /// <summary>How messages name it: the file as given, or <c>program ID (NAME)</c>.</summary>
        public string Shown { get; } = shown;

        public void Dispose() => store?.Dispose();
    }

    private static Drawing Open(PreviewArgs args, MachineProfile machine)
    {
        if (args.ProgramId is not { } id)
        {
            var path = args.File ?? throw new CliException("say what to draw: a FILE or --program ID");
            CliGlobals.RequireFile(path, "a G-code file");
            var file = new GCodeToolpathSource(path, machine);
            return new Drawing(file, file, path, machine.Name);
        }

        if (args.File is not null)
        {
            throw new CliException("give a FILE or --program ID, not both");
        }

        var location = StoreOptions.Resolve(args.Store);
        var store = ProgramsCommand.OpenStore(location);
        try
        {
            var info = store.GetProgram(id) ?? throw new CliException($"no program {id} in {location.Display}");
            if (args.Profile is not null && !string.Equals(info.Profile, machine.Name, StringComparison.OrdinalIgnoreCase))
            {
                // The stored positions are the import's interpretation: drawing them under another profile would lie.
                throw new CliException($"program {id} was imported under profile '{info.Profile}', not '{machine.Name}': its stored blocks are drawn as that profile read them (import it under '{machine.Name}' to draw it so)");
            }

            var errors = store.GetDiagnostics(id).Where(d => d.Severity == Severity.Error).ToList();
            var source = new DecodedBlockToolpathSource(
                () => store.ReadStoredBlocks(id).Select(b => (b.Block, b.Holes)), info.Blocks, info.Name ?? Path.GetFileName(info.Path),
                errors.Take(GCodeToolpathSource.MaxIssuesKept).ToList(), Math.Max(info.Errors, errors.Count));
            return new Drawing(source, source, $"program {id.ToString(CultureInfo.InvariantCulture)} ({info.Name ?? info.Path})", info.Profile, store);
        }
        catch
        {
            store.Dispose();
            throw;
        }
    }

    /// <summary>Renders the picture, or refuses a program with errors (listed; null returned).</summary>
    private static async Task<PreviewPicture?> RenderAsync(Drawing drawing, PreviewOptions options, PreviewArgs args, MachineProfile machine, CliConsole console, CancellationToken ct)
    {
        var (source, issues) = (drawing.Source, drawing.Issues);
        try
        {
            return await CliProgress.RunAsync("preview", console, report => Task.Run(
                () => PreviewRenderer.Render(source, options with { Progress = (f, s) => report(f, s) }, args.Executed, ct),
                ct)).ConfigureAwait(false);
        }
        catch (PreviewRefusedException)
        {
            // The gate every command keeps: a program with errors is not drawn as if it were whole (refused after
            // the measuring pass, before the picture takes its memory).
            Refusals.Print(console.Error, "pmacstream preview", "preview", Refusals.Shown(drawing.Shown), issues.Issues.Take(MaxListed).ToList(), (int)Math.Min(int.MaxValue, issues.IssueCount),
                $"{Refusals.Shown(drawing.Shown)}: {issues.IssueCount} error(s) under profile '{drawing.Profile}'; {args.Png} not written");
            return null;
        }
        catch (InvalidDataException e)
        {
            throw new CliException(e.Message, CliGlobals.Failed);
        }
        catch (Exception e) when (MissingNativeLibrary(e) is { } missing)
        {
            throw new CliException(
                $"cannot draw: the native drawing library did not load ({missing}). The preview needs libSkiaSharp, which ships with pmacstream, and fontconfig (Debian/Ubuntu: apt-get install libfontconfig1)");
        }
    }

    /// <summary>What was drawn, what was left out, and what the executed log shows; the exit code.</summary>
    private static int Report(PreviewArgs args, Drawing drawing, PreviewPicture picture, int width, int height, CliConsole console)
    {
        var (source, issues) = (drawing.Source, drawing.Issues);
        var ci = CultureInfo.InvariantCulture;
        var x = picture.Extents;
        var o = console.Out;
        o.WriteLine($"wrote {args.Png} ({width}x{height}, view {args.View}): {x.Moves.ToString(ci)} moves ({x.Lines.ToString(ci)} linear, {x.Arcs.ToString(ci)} arc, {x.Rapids.ToString(ci)} rapid)");
        o.WriteLine(string.Create(ci, $"extents (mm): X {x.Min.X:0.###} .. {x.Max.X:0.###}, Y {x.Min.Y:0.###} .. {x.Max.Y:0.###}, Z {x.Min.Z:0.###} .. {x.Max.Z:0.###}; program units {(picture.Units == LengthUnits.Inches ? "inch" : "mm")}"));
        if (source.RotaryAxes.Length > 0)
        {
            o.WriteLine($"rotary axes {string.Join(' ', source.RotaryAxes.ToCharArray())}: not drawn (the picture shows X, Y and Z; the legend says so)");
        }

        if (issues.IssueCount > 0)
        {
            // Forced: drawn, and what was left out is said.
            Refusals.Print(console.Error, "pmacstream preview", string.Empty, Refusals.Shown(drawing.Shown), issues.Issues.Take(MaxListed).ToList(), (int)Math.Min(int.MaxValue, issues.IssueCount),
                $"--force: {issues.IssueCount} error(s) listed above; the blocks that cannot be read are not drawn");
        }

        if (picture.Execution is not { } report)
        {
            return CliGlobals.Ok;
        }

        o.WriteLine($"executed log {args.Executed}: {report.LogRows.ToString(ci)} moves");
        if (report.IsExact)
        {
            o.WriteLine("every drawn move was executed exactly once");
            return CliGlobals.Ok;
        }

        Describe(o, "never executed", report.MissingLines, report.Missing, r => string.Empty);
        Describe(o, "executed more than once", report.RepeatedLines, report.Repeated, r => r.Times == 255 ? " (255+ times)" : $" ({r.Times} times)");
        return CliGlobals.Failed;
    }

    private static void Describe(TextWriter o, string what, long lines, IReadOnlyList<LineRun> runs, Func<LineRun, string> suffix)
    {
        if (lines == 0)
        {
            return;
        }

        o.WriteLine($"{what}: {lines.ToString(CultureInfo.InvariantCulture)} lines");
        foreach (var run in runs.Take(MaxListed))
        {
            o.WriteLine($"  {run}{suffix(run)}");
        }

        if (runs.Count > MaxListed)
        {
            o.WriteLine($"  ... ({runs.Count - MaxListed}{(runs.Count >= ExecutionReport.MaxRuns ? "+" : string.Empty)} more runs)");
        }
    }

    /// <summary>
    /// When Skia's native library (or one it needs, such as libfontconfig) did not load: the loader's first reason,
    /// which names the file (its first line is only general advice).
    /// </summary>
    private static string? MissingNativeLibrary(Exception e)
    {
        for (Exception? x = e; x is not null; x = x.InnerException)
        {
            if (x is DllNotFoundException dll)
            {
                var lines = dll.Message.Split('\n', StringSplitOptions.TrimEntries | StringSplitOptions.RemoveEmptyEntries);
                return lines.Length > 1 ? lines[1] : lines.FirstOrDefault() ?? dll.GetType().Name;
            }
        }

        return null;
    }

    internal static (int Width, int Height) ParseSize(string text)
    {
        var parts = text.Split('x', 'X');
        if (parts.Length == 2
            && int.TryParse(parts[0], NumberStyles.None, CultureInfo.InvariantCulture, out var w)
            && int.TryParse(parts[1], NumberStyles.None, CultureInfo.InvariantCulture, out var h)
            && w is >= 16 and <= 8192 && h is >= 16 and <= 8192)
        {
            return (w, h);
        }

        throw new CliException($"--size expects WIDTHxHEIGHT such as 1200x900, each 16..8192; got '{text}'");
    }

    private static PreviewView ParseView(string text) => text switch
    {
        "xz" => PreviewView.XZ,
        "yz" => PreviewView.YZ,
        "iso" => PreviewView.Iso,
        _ => PreviewView.XY,
    };
}
