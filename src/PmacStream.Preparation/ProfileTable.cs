using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>One code of a profile as <c>pmacstream profiles NAME</c> and the profile table in docs show it.</summary>
/// <param name="Code">The code (<c>G01</c>).</param>
/// <param name="Group">Its modal group's name.</param>
/// <param name="Meaning">What the code does.</param>
/// <param name="Words">The parameter words it reads (Q, L, P ...), and the ones it needs.</param>
/// <param name="RunsIt">What runs it on the controller: the PROG 1000/1001 routine, or why nothing does yet.</param>
public sealed record ProfileCodeRow(string Code, string Group, string Meaning, string Words, string RunsIt);

/// <summary>
/// A profile's codes with what runs each on the controller (the profile's <see cref="CodeDefinition.Controller"/>
/// joined with <see cref="Prog1000Library"/>'s routines), as rows, plain text or markdown.
/// </summary>
public static class ProfileTable
{
    /// <summary>The profile's codes, G then M, each with its group, meaning, words and what runs it.</summary>
    public static IReadOnlyList<ProfileCodeRow> Rows(MachineProfile profile)
    {
        var routines = Prog1000Library.Routines(profile).ToDictionary(r => r.Code, StringComparer.OrdinalIgnoreCase);
        return profile.GCodes.Concat(profile.MCodes).Select(c =>
        {
            var r = routines[c.Code.Trim().ToUpperInvariant()];
            return new ProfileCodeRow(c.Code, c.Group, c.Description, Words(c), RunsIt(r));
        }).ToList();
    }

    /// <summary>The markdown section of one profile: its facts, then a table of its codes.</summary>
    public static string Markdown(MachineProfile profile)
    {
        var sb = new StringBuilder();
        var ci = CultureInfo.InvariantCulture;
        sb.Append("## ").Append(profile.Name).Append("\n\n").Append(profile.Description).Append("\n\n");
        sb.Append("G04 P in ").Append(profile.DwellPInMilliseconds ? "milliseconds" : "seconds")
            .Append("; block skip `/` inside a block: ").Append(profile.SlashInBlock ? "yes" : "no")
            .Append("; G10 L20: ").Append(profile.ExtendedWorkOffsets ? "extended work offsets (G54.1 P)" : "the current position reads as the values")
            .Append("; G10 L2 P0: ").Append(profile.ExternalWorkOffset ? "the external work offset, added to every work offset" : "the work offset in force")
            .Append("; arcs: ").Append(profile.ArcTolerance.Describe())
            .Append("; subprograms and macros: ").Append(profile.Macros switch
            {
                GCode.Expansion.MacroDialect.Fanuc => "FANUC/Haas subprograms and Custom Macro B, expanded on the host",
                GCode.Expansion.MacroDialect.LinuxCnc => "LinuxCNC o-words and parameters, expanded on the host",
                _ => "not read",
            })
            .Append("; tools 0-").Append(profile.ToolCount.ToString(ci))
            .Append("; letters ").Append(profile.Letters)
            .Append("; power-on `").Append(profile.Startup).Append("`.\n\n");
        sb.Append("G groups (store columns GA-GI for the first nine): ")
            .Append(string.Join(", ", profile.GGroups.Select(g => $"`{g.Name}` {g.Description}{(g.Modal ? "" : " (one-shot)")}"))).Append(".\n");
        sb.Append("M groups (MA-MC for the first three): ")
            .Append(string.Join(", ", profile.MGroups.Select(g => $"`{g.Name}` {g.Description}{(g.Modal ? "" : " (one-shot)")}"))).Append(".\n\n");
        sb.Append("| code | group | meaning | words | what runs it on the controller |\n|---|---|---|---|---|\n");
        foreach (var r in Rows(profile))
        {
            sb.Append("| ").Append(r.Code).Append(" | ").Append(r.Group).Append(" | ").Append(Cell(r.Meaning)).Append(" | ")
                .Append(r.Words).Append(" | ").Append(Cell(r.RunsIt)).Append(" |\n");
        }

        return sb.ToString();
    }

    private static string Words(CodeDefinition c)
    {
        var parts = new List<string>();
        if (c.Words.Length > 0)
        {
            parts.Add(string.Join(' ', c.Words.ToCharArray()));
        }

        if (c.Requires.Length > 0)
        {
            parts.Add("needs " + string.Join(' ', c.Requires.ToCharArray()));
        }

        parts.AddRange(c.Values.Select(v => $"{v.Key} {v.Value.Text}"));
        return string.Join("; ", parts);
    }

    private static string RunsIt(Prog1000Routine r) => r.Controller switch
    {
        // A routine of several lines is shown on one, its lines separated by " / ".
        ControllerSupport.Library when r.Body.Length > 0 => $"PROG {r.Program} N{r.Label}: {r.Body.Replace("\r\n", " / ", StringComparison.Ordinal)}{(r.Note.Length > 0 ? $" ({r.Note})" : "")}",
        ControllerSupport.Library => $"PROG {r.Program} N{r.Label}, empty: {r.Note}",
        ControllerSupport.Host => $"host: {r.Note}",
        _ => $"not yet: {r.Note}",
    };

    private static string Cell(string text) => text.Replace("|", "\\|", StringComparison.Ordinal);
}
