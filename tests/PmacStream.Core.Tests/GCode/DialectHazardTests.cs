using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// Issue 27 item 5: a code that means different things in FANUC/Haas, LinuxCNC and grbl, used the other dialect's way,
/// is warned (W009-W014) with both meanings named; the block still runs with the profile's meaning.
/// </summary>
public class DialectHazardTests
{
    private static IReadOnlyList<Diagnostic> Check(string text, string profile) =>
        new Checker(MachineProfile.Named(profile)!).CheckText(text).Diagnostics;

    private static Point3 LastEnd(string text, string profile)
    {
        // Where the last block left the machine: the interpreter's position after the program.
        var interp = new Interpreter(MachineProfile.Named(profile)!);
        using var reader = new GCodeReader(new MemoryStream(System.Text.Encoding.ASCII.GetBytes(text)));
        while (reader.Read())
        {
            interp.Execute(reader.Current);
        }

        return interp.Position;
    }

    // What gSender writes to zero the work offset at the tool (issue 27), then a move.
    private const string GSender = "G21 G90\nG0 X5 Y5 Z0\nG10 L20 P1 X0 Y0 Z50\nG54\nG0 X10 Y10 Z50\nM30\n";

    [Fact]
    public void A_gSender_G10_L20_then_G54_under_fanuc_mill_is_warned_with_both_meanings()
    {
        var w = Check(GSender, "fanuc-mill").Where(d => d.Code == DiagnosticCodes.DialectG10L20).ToList();
        w.Should().ContainSingle().Which.Line.Should().Be(5, "the first move after it, in G54, not G54.1 P1");
        w[0].Message.Should().Contain("G10 L20 P1 at line 3").And.Contain("G54.1 P1").And.Contain("grbl and LinuxCNC").And.Contain("Z50");
        Check(GSender, "linuxcnc-mill").Should().NotContain(d => d.Code == DiagnosticCodes.DialectG10L20, "LinuxCNC's meaning is the program's");
        Check(GSender, "grbl").Should().NotContain(d => d.Code == DiagnosticCodes.DialectG10L20);

        // The hazard is real: from Z0, "here reads Z50" makes G0 Z50 go nowhere; FANUC's meaning goes 50 mm up.
        (LastEnd(GSender, "fanuc-mill").Z - LastEnd(GSender, "linuxcnc-mill").Z).Should().BeApproximately(50, 1e-9);
    }

    [Fact]
    public void A_FANUC_program_that_selects_the_extended_offset_it_set_is_not_warned()
    {
        Check("O1\nG10 L20 P1 X0 Y0 Z50.\nG10 L20 P2 X1. Y0 Z0\nG54.1 P1\nG00 X10.\nG54.1 P2\nX1.\nM30\n", "fanuc-mill")
            .Should().NotContain(d => d.Code == DiagnosticCodes.DialectG10L20);
    }

    [Theory]
    [InlineData("fanuc-mill", "G04 P0.5", true)]       // half a millisecond: written in seconds
    [InlineData("fanuc-mill", "G04 P500", false)]
    [InlineData("linuxcnc-mill", "G4 P500", true)]     // 500 s: written in milliseconds
    [InlineData("linuxcnc-mill", "G4 P0.5", false)]
    [InlineData("grbl", "G4 P1000", true)]
    public void A_dwell_whose_P_looks_written_in_the_other_unit_is_warned(string profile, string dwell, bool warned)
    {
        var d = Check($"G21\n{dwell}\nM30\n", profile).Where(x => x.Code == DiagnosticCodes.DialectDwellUnits).ToList();
        d.Should().HaveCount(warned ? 1 : 0);
        if (warned)
        {
            d[0].Message.Should().Contain("milliseconds").And.Contain("seconds");
        }
    }

    [Theory]
    [InlineData("fanuc-mill", "FANUC meaning")]
    [InlineData("linuxcnc-mill", "LinuxCNC/grbl meaning")]
    public void G10_L2_P0_names_both_meanings_and_the_one_the_profile_takes(string profile, string taken)
    {
        var d = Check("G21 G90 G55\nG10 L2 P0 X1 Y2\nM30\n", profile).Single(x => x.Code == DiagnosticCodes.DialectG10L2P0);
        d.Message.Should().Contain("external work offset").And.Contain(taken);
        if (profile == "linuxcnc-mill")
        {
            d.Message.Should().Contain("(G55)", "the offset in force");
        }
    }

    [Fact]
    public void G28_without_axes_or_through_a_work_point_in_G90_is_warned()
    {
        Check("G21 G90\nG0 X1 Y1 Z5\nG28\nM2\n", "linuxcnc-mill").Should().Contain(d => d.Code == DiagnosticCodes.DialectReturn && d.Line == 3 && d.Message.Contains("every axis"));
        var through = Check("O1\nG21 G90\nG00 X1. Y1. Z25.\nG28 Z0\nM30\n", "fanuc-mill").Where(d => d.Code == DiagnosticCodes.DialectReturn).ToList();
        through.Should().ContainSingle().Which.Message.Should().Contain("intermediate point Z0").And.Contain("G91 G28 Z0");
        Check("O1\nG21 G90\nG00 X1. Y1. Z25.\nG91 G28 Z0\nG90\nM30\n", "fanuc-mill").Should().NotContain(d => d.Code == DiagnosticCodes.DialectReturn);
        Check("O1\nG21 G90\nG00 X1. Y1. Z0\nG28 Z0\nM30\n", "fanuc-mill").Should().NotContain(d => d.Code == DiagnosticCodes.DialectReturn, "the intermediate point is where the tool is");
    }

    [Fact]
    public void M06_with_no_T_since_the_last_change_is_warned_once_per_change()
    {
        var d = Check("O1\nT1 M06\nG00 X1.\nM06\nT3\nM06\nM30\n", "fanuc-mill").Where(x => x.Code == DiagnosticCodes.DialectToolChange).ToList();
        d.Should().ContainSingle().Which.Line.Should().Be(4);
        d[0].Message.Should().Contain("T1");
        Check("G21\nM6 T2\nT3\nM6\nM2\n", "linuxcnc-mill").Should().NotContain(x => x.Code == DiagnosticCodes.DialectToolChange);
    }

    [Fact]
    public void A_G92_shift_left_at_program_end_is_warned()
    {
        var d = Check("G21 G90\nG0 X10 Y0 Z5\nG92 X0\nG0 X1\nM2\n", "linuxcnc-mill").Single(x => x.Code == DiagnosticCodes.DialectG92AtEnd);
        d.Line.Should().Be(5);
        d.Message.Should().Contain("X10").And.Contain("G92.1");
        Check("G21 G90\nG0 X10 Y0 Z5\nG92 X0\nG92.1\nM2\n", "linuxcnc-mill").Should().NotContain(x => x.Code == DiagnosticCodes.DialectG92AtEnd);
    }
}
