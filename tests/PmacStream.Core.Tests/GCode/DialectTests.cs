using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// Issue 16's false errors and dialect facts: what real CAM programs write checks clean under the default profile
/// (fanuc-mill), and the lexer/checker read labels, tape marks, program numbers and block skip as FANUC documents.
/// </summary>
public class DialectTests
{
    private static (CheckSummary Summary, IReadOnlyList<Diagnostic> Diagnostics) Check(string program, string profile = MachineProfile.DefaultName) =>
        new Checker(MachineProfile.Named(profile)!).CheckText(program);

    private static List<DecodedBlock> Run(string program, string profile = MachineProfile.DefaultName, bool blockDelete = false)
    {
        var interp = new Interpreter(MachineProfile.Named(profile)!) { BlockDeleteEnabled = blockDelete };
        var n = 0;
        return program.Split('\n').Select(l => interp.Step(GCodeReader.LexLine(l, ++n))).OfType<DecodedBlock>().ToList();
    }

    private static string Errors(IReadOnlyList<Diagnostic> diags) =>
        string.Join(" | ", diags.Where(d => d.Severity == Severity.Error).Select(d => $"{d.Code}@{d.Line}:{d.Column} {d.Message}"));

    [Fact]
    public void A_sequence_number_with_only_a_comment_is_a_label_under_every_profile()
    {
        foreach (var profile in MachineProfile.BuiltInNames.Where(p => p != "grbl"))
        {
            var (summary, diags) = Check("O1\nN10 (Face1)\nG00 X1\nG00 Y1\nM30\n", profile);
            Errors(diags).Should().BeEmpty(profile);
            summary.Blocks.Should().Be(3, "a label is not a block");
            diags.Should().NotContain(d => d.Code == DiagnosticCodes.NoSequenceNumber, "labels do not make the program a numbered one");
        }

        Check("G21\nN10 (Face1)\nG0 X1\n", "grbl").Summary.Errors.Should().Be(0);
        Check("O1\nN10\n").Diagnostics.Should().Contain(d => d.Code == DiagnosticCodes.NoFunction && d.Line == 2, "a bare N still has no function");
    }

    [Fact]
    public void Ten_modal_groups_in_one_block_are_not_a_conflict_and_all_ten_are_kept()
    {
        const string line = "G90 G54 G64 G50 G17 G40 G80 G94 G91.1 G49";
        Errors(Check("O1\n" + line + "\nM30").Diagnostics).Should().BeEmpty();
        var state = Run(line)[0].Modal;
        state.G.Where(v => v.HasValue).Select(v => v!.Value).Should().Contain([90, 54, 64, 50, 17, 40, 80, 94, 91.1, 49]);
        Check("O1\nG00 G01 X1 F100").Diagnostics.Should().Contain(d => d.Code == DiagnosticCodes.ModalGroupConflict && d.Message.Contains("group 01"));
    }

    /// <summary>The ordinary codes that made real programs fail under paper-24g7m's 24 G + 7 M set (issue 16's list).</summary>
    public static TheoryData<string, string> RealCodes => new()
    {
        { "M06 and M6", "T1 M06\nT2 M6" },
        { "G94", "G90 G94 G17 G49 G40 G80" },
        { "G80", "G80" },
        { "M02", "G00 X1\nM02" },
        { "M01", "M01" },
        { "G53", "G53 G00 Z0.\nG53 Y0." },
        { "G28 G91 Z0", "G28 G91 Z0.\nG90" },
        { "G10 L2 / L20", "G10 L2 P1 X0 Y0 Z0\nG10 L20 P1 X0 Y0" },
        { "G98 G81 G73 G83 with Q", "G98 G81 X1 Y1 Z-1 R1 F100\nG73 X2 Z-2 R1 Q0.5\nG83 X3 Z-3 R1 Q.25\nG99 X4\nG80" },
        { "G64", "G64" },
        { "G30", "G30\nG30 P2 Z0" },
        { "G50", "G50" },
        { "G91.1", "G91.1" },
        { "G41.2", "G41.2 D1 G01 X1 F100\nG40 X2" },
        { "rotary A words", "G00 A0\nG01 X1 A90. F500\nA180.\nG93 G01 A270. F20\nG94" },
        { "Haas codes", "M31\nG187 P2 E0.01\nM10\nM11\nM33\nG103 P1\nG187" },
        { "FANUC smoothing and extended offsets", "G05.1 Q1 R5\nG54.1 P3\nG05.1 Q0" },
        { "tool length and cutter compensation", "G43 H1 Z50.\nG10 L12 P1 R3.\nG41 D1 G01 X10 F200\nG40 G01 X20\nG49" },
    };

    [Theory]
    [MemberData(nameof(RealCodes))]
    public void Codes_real_posts_write_check_without_errors_under_the_default_profile(string what, string lines)
    {
        var (_, diags) = Check("%\nO1001 (TEST)\nG21 G17 G90\nS1000 M03\n" + lines + "\nM30\n%\n");
        Errors(diags).Should().BeEmpty(what);
    }

