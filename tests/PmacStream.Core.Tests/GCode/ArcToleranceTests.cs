using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// Issue 27 item 3: arcs are refused as LinuxCNC refuses them (rs274ngc's arc_data_ijk and arc_data_r), in the
/// program's units, and arcs that run although their end is off the circle by more than rounding are warned (W008).
/// </summary>
public class ArcToleranceTests
{
    private static IReadOnlyList<Diagnostic> Check(string text, string profile = MachineProfile.DefaultName) =>
        new Checker(MachineProfile.Named(profile)!).CheckText(text).Diagnostics;

    private static IReadOnlyList<Diagnostic> Arcs(IReadOnlyList<Diagnostic> d) =>
        d.Where(x => x.Code is DiagnosticCodes.ArcRadiusMismatch or DiagnosticCodes.ArcRoundedOffCircle).ToList();

    [Theory]
    [InlineData("G02 X2.0001 Y0 I1. J0")]
    [InlineData("G02 X2.0002 Y0 I1. J0")]
    [InlineData("G03 X0.1002 Y0 I0.05 J0")]   // a small arc: 0.0002 in is 0.4 % of its radius
    [InlineData("G02 X1.4142 Y0 I0.7071 J-0.7071")]
    public void An_inch_arc_rounded_to_four_decimals_runs_without_a_finding(string arc)
    {
        foreach (var profile in new[] { "fanuc-mill", "linuxcnc-mill" })
        {
            Arcs(Check($"O1\nG20 G90 G17\nG00 X0 Y0\nG01 F10.\n{arc}\nM30", profile)).Should().BeEmpty(profile);
        }
    }

    [Fact]
    public void The_same_arcs_in_millimetres_were_refused_before_units_counted()
    {
        // 0.0002 in = 0.00508 mm on a radius of 1.27 mm (0.4 %): the old rule (0.002 mm and 0.1 %, whatever the units) refused it.
        var old = ArcTolerance.FromMillimetres(0.002);
        old.Refuses(1.27, 1.27 + 0.00508, inch: false).Should().BeTrue();
        ArcTolerance.LinuxCnc.Refuses(0.05, 0.0502, inch: true).Should().BeFalse();
    }

    [Fact]
    public void An_inch_arc_off_by_a_hundredth_is_refused_with_its_radii_in_inches()
    {
        var d = Arcs(Check("O1\nG20 G90 G17\nG00 X0 Y0\nG01 F10.\nG02 X2.01 Y0 I1. J0\nM30"));
        d.Should().ContainSingle().Which.Should().Match<Diagnostic>(x => x.Code == DiagnosticCodes.ArcRadiusMismatch && x.Line == 5 && x.Column == 14);
        d[0].Message.Should().Contain("start radius 1 in").And.Contain("end radius 1.01 in").And.Contain("0.002828 in");
    }

    [Theory]
    [InlineData("G02 X20.02 Y0 I10. J0", false)]     // 0.02 mm: under 2 x 0.01 x sqrt 2 mm
    [InlineData("G02 X20.05 Y0 I10. J0", true)]      // 0.05 mm and 0.5 % of the radius
    [InlineData("G02 X200.05 Y0 I100. J0", false)]   // 0.05 mm but 0.05 % of the radius
    [InlineData("G02 X20003. Y0 I10000. J0", true)]  // 3 mm is 0.03 %, but more than 100 x 0.028 mm
    public void A_metric_arc_is_refused_only_off_by_more_than_the_millimetre_tolerance_and_0_1_percent(string arc, bool refused)
    {
        var d = Check($"O1\nG21 G90 G17\nG00 X0 Y0\nG01 F100.\n{arc}\nM30", "linuxcnc-mill");
        d.Any(x => x.Code == DiagnosticCodes.ArcRadiusMismatch).Should().Be(refused);
    }

    [Theory]
    [InlineData("G20", "G02 X2. Y0 R0.99996", false)]  // 0.00004 in short: inside rs274ngc's 0.00005 in
    [InlineData("G20", "G02 X2. Y0 R0.9999", true)]
    [InlineData("G21", "G02 X20. Y0 R9.999", false)]   // 0.001 mm short: inside 0.00127 mm
    [InlineData("G21", "G02 X20. Y0 R9.998", true)]
    public void An_R_shorter_than_half_the_chord_runs_within_rs274ngcs_radius_tolerance(string units, string arc, bool refused)
    {
        var d = Check($"O1\n{units} G90 G17\nG00 X0 Y0\nG01 F10.\n{arc}\nM30");
        d.Any(x => x.Code == DiagnosticCodes.ArcRadiusMismatch).Should().Be(refused);
        if (refused)
        {
            d.First(x => x.Code == DiagnosticCodes.ArcRadiusMismatch).Message.Should().Contain("shorter than half the chord");
        }
    }

