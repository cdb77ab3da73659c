using System.Text.Json.Nodes;
using PmacStream.GCode;

namespace PmacStream.IntegrationTests.Streaming;

/// <content>
/// Issue 27: rs274 runs o-words and FANUC-style M98/M99 itself; the host's expansion of the same programs must pass
/// through every one of its canonical moves in order.
/// </content>
public partial class Rs274ComparisonTests
{
    /// <summary>FANUC-style subprograms as rs274 runs them (M98 P L, M99; no Custom Macro B, which rs274 does not read).</summary>
    private const string FanucSubprograms = """
        O0001
        G21 G90 G17 G94 G40 G49 G54
        T1 M6
        G43 H1
        G0 X0 Y0 Z5
        M98 P1002 L3
        G0 X50 Y5
        M98 P1003
        G0 Z30
        M30
        O1002
        G91 G1 X5 Z-0.5 F300
        G90 G0 Z5
        G91 G2 X5 Y0 R2.5
        G90
        M99
        O1003
        G1 X60 Y10 F500
        M98 P1002
        M99
        """;

    /// <summary>fanuc-mill with rs274's tool lengths (and no work offsets: rs274 has none without a parameter file).</summary>
    private static MachineProfile FanucWithTools()
    {
        var json = JsonNode.Parse(MachineProfile.Named("fanuc-mill")!.ToJson())!.AsObject();
        json["toolLengths"] = new JsonObject { ["1"] = 50, ["2"] = 75.5, ["3"] = 42.25 };
        return MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+tools");
    }

    [SkippableFact]
    public void Rs274_passes_through_every_block_end_of_expanded_subprograms_and_o_words()
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274-expand");
        var dir = temp.Path;
        foreach (var (name, text, profile) in new[]
        {
            ("fanuc-subs.ngc", FanucSubprograms, FanucWithTools()),
            ("owords.ngc", ExpansionProofTests.OWords, Machine()),
        })
        {
            var path = Path.Combine(dir, name);
            File.WriteAllText(path, text + "\n");
            var diags = new List<Diagnostic>();
            new Checker(profile).CheckFile(path, diags.Add);
            diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty($"{name} checks clean under {profile.Name}");
            var (accepted, why) = CompareExpanded(rs274, path, profile, dir);
            accepted.Should().BeTrue(why);
            output.WriteLine($"{name}: {why}");
        }

        // The comparison can fail: three steps expanded where rs274 ran two do not lie on its moves.
        var two = Path.Combine(dir, "two.ngc");
        File.WriteAllText(two, FanucSubprograms.Replace("L3", "L2", StringComparison.Ordinal) + "\n");
        var three = Path.Combine(dir, "fanuc-subs.ngc");
        var wrong = () => CompareExpanded(rs274, three, FanucWithTools(), dir, canonFrom: two);
        wrong.Should().Throw<Exception>().WithMessage("*rs274 never reaches*");
    }

    /// <summary><see cref="Compare"/> for the host's expansion of the program (expanded block ends against rs274's moves).</summary>
    private static (bool Accepted, string Why) CompareExpanded(string rs274, string path, MachineProfile profile, string dir, string? canonFrom = null)
    {
        var (exit, canon, err) = Run(rs274, canonFrom ?? path, dir, profile);
        var complaint = (err + canon).Split('\n').Select(l => l.Trim()).FirstOrDefault(l => l.Length > 0 && l != "executing" && !CanonLine().IsMatch(l));
        if (exit != 0 || complaint is not null)
        {
            return (false, $"rs274 refused it (exit {exit}): {complaint}");
        }

        var moves = Moves(canon, out var inch);
        var tolerance = inch ? InchTolerance : Tolerance;
        var ends = ExpansionProofTests.Expected(path, profile);
        var at = 0;
        foreach (var (line, end) in ends)
        {
            while (at < moves.Count && Distance(moves[at], end) > tolerance)
            {
                at++;
            }

            at.Should().BeLessThan(moves.Count, $"{Path.GetFileName(path)}: expanded line {line}: rs274 never reaches ({end.X}, {end.Y}, {end.Z}) after the ends before it");
            at++;
        }

        return (true, $"{ends.Count} expanded block ends, all on rs274's {moves.Count} moves in order");
    }
}
