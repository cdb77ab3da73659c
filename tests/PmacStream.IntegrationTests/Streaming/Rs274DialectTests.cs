using PmacStream.GCode;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 27 item 5: the gSender program that zeroes with <c>G10 L20 P1</c> then selects <c>G54</c>. rs274 runs it with
/// LinuxCNC's meaning, which linuxcnc-mill shares (every block end on rs274's moves); under fanuc-mill the same text
/// means the extended offset G54.1 P1, the moves end elsewhere, and the check warns (W009).
/// </summary>
public partial class Rs274ComparisonTests
{
    private const string GSenderZeroing = "G21 G90 G17 G94\nG0 X5 Y5 Z0\nG10 L20 P1 X0 Y0 Z50\nG54\nG0 X10 Y10 Z50\nG1 X20 F500\nG0 Z60\nM2\n";

    [SkippableFact]
    public void Rs274_runs_a_gSender_G10_L20_zeroing_as_linuxcnc_mill_does_and_fanuc_mill_warns_about_it()
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274-dialect");
        var path = Path.Combine(temp.Path, "gsender.nc");
        File.WriteAllText(path, GSenderZeroing);

        var linuxcnc = Machine();
        new Checker(linuxcnc).CheckText(GSenderZeroing).Diagnostics.Should().NotContain(d => d.Code == DiagnosticCodes.DialectG10L20);
        var (accepted, why) = Compare(rs274, path, linuxcnc, temp.Path);
        accepted.Should().BeTrue(why);

        var fanuc = MachineProfile.Default;
        new Checker(fanuc).CheckText(GSenderZeroing).Diagnostics.Should().Contain(d => d.Code == DiagnosticCodes.DialectG10L20 && d.Line == 5);
        var wrong = () => Compare(rs274, path, fanuc, temp.Path);
        wrong.Should().Throw<Exception>().WithMessage("*rs274 never reaches*", "under FANUC's meaning the moves run 50 mm higher than rs274's");
    }
}