    [Fact]
    public void A_short_R_runs_as_the_half_circle_on_the_chord()
    {
        var interp = new Interpreter(MachineProfile.Default);
        using var reader = new GCodeReader(new MemoryStream(System.Text.Encoding.ASCII.GetBytes("G21 G90 G17\nG00 X0 Y0\nG02 X20. Y0 R9.999 F100.")));
        while (reader.Read())
        {
            interp.Execute(reader.Current);
        }

        interp.LastArc.Centre.Should().Be(new Point3(10, 0, 0));
    }

    [Fact]
    public void An_arc_inside_the_tolerance_but_off_by_more_than_rounding_is_warned_with_both_radii()
    {
        // Three decimals: rounding explains at most 2 x sqrt 2 x 0.001 mm; 0.01 mm is more, and under the 0.028 mm tolerance.
        var d = Arcs(Check("O1\nG21 G90 G17\nG00 X0 Y0\nG01 F100.\nG02 X20.010 Y0 I10.000 J0\nG02 X0 Y0 I-10.005 J0\nM30"));
        d.Should().ContainSingle().Which.Should().Match<Diagnostic>(x => x.Code == DiagnosticCodes.ArcRoundedOffCircle && x.Severity == Severity.Warning && x.Line == 5);
        d[0].Message.Should().Contain("0.01 mm off").And.Contain("(0.002828 mm)").And.Contain("start radius 10 mm").And.Contain("end radius 10.01 mm");

        // Four decimals of an inch, off by one unit of the last: rounding, no warning.
        Arcs(Check("O1\nG20 G90 G17\nG00 X0 Y0\nG01 F10.\nG02 X2.0001 Y0 I1.0000 J0\nM30")).Should().BeEmpty();
    }

    [Fact]
    public void The_profile_says_the_rule_and_the_older_single_number_still_reads()
    {
        var json = MachineProfile.Default.ToJson();
        json.Should().Contain("\"arcTolerance\": {");
        var back = MachineProfile.Parse(json, "copy").ArcTolerance;
        back.Inch.Should().BeApproximately(2 * 0.001 * Math.Sqrt(2), 1e-12);
        back.Millimetre.Should().BeApproximately(2 * 0.01 * Math.Sqrt(2), 1e-12);
        back.Relative.Should().Be(0.001);
        back.RadiusInch.Should().Be(0.00005);

        var custom = MachineProfile.Parse(json.Replace(json.Substring(json.IndexOf("\"arcTolerance\"", StringComparison.Ordinal), json.IndexOf('}', json.IndexOf("\"arcTolerance\"", StringComparison.Ordinal)) - json.IndexOf("\"arcTolerance\"", StringComparison.Ordinal) + 1), "\"arcTolerance\": { \"mm\": 0.001 }"), "tight");
        custom.ArcTolerance.Millimetre.Should().Be(0.001);
        custom.ArcTolerance.Inch.Should().Be(ArcTolerance.LinuxCnc.Inch, "what the object leaves out is LinuxCNC's");

        MachineProfile.Paper.ArcTolerance.Millimetre.Should().Be(0.002, "the paper's profile keeps its single number");
        MachineProfile.Paper.ArcTolerance.Inch.Should().BeApproximately(0.002 / 25.4, 1e-15, "millimetres whatever the program's units, as before");

        var bad = () => MachineProfile.Parse(json.Replace("\"relative\": 0.001", "\"relative\": -1"), "bad");
        bad.Should().Throw<InvalidDataException>().WithMessage("*arcTolerance.relative must be 0 or more*");
    }

    [Fact]
    public void Grbl_keeps_its_own_rule_in_millimetres()
    {
        var grbl = MachineProfile.Named("grbl")!.ArcTolerance;
        grbl.Refuses(10, 10.006, inch: false).Should().BeFalse("0.006 mm is 0.06 % of 10 mm");
        grbl.Refuses(1, 1.006, inch: false).Should().BeTrue("0.006 mm is 0.6 % of 1 mm (grbl gcode.c: > 0.005 mm and > 0.1 %)");
        grbl.Refuses(1000, 1000.6, inch: false).Should().BeTrue("more than grbl's 0.5 mm");
    }
}
