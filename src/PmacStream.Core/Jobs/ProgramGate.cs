using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Jobs;

/// <summary>
/// The job gate's second half, after the check's errors (which refuse the split itself): a program that uses a code
/// the controller cannot run yet (<see cref="ControllerSupport.NotYet"/>, the manifest's <c>notYetCodes</c>) is
/// refused for a job unless forced, because the PMAC would skip the code's missing routine and run the rest of its
/// block (the X/Y after a G28, the cut after an M06 without a tool change). Each such code is reported at its first
/// use as <c>FILE:LINE:COL: error E127: ...</c>; a split forced past the check's errors is refused the same way when
/// a job is resumed from it without force.
/// </summary>
public static class ProgramGate
{
    /// <summary>Throws <see cref="ProgramRefusedException"/> when <paramref name="manifest"/> lists codes the controller cannot run yet, unless <paramref name="force"/>.</summary>
    public static void EnsureRunnable(string sourcePath, ChunkManifest manifest, MachineProfile profile, bool force, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(manifest);
        ArgumentNullException.ThrowIfNull(profile);
        if (force)
        {
            return;
        }

        if (manifest.NotYetCodes is { Count: > 0 } notYet)
        {
            var diagnostics = NotRunnable(sourcePath, notYet, profile, cancellationToken);
            throw new ProgramRefusedException(sourcePath, diagnostics, diagnostics.Count,
                $"{Path.GetFileName(sourcePath)}: the controller cannot run {Describe(notYet)} yet under profile '{profile.Name}'")
            {
                NotRunnableCodes = notYet,
                Profile = profile.Name,
            };
        }

        // Split under a profile (it lists its not-yet codes, none perhaps) but not checked: forced past the check.
        if (manifest.CheckedProfile is null && manifest.NotYetCodes is not null)
        {
            throw new ProgramRefusedException(sourcePath, [], 0,
                $"{Path.GetFileName(sourcePath)}: its split was forced past the check's errors ('pmacstream check' lists them)")
            {
                Profile = profile.Name,
                ForcedSplit = true,
            };
        }
    }

    /// <summary>The codes with their first lines, in line order: <c>G28 (line 9), M06 (line 13)</c>.</summary>
    public static string Describe(IReadOnlyDictionary<string, int> codes)
    {
        ArgumentNullException.ThrowIfNull(codes);
        return string.Join(", ", codes.OrderBy(c => c.Value).ThenBy(c => c.Key, StringComparer.Ordinal).Select(c => $"{c.Key} (line {c.Value})"));
    }

    /// <summary>
    /// One E127 per code at its first use, with the word's column: the source is read up to the last of those lines
    /// (lexed only; the codes are usually in the program's first blocks, a G28 at its end costs one read).
    /// </summary>
    public static IReadOnlyList<Diagnostic> NotRunnable(string sourcePath, IReadOnlyDictionary<string, int> codes, MachineProfile profile, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(codes);
        ArgumentNullException.ThrowIfNull(profile);
        var byLine = codes.GroupBy(c => c.Value).ToDictionary(g => g.Key, g => g.Select(c => c.Key).ToList());
        var last = byLine.Keys.DefaultIfEmpty(0).Max();
        var found = new List<Diagnostic>();
        using (var reader = GCode.Expansion.ProgramExpansion.OpenReader(sourcePath, profile))
        {
            while (reader.LineNumber < last && reader.Read())
            {
                if ((reader.LineNumber & 0xFFF) == 0)
                {
                    cancellationToken.ThrowIfCancellationRequested();
                }

                if (!byLine.TryGetValue(reader.LineNumber, out var here))
                {
                    continue;
                }

                foreach (var code in here)
                {
                    found.Add(Make(code, reader.LineNumber, ColumnOf(reader.Current, code, profile), profile));
                }

                byLine.Remove(reader.LineNumber);
            }
        }

        // A line the manifest names but the file no longer has (it cannot happen for an unchanged program): column 1.
        found.AddRange(byLine.SelectMany(l => l.Value.Select(code => Make(code, l.Key, 1, profile))));
        return found.OrderBy(d => d.Line).ThenBy(d => d.Column).ToList();
    }

    private static int ColumnOf(GBlock block, string code, MachineProfile profile)
    {
        foreach (var w in block.Words)
        {
            if (w.Letter is 'G' or 'M' && profile.Find(w.Letter, w.Value) is { } def && string.Equals(def.Code, code, StringComparison.OrdinalIgnoreCase))
            {
                return w.Column;
            }
        }

        return 1;
    }

    private static Diagnostic Make(string code, int line, int column, MachineProfile profile)
    {
        var what = profile.Find(code[0], double.Parse(code.AsSpan(1), System.Globalization.CultureInfo.InvariantCulture))?.Description ?? string.Empty;
        return new Diagnostic(Severity.Error, DiagnosticCodes.NotRunnableInJob, line, column, DiagnosticText.Format(DiagnosticCodes.NotRunnableInJob, code, what, profile.Name));
    }
}
