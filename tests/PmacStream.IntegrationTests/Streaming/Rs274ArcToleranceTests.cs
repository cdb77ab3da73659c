using System.Globalization;
using PmacStream.GCode;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 27 item 3: the checker refuses exactly the arcs LinuxCNC's rs274 refuses (its arc_data_ijk and arc_data_r
/// tolerances, per unit system), on arcs rounded to four decimals and pushed off their circle by growing amounts,
/// and the arcs both accept end where rs274's do.
/// </summary>
public partial class Rs274ComparisonTests
{
    /// <summary>(units, radius, how far the end is pushed off the circle, R format) for each arc compared.</summary>
    private static IEnumerable<(string Units, double Radius, double Off, bool RFormat)> ArcCases()
    {
        foreach (var r in new[] { 0.05, 1.0, 10.0 })
        {
            foreach (var off in new[] { 0, 0.0001, 0.0002, 0.002, 0.0035, 0.01, 0.3 })
            {
                yield return ("G20", r, off, false);
            }
        }

        foreach (var r in new[] { 1.0, 10.0, 100.0, 5000.0 })
        {
            foreach (var off in new[] { 0, 0.005, 0.02, 0.03, 0.05, 0.2, 3.0 })
            {
                yield return ("G21", r, off, false);
            }
        }

        foreach (var (units, short_) in new[] { ("G20", 0.00004), ("G20", 0.00006), ("G20", 0.0002), ("G21", 0.001), ("G21", 0.0015), ("G21", 0.01) })
        {
            yield return (units, 1.0, short_, true);
        }
    }

    private static string ArcProgram(string units, double radius, double off, bool rFormat)
    {
        static string F(double v) => v.ToString("0.0###", CultureInfo.InvariantCulture);
        if (rFormat)
        {
            // A chord of 2 x radius: R is `off` shorter than half of it.
            return $"{units} G90 G17 G94\nG0 X0 Y0 Z1\nG1 Z0 F10\nG2 X{F(2 * radius)} Y0 R{(radius - off).ToString("0.0#####", CultureInfo.InvariantCulture)}\nG0 Z1\nM2\n";
        }

        // Centre (radius, 0) from a start at the origin; the end at 1.1 rad, pushed out by `off`, rounded to 4 decimals.
        var a = Math.PI - 1.1;
        var ex = radius + ((radius + off) * Math.Cos(a));
        var ey = (radius + off) * Math.Sin(a);
        return $"{units} G90 G17 G94\nG0 X0 Y0 Z1\nG1 Z0 F10\nG2 X{F(ex)} Y{F(ey)} I{F(radius)} J0\nG0 Z1\nM2\n";
    }

    [SkippableFact]
    public void Rs274_and_the_checker_refuse_the_same_arcs_in_inch_and_metric_programs()
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274-arcs");
        var profile = Machine();
        var (refused, accepted) = (0, 0);
        var disagreements = new List<string>();
        var log = new List<string>();
        var n = 0;
        foreach (var (units, radius, off, rFormat) in ArcCases())
        {
            var text = ArcProgram(units, radius, off, rFormat);
            var path = Path.Combine(temp.Path, $"arc{n++}.ngc");
            File.WriteAllText(path, text);
            var ours = new Checker(profile).CheckText(text).Diagnostics.Where(d => d.Code == DiagnosticCodes.ArcRadiusMismatch).ToList();
            var (ok, why) = Compare(rs274, path, profile, temp.Path);
            var line = text.Split('\n')[3];
            log.Add($"{units} {line}: rs274 {(ok ? "runs it" : "refuses it")}, checker {(ours.Count > 0 ? "E115" : "runs it")}");
            if (ok == (ours.Count > 0))
            {
                disagreements.Add($"{units} {line}: rs274 {why}; checker {string.Join("; ", ours.Select(d => d.Message))}");
            }

            (refused, accepted) = ok ? (refused, accepted + 1) : (refused + 1, accepted);
        }

        disagreements.Should().BeEmpty(string.Join("\n", log));
        refused.Should().BeGreaterThan(8, "the cases reach past the tolerance");
        accepted.Should().BeGreaterThan(15, "and stay inside it");
    }
}