    [Fact]
    public void Codes_the_controller_cannot_run_yet_are_warned_once_each_at_their_first_use()
    {
        var (summary, diags) = Check("O1\nT1 M41\nG43 H1 Z10\nT2 M41\nG41.2 D1 X10 F100\n");
        diags.Where(d => d.Code == DiagnosticCodes.NotYetOnController).Select(d => (d.Line, d.Message[..5])).Should().Equal(
            (2, "M41 ("), (5, "G41.2"));
        summary.NotYetCodes.Should().Equal(new Dictionary<string, int> { ["M41"] = 2, ["G41.2"] = 5 });
        Check("O1\nG00 X1\nG01 X2 F100\nM30").Summary.NotYetCodes.Should().BeEmpty();
    }

    [Fact]
    public void Nested_parentheses_stay_an_error_and_the_comment_ends_at_its_matching_parenthesis()
    {
        var (_, diags) = Check("O1\nG00 X1 (a (b) c) Y2\n");
        diags.Should().ContainSingle().Which.Code.Should().Be(DiagnosticCodes.NestedComment);
        var block = GCodeReader.LexLine("G00 X1 (a (b) c) Y2");
        block.Words.Select(w => w.Letter).Should().Equal('G', 'X', 'Y');
        Check("O1\nG00 X1 (a)(b) Y2\n").Diagnostics.Should().BeEmpty();
    }

    [Fact]
    public void A_percent_line_after_the_first_block_ends_the_tape_and_what_follows_is_ignored()
    {
        var (summary, diags) = Check("%\nO1\nG00 X1\nM30\n%\nG05 (not G-code: a second program, notes)\n\n");
        diags.Select(d => d.Code).Should().Equal(DiagnosticCodes.TextAfterTapeEnd);
        diags[0].Line.Should().Be(5);
        summary.Blocks.Should().Be(2);
        summary.Lines.Should().Be(7, "the file's lines are still counted");
        Check("%\nO1\nG00 X1\nM30\n%\n\n").Diagnostics.Should().BeEmpty("blank lines after the end are no text");
        Check("(header)\n%\nO1\nG00 X1\nM30\n%").Summary.Blocks.Should().Be(2, "a % before any block opens the tape");
    }

    [Fact]
    public void A_leading_colon_is_the_program_number_and_a_colon_elsewhere_is_illegal()
    {
        GCodeReader.LexLine(":1234 (PART)").ProgramNumber.Should().Be(1234);
        Check(":1234\nG00 X1\n").Diagnostics.Should().BeEmpty();
        Check("O1\nG00 X1 :5\n").Diagnostics.Should().ContainSingle().Which.Should().Match<Diagnostic>(d => d.Code == DiagnosticCodes.IllegalCharacter && d.Column == 8);
    }

    [Fact]
    public void Block_skip_at_the_start_and_inside_a_block_follows_the_profile()
    {
        const string program = "G00 X0 Y0\n/G00 X5\nG00 X1 /Y9\n";
        var on = Run(program, blockDelete: true);
        on.Should().HaveCount(2, "the /-line is skipped");
        on[1].End.Should().Be(new Point3(1, 0, 0), "FANUC skips the rest of the block after a / inside it");
        var off = Run(program, blockDelete: false);
        off.Should().HaveCount(3);
        off[2].End.Should().Be(new Point3(1, 9, 0));
        Check("O1\n" + program).Diagnostics.Should().BeEmpty();
        Check(program, "linuxcnc-mill").Diagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.IllegalCharacter && d.Line == 3 && d.Column == 8);
    }

    [Theory]
    [InlineData("fanuc-mill", "G04 P1500", 1.5)]
    [InlineData("linuxcnc-mill", "G4 P1.5", 1.5)]
    [InlineData("grbl", "G4 P1.5", 1.5)]
    [InlineData("paper-24g7m", "G04 X1.5", 1.5)]
    public void Dwell_p_is_in_the_dialects_unit(string profile, string line, double seconds)
    {
        Run(line, profile).Single().DurationSeconds.Should().Be(seconds);
    }

    [Fact]
    public void Address_words_are_checked_where_their_code_uses_them()
    {
        var (_, diags) = Check("O1\nG00 X1 Q5\nG83 X1 Y1 Z-5 R1 Q2 F100\nX2 Q1\nG80\nM98 P1000 L2\nG10 L2 P1 X0\nM19 R90.\n");
        diags.Where(d => d.Code == DiagnosticCodes.UnusedWord).Select(d => d.Line).Should().Equal(2);
        Errors(diags).Should().BeEmpty();
        Check("O1\nG81 X1 Y1 Z-1 R1 K-1 F100\n").Diagnostics.Should().Contain(d => d.Code == DiagnosticCodes.ValueNotAllowed);
        Check("O1\nG65 P9810 X1 Y2 Z3 F100\n").Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty("macro arguments take any letter");
    }
}
