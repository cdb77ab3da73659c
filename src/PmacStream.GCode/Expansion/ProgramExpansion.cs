using System.Globalization;

namespace PmacStream.GCode.Expansion;

/// <summary>
/// Where expansion meets checking and splitting: whether a program is expanded under a profile, the expanded text as
/// a stream, and diagnostics of expanded lines taken back to the source (the line of the checked file, and where in
/// a subprogram and which call it came from).
/// </summary>
public static class ProgramExpansion
{
    /// <summary>
    /// True when <paramref name="path"/> is expanded under <paramref name="profile"/>: the profile expands a macro
    /// language and the program uses it. A program without subprograms or macros is read as it is (and tracked by its
    /// source lines, exactly as before).
    /// </summary>
    public static bool Applies(string path, MachineProfile? profile) =>
        profile is { Macros: not MacroDialect.None } && MacroExpander.Needs(path, profile.Macros);

    /// <summary>The options for a profile (its dialect and tables), with <paramref name="options"/>' folders, limits and variable file.</summary>
    public static ExpansionOptions For(MachineProfile profile, ExpansionOptions? options) =>
        (options ?? new ExpansionOptions()) with { Dialect = profile.Macros, Profile = options?.Profile ?? profile };

    /// <summary>
    /// A reader of the program as the controller gets it: its expansion when <see cref="Applies"/> (lines numbered as
    /// <c>M0==</c> numbers them), else its file. What replays a program to a tracked line (start from a line, resume,
    /// move times, the job gate) reads through this, so a line means the same block everywhere.
    /// </summary>
    public static GCodeReader OpenReader(string path, MachineProfile profile, ExpansionOptions? options = null) =>
        Applies(path, profile) ? new GCodeReader(new ExpandedStream(new MacroExpander(path, For(profile, options)))) : GCodeReader.Open(path);

    /// <summary>Checks a program through its expansion (what <see cref="Checker.CheckFile"/> does when <see cref="Applies"/>).</summary>
    public static CheckSummary Check(Checker checker, string path, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock,
        ExpansionOptions? options, CancellationToken cancellationToken)
    {
        var expander = new MacroExpander(path, For(checker.Profile, options));
        using var stream = new ExpandedStream(expander);
        var summary = checker.Check(stream, path, d => onDiagnostic(ToSource(d, expander.Map)), onBlock, cancellationToken);
        if (expander.Error is { } e)
        {
            onDiagnostic(ToDiagnostic(e, path));
            summary = summary with { Errors = summary.Errors + 1 };
        }

        return summary;
    }

    /// <summary>
    /// Checks a program through its expansion handing the interpreter to <paramref name="onInterpreted"/> after each
    /// expanded block: the store's import, whose blocks are numbered as <c>M0==</c> numbers them. With
    /// <paramref name="map"/>, the expansion's source map is kept there too (the store keeps it with the revision).
    /// </summary>
    public static CheckSummary Check(Checker checker, string path, Action<Diagnostic> onDiagnostic, Action<Interpreter> onInterpreted,
        ExpansionOptions? options, CancellationToken cancellationToken, ExpansionMap? map = null)
    {
        ArgumentNullException.ThrowIfNull(checker);
        var expander = new MacroExpander(path, For(checker.Profile, options), map);
        using var stream = new ExpandedStream(expander);
        var summary = checker.Check(stream, path, d => onDiagnostic(ToSource(d, expander.Map)), onInterpreted, cancellationToken);
        if (expander.Error is { } e)
        {
            onDiagnostic(ToDiagnostic(e, path));
            summary = summary with { Errors = summary.Errors + 1 };
        }

        return summary;
    }

    /// <summary>
    /// A diagnostic of an expanded line, on the source line it came from: in the checked file, that line (with the
    /// call and iteration it ran in); in a subprogram file, the main program's calling line, naming the file's line.
    /// </summary>
    public static Diagnostic ToSource(Diagnostic d, ExpansionMap map)
    {
        if (d.Line <= 0 || map.Find(d.Line) is not { } o)
        {
            return d;
        }

        var context = o.Frame != 0 || o.Iteration > 0 ? $" [{map.Describe(d.Line)}]" : string.Empty;
        if (o.File == 0)
        {
            return d with { Line = o.Line, Message = d.Message + context };
        }

        var main = map.MainLine(d.Line);
        return d with { Line = main > 0 ? main : d.Line, Column = 1, Message = $"{d.Message} [{Path.GetFileName(map.Files[o.File])}:{o.Line}:{d.Column}; {map.Describe(d.Line)}]" };
    }

    /// <summary>An expansion's refusal as a diagnostic of the checked file <paramref name="path"/>.</summary>
    public static Diagnostic ToDiagnostic(ExpansionException e, string path)
    {
        var same = string.Equals(Path.GetFullPath(path), Path.GetFullPath(e.File), StringComparison.Ordinal);
        var context = e.Context.Length > 0 ? $" ({e.Context})" : string.Empty;
        return same
            ? new Diagnostic(Severity.Error, e.Code, e.Line, e.Column, e.Message + context)
            : new Diagnostic(Severity.Error, e.Code, e.MainLine > 0 ? e.MainLine : 1, 1,
                string.Create(CultureInfo.InvariantCulture, $"{e.Message} [{Path.GetFileName(e.File)}:{e.Line}:{e.Column}]{context}"));
    }
}
