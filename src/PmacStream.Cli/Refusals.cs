using PmacStream.GCode;
using PmacStream.Jobs;

namespace PmacStream.Cli;

/// <summary>
/// How every command that reads a program reports a program it refuses: each finding as
/// <c>FILE:LINE:COL: error CODE: message</c>, then one line that says what was not done and the real option that
/// goes on anyway (the commands without one say nothing of it).
/// </summary>
internal static class Refusals
{
    /// <summary>What <c>--force</c> does on each command that has it.</summary>
    private static readonly Dictionary<string, string> Force = new(StringComparer.Ordinal)
    {
        ["stream"] = "--force runs it anyway",
        ["resume"] = "--force resumes it anyway",
        ["split"] = "--force splits anyway",
        ["preview"] = "--force draws what can be read",
    };

    /// <summary>The command's force hint in parentheses, or nothing for a command without <c>--force</c>.</summary>
    public static string ForceHint(string command) => Force.TryGetValue(command, out var hint) ? $" ({hint})" : string.Empty;

    /// <summary>The path as the operator typed it, relative to the current folder when inside it.</summary>
    public static string Shown(string path)
    {
        var relative = Path.GetRelativePath(Environment.CurrentDirectory, path);
        return relative.StartsWith("..", StringComparison.Ordinal) || Path.IsPathRooted(relative) ? path : relative;
    }

    /// <summary>The findings listed (<paramref name="total"/> counts them all), then <c>PREFIX: WHAT (HINT)</c>.</summary>
    public static void Print(TextWriter error, string prefix, string command, string file, IReadOnlyList<Diagnostic> listed, int total, string what)
    {
        foreach (var d in listed)
        {
            error.WriteLine(d.Format(file));
        }

        if (total > listed.Count)
        {
            error.WriteLine($"... and {total - listed.Count} more");
        }

        error.WriteLine($"{prefix}: {what}{ForceHint(command)}");
    }

    /// <summary>A refusal of the job gate: what refused it (errors, codes the controller cannot run, a forced split) and that nothing was sent.</summary>
    public static void Print(TextWriter error, string prefix, string command, ProgramRefusedException e)
    {
        var file = Shown(e.SourcePath);
        var under = e.Profile.Length > 0 ? $" under profile '{e.Profile}'" : string.Empty;
        var what = e.NotRunnableCodes.Count > 0
            ? $"{file}: the controller cannot run {ProgramGate.Describe(e.NotRunnableCodes)} yet{under} (the PMAC would skip each code and run the rest of its block); nothing sent to the controller"
            : e.ForcedSplit
                ? $"{file}: the job's split was forced past the check's errors{under} ('pmacstream check {file}' lists them); nothing sent to the controller"
                : e.ErrorCount > 0
                    ? $"{file}: {e.ErrorCount} error(s){under}; nothing sent to the controller"
                    : $"{e.Message}; nothing sent to the controller";
        Print(error, prefix, command, file, e.Diagnostics, Math.Max(e.ErrorCount, e.Diagnostics.Count), what);
    }
}
