using System.Text;
using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// Every diagnostic code: a bad block that triggers it (line and column asserted) and a good one that does not, under
/// the default profile (fanuc-mill) unless a case names another.
/// </summary>
public class CheckerDiagnosticTests
{
    private static IReadOnlyList<Diagnostic> Check(string text, string profile = MachineProfile.DefaultName) =>
        new Checker(MachineProfile.Named(profile)!).CheckText(text).Diagnostics;

    private static IReadOnlyList<Diagnostic> CheckBytes(byte[] bytes)
    {
        var list = new List<Diagnostic>();
        new Checker(MachineProfile.Default).Check(new MemoryStream(bytes), "<bytes>", list.Add);
        return list;
    }

    public static DiagnosticCases Bad => new()
    {
        { DiagnosticCodes.IllegalCharacter, "O1\nG01 X1 F100 @", 2, 13 },
        { DiagnosticCodes.MalformedNumber, "O1\nG01 X1.2.3 F100", 2, 5 },
        { DiagnosticCodes.MalformedNumber, "O1\nG01 X- F100", 2, 5 },
        { DiagnosticCodes.UnclosedComment, "O1\nG01 X1 F100 (open", 2, 13 },
        { DiagnosticCodes.UnknownGCode, "O1\nG00 X1\nG05 X2", 3, 1 },
        { DiagnosticCodes.UnknownMCode, "O1\nM50", 2, 1 },
        { DiagnosticCodes.UnknownMCode, "O1\nM06", 2, 1, "paper-24g7m" },
        { DiagnosticCodes.UnknownMCode, "G21\nM6 T1", 2, 1, "grbl" },
        { DiagnosticCodes.NegativeValue, "O1\nG01 X1 F-5", 2, 8 },
        { DiagnosticCodes.NegativeValue, "O1\nS-100 M03", 2, 1 },
        { DiagnosticCodes.ToolOutOfRange, "O1\nT10000", 2, 1 },
        { DiagnosticCodes.ToolOutOfRange, "O1\nT99", 2, 1, "paper-24g7m" },
        { DiagnosticCodes.ToolOutOfRange, "O1\nG00 T1.5", 2, 5 },
        { DiagnosticCodes.DecimalCode, "O1\nG1.5 X1 F100", 2, 1 },
        { DiagnosticCodes.DecimalCode, "O1\nM3.5", 2, 1 },
        { DiagnosticCodes.DecimalCode, "O1\nG91.1", 2, 1, "paper-24g7m" },
        { DiagnosticCodes.ModalGroupConflict, "O1\nG00 G01 X1 F100", 2, 5 },
        { DiagnosticCodes.ModalGroupConflict, "O1\nM03 M05", 2, 5 },
        { DiagnosticCodes.NoFunction, "O1\nN10", 2, 1 },
        { DiagnosticCodes.NoFunction, "O1\n  P5", 2, 3 },
        { DiagnosticCodes.DuplicateWord, "O1\nG00 X1 X2", 2, 8 },
        { DiagnosticCodes.MotionWithoutAxes, "O1\nF100\nG02 R5", 3, 1 },
        { DiagnosticCodes.ArcWithoutCenter, "O1\nF100\nG02 X2 Y0", 3, 1 },
        { DiagnosticCodes.ArcWithoutCenter, "O1\nF100\nG18\nG02 X2 Z0 J1", 4, 1 },
        { DiagnosticCodes.ArcRadiusMismatch, "O1\nF100\nG02 X2 Y0 I1.5 J0", 3, 11 },
        { DiagnosticCodes.ArcRadiusMismatch, "O1\nF100\nG02 X10 Y0 R2", 3, 12 },
        { DiagnosticCodes.FeedMoveWithoutFeed, "O1\nG01 X1", 2, 1 },
        { DiagnosticCodes.FeedMoveWithoutFeed, "O1\nG01 F0\nX1", 3, 1 },
        { DiagnosticCodes.UnsupportedLetter, "O1\nG00 X1 Q5", 2, 8, "paper-24g7m" },
        { DiagnosticCodes.UnsupportedLetter, "G0 X1 A90", 1, 7, "grbl" },
        { DiagnosticCodes.UnsupportedLetter, "O100\nG0 X1", 1, 1, "grbl" },
        { DiagnosticCodes.EmptyProgram, string.Empty, 1, 1 },
        { DiagnosticCodes.EmptyProgram, "(just a comment)\n\n%\n", 3, 1 },
        { DiagnosticCodes.NulByte, "O1\nG00 X1\0\0\0", 2, 7 },
        { DiagnosticCodes.NoProgramNumber, "\nG00 X1", 2, 1 },
        { DiagnosticCodes.NoSequenceNumber, "O1\nN10 G00 X1\nG00 Y1", 3, 1 },
        { DiagnosticCodes.NoSequenceNumber, "O1\nG00 X1\nN20 G00 Y1", 2, 1 },
        { DiagnosticCodes.UnusedWord, "O1\nG00 X1 R5", 2, 8 },
        { DiagnosticCodes.UnusedWord, "O1\nM05 P2", 2, 5 },
        { DiagnosticCodes.LowercaseLetter, "O1\ng00 x1", 2, 1 },
        { DiagnosticCodes.MissingWord, "O1\nG04", 2, 1 },
        { DiagnosticCodes.NestedComment, "O1\nG00 X1 (outer (inner) text)", 2, 15 },
        { DiagnosticCodes.RequiredWordMissing, "O1\nG10 P1 X0 Y0", 2, 1 },
        { DiagnosticCodes.RequiredWordMissing, "O1\nG54.1", 2, 1 },
        { DiagnosticCodes.RequiredWordMissing, "O1\nG98 G81 X1 Y1 R2 F100", 2, 5 },
        { DiagnosticCodes.RequiredWordMissing, "G21\nG10 L20 X0", 2, 1, "grbl" },
        { DiagnosticCodes.ValueNotAllowed, "O1\nG10 L5 P1 X0", 2, 5 },
        { DiagnosticCodes.ValueNotAllowed, "O1\nG54.1 P0", 2, 7 },
        { DiagnosticCodes.ValueNotAllowed, "O1\nG83 X1 Y1 Z-5 R1 Q0 F100", 2, 18 },
        { DiagnosticCodes.ValueNotAllowed, "O1\nG81 X1 Y1 Z-5 R1 K1.5 F100", 2, 18 },
        { DiagnosticCodes.ValueNotAllowed, "G21\nG10 L2 P7 X0", 2, 8, "grbl" },
        { DiagnosticCodes.NoMotionMode, "G21\nX1 Y1", 2, 1, "linuxcnc-mill" },
        { DiagnosticCodes.NoMotionMode, "G0 X0\nG81 X1 Y1 Z-1 R1 F10\nG80\nX2", 4, 1, "linuxcnc-mill" },
        { DiagnosticCodes.NotYetOnController, "O1\nT1 M41\nM41", 2, 4 },
        { DiagnosticCodes.NotYetOnController, "O1\nG00 G41.2 D1 X1", 2, 5 },
        { DiagnosticCodes.TextAfterTapeEnd, "%\nO1\nG00 X1\n%\nG00 X2\n", 4, 1 },
        { DiagnosticCodes.IllegalCharacter, "G0 X1 /Y2", 1, 7, "linuxcnc-mill" },
        { DiagnosticCodes.TooManyWords, "O1\nG01 F100 " + string.Join(" ", Enumerable.Repeat("X1", 255)), 2, 10 + (3 * 254) },
        { DiagnosticCodes.TransformNotRunnable, "O1\nG51 X0 Y0 I2000 J1000\nG02 X1 Y0 I0.5 F100", 3, 1 },
        { DiagnosticCodes.CycleInInverseTime, "O1\nG93 G81 X1 Y1 Z-1 R1 F2", 2, 5 },
        { DiagnosticCodes.RotaryOffset, "O1\nG10 L2 P2 A90.", 2, 11 },
        { DiagnosticCodes.NoCutterRadius, "O1\nG00 G41 D1 X1", 2, 5 },
        { DiagnosticCodes.CompensationNotRunnable, "O1\nG10 L12 P1 R5.\nG00 X0 Y-20.\nG41 D1 G02 X10. Y-10. R10. F100", 4, 8 },
        { DiagnosticCodes.CompensationEntryTooShort, "O1\nG10 L12 P1 R5.\nG00 X0 Y-4.\nG41 D1 G01 X0 Y0 F100", 4, 8 },
        { DiagnosticCodes.CompensationConcaveCorner, "O1\nG10 L12 P1 R5.\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100\nG03 X12. Y-2. I6. J-1.", 5, 1 },
        { DiagnosticCodes.ArcRoundedOffCircle, "O1\nF100\nG02 X20.010 Y0 I10.000 J0", 3, 1 },
        { DiagnosticCodes.DialectG10L20, "O1\nG10 L20 P1 X0 Y0 Z50.\nG54\nG00 X10.", 4, 1 },
        { DiagnosticCodes.DialectDwellUnits, "O1\nG04 P0.5", 2, 5 },
        { DiagnosticCodes.DialectDwellUnits, "G4 P500", 1, 4, "linuxcnc-mill" },
        { DiagnosticCodes.DialectG10L2P0, "O1\nG10 L2 P0 X1.", 2, 8 },
        { DiagnosticCodes.DialectReturn, "O1\nG90 G00 Z10.\nG28 Z0", 3, 1 },
        { DiagnosticCodes.DialectReturn, "G28", 1, 1, "grbl" },
        { DiagnosticCodes.DialectToolChange, "O1\nM06", 2, 1 },
        { DiagnosticCodes.DialectG92AtEnd, "O1\nG00 X10.\nG92 X0\nM30", 4, 1 },
    };

    public static TheoryData<string, string> Good => new()
    {
        { DiagnosticCodes.IllegalCharacter, "O1\nG01 X1 F100 (ok: @ in a comment) ; and here @" },
        { DiagnosticCodes.MalformedNumber, "O1\nG01 X1.23 Y.5 Z5. F+100" },
        { DiagnosticCodes.UnclosedComment, "O1\nG01 X1 F100 (closed)(twice)" },
        { DiagnosticCodes.UnknownGCode, "O1\nG0 X2\nG00 X1" },
        { DiagnosticCodes.UnknownMCode, "O1\nM05\nT1 M06\nM01\nM02" },
        { DiagnosticCodes.NegativeValue, "O1\nG01 X-1 F5\nS100 M03" },
        { DiagnosticCodes.ToolOutOfRange, "O1\nT24\nT9999" },
        { DiagnosticCodes.DecimalCode, "O1\nG1 X1 F100\nM3\nG91.1\nG54.1 P2" },
        { DiagnosticCodes.ModalGroupConflict, "O1\nG00 G17 G90 G21 G54 X1\nM03 M08\nG90 G54 G64 G50 G17 G40 G80 G94 G91.1 G49\nG28 G91 Z0" },
        { DiagnosticCodes.NoFunction, "O1\nN10 M05\nN20 (FACE1)\nN30 (label) (two comments)" },
        { DiagnosticCodes.DuplicateWord, "O1\nG00 X1 Y2" },
        { DiagnosticCodes.MotionWithoutAxes, "O1\nF100\nG02 X2 Y0 R1\nG03 I-1\nG01\nG00" },
        { DiagnosticCodes.ArcWithoutCenter, "O1\nF100\nG02 X2 Y0 I1 J0\nG18\nG03 X0 Z0 I-1" },
        { DiagnosticCodes.ArcRadiusMismatch, "O1\nF100\nG02 X2 Y0 I1 J0\nG03 X0 Y0 R1\nG02 X2 Y0 R-1.0005" },
        { DiagnosticCodes.FeedMoveWithoutFeed, "O1\nG01 X1 F100\nG00 X0" },
        { DiagnosticCodes.UnsupportedLetter, "O1\nG00 X1 Y5 Z2\nG01 A90. F100\nG83 X1 Y1 Z-3 R1 Q0.5 F50\nG80" },
        { DiagnosticCodes.EmptyProgram, "O1\nM05" },
        { DiagnosticCodes.NulByte, "O1\nG00 X1" },
        { DiagnosticCodes.NoProgramNumber, "%\nO1001 (PART)\nG00 X1\n%" },
        { DiagnosticCodes.NoSequenceNumber, "O1\nG00 X1\nG00 Y1" },
        { DiagnosticCodes.UnusedWord, "O1\nG00 X1\nG04 P200" },
        { DiagnosticCodes.LowercaseLetter, "O1\nG00 X1 (lower case in comments is fine)" },
        { DiagnosticCodes.MissingWord, "O1\nG04 P500\nG04 X1.5" },
        { DiagnosticCodes.NestedComment, "O1\nG00 X1 (one) (two)" },
        { DiagnosticCodes.RequiredWordMissing, "O1\nG10 L2 P1 X0 Y0\nG54.1 P1\nG98 G81 X1 Y1 Z-1 R2 F100\nX2\nG80" },
        { DiagnosticCodes.ValueNotAllowed, "O1\nG10 L20 P1 X0\nG54.1 P48\nG83 X1 Y1 Z-5 R1 Q0.2 K2 F100\nG80" },
        { DiagnosticCodes.NoMotionMode, "G21\nG0 X1 Y1\nG81 X1 Y1 Z-1 R1 F10\nG80\nG1 X2 F100" },
        { DiagnosticCodes.NotYetOnController, "O1\nG00 G17 G21 G90 G54 X1\nG01 X2 F100\nM03 S1000\nM08\nM30" },
        { DiagnosticCodes.TextAfterTapeEnd, "%\nO1\nG00 X1\nM30\n%\n\n  \n" },
        { DiagnosticCodes.TooManyWords, "O1\nG01 F100 " + string.Join(" ", Enumerable.Repeat("X1", 254)) },
        { DiagnosticCodes.TransformNotRunnable, "O1\nG51 X0 Y0 P2000\nG02 X1 Y0 I0.5 F100\nG50" },
        { DiagnosticCodes.CycleInInverseTime, "O1\nG94 G81 X1 Y1 Z-1 R1 F100\nG80\nG93 G01 X2 F2\nG94" },
        { DiagnosticCodes.RotaryOffset, "O1\nG10 L2 P2 X1 A0\nG52 A0\nG00 A90.\nG52 X0" },
        { DiagnosticCodes.NoCutterRadius, "O1\nG10 L12 P1 R5.\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100\nG40 X0 Y-20.\nG41 D0 X0 Y0\nG40" },
        { DiagnosticCodes.CompensationNotRunnable, "O1\nG10 L12 P1 R5.\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100\nY10.\nG40 X20. Y-10.\nG02 X30. Y0 R10." },
        { DiagnosticCodes.CompensationEntryTooShort, "O1\nG10 L12 P1 R5.\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100" },
        { DiagnosticCodes.CompensationConcaveCorner, "O1\nG10 L12 P1 R5.\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100\nY10.\nX10.\nY-10." },
        { DiagnosticCodes.ArcRoundedOffCircle, "O1\nG20 F10.\nG02 X2.0002 Y0 I1.0001 J0\nG02 X0.0001 Y0 I-1. J0" },
        { DiagnosticCodes.DialectG10L20, "O1\nG10 L20 P1 X0 Y0 Z50.\nG54.1 P1\nG00 X10." },
        { DiagnosticCodes.DialectDwellUnits, "O1\nG04 P500\nG04 X0.5" },
        { DiagnosticCodes.DialectG10L2P0, "O1\nG10 L2 P1 X1." },
        { DiagnosticCodes.DialectReturn, "O1\nG91 G28 Z0\nG90" },
        { DiagnosticCodes.DialectToolChange, "O1\nT1 M06\nT2\nM06" },
        { DiagnosticCodes.DialectG92AtEnd, "O1\nG00 X10.\nG92 X0\nG92.1\nM30" },
    };

    [Theory]
    [MemberData(nameof(Bad))]
    public void Bad_block_triggers_the_code_at_its_line_and_column(string code, string program, int line, int column, string profile)
    {
        var diags = Check(program, profile);
        diags.Should().Contain(d => d.Code == code && d.Line == line && d.Column == column,
            "{0} expected at {1}:{2}, got: {3}", code, line, column, string.Join(" | ", diags.Select(d => $"{d.Code}@{d.Line}:{d.Column}")));
        diags.First(d => d.Code == code).Severity.Should().Be(code[0] == 'E' ? Severity.Error : Severity.Warning);
    }

    [Theory]
    [MemberData(nameof(Good))]
    public void Good_block_does_not_trigger_the_code(string code, string program)
    {
        var diags = Check(program);
        diags.Should().NotContain(d => d.Code == code, string.Join(" | ", diags.Select(d => $"{d.Code}@{d.Line}:{d.Column} {d.Message}")));
    }

    [Fact]
    public void Every_code_has_a_bad_case_and_a_good_case_and_both_messages()
    {
        var bad = Bad.Select(r => (string)r[0]).ToHashSet();
        var good = Good.Select(r => (string)r[0]).ToHashSet();
        // Byte-level cases below; E127 is the job gate's (PrepareTests), never the checker's.
        var special = new[] { DiagnosticCodes.LineTooLong, DiagnosticCodes.Utf16File, DiagnosticCodes.NotRunnableInJob };
        foreach (var code in DiagnosticCodes.All)
        {
            (bad.Contains(code) || special.Contains(code)).Should().BeTrue($"{code} needs a bad case");
            (good.Contains(code) || special.Contains(code)).Should().BeTrue($"{code} needs a good case");
            DiagnosticText.IsRegistered(code).Should().BeTrue();
            var en = DiagnosticText.Format(System.Globalization.CultureInfo.GetCultureInfo("en"), code, "X", "Y", "Z", "W");
            var zh = DiagnosticText.Format(System.Globalization.CultureInfo.GetCultureInfo("zh-CN"), code, "X", "Y", "Z", "W");
            en.Should().NotBe(zh);
            zh.Should().MatchRegex(@"\p{IsCJKUnifiedIdeographs}");
        }

        DiagnosticCodes.All.Should().OnlyHaveUniqueItems();
    }

    [Fact]
    public void Line_too_long_is_cut_and_reported_and_the_next_line_is_read()
    {
        var big = "O1\nG00 X1 (" + new string('A', GCodeReader.MaxLineLength + 10) + ")\nG00 Y@\n";
        var diags = CheckBytes(Encoding.ASCII.GetBytes(big));
        diags.Should().Contain(d => d.Code == DiagnosticCodes.LineTooLong && d.Line == 2 && d.Column == GCodeReader.MaxLineLength);
        diags.Should().Contain(d => d.Code == DiagnosticCodes.MalformedNumber && d.Line == 3 && d.Column == 5);
        CheckBytes(Encoding.ASCII.GetBytes("O1\nG00 X1 (" + new string('A', 1000) + ")\n")).Should().NotContain(d => d.Code == DiagnosticCodes.LineTooLong);
    }

    [Fact]
    public void Utf16_is_reported_once_and_utf8_bom_is_skipped()
    {
        var utf16 = Encoding.Unicode.GetPreamble().Concat(Encoding.Unicode.GetBytes("O1\nG00 X1\n")).ToArray();
        var d16 = CheckBytes(utf16);
        d16.Should().ContainSingle().Which.Should().Match<Diagnostic>(d => d.Code == DiagnosticCodes.Utf16File && d.Line == 1 && d.Column == 1);

        var utf8 = Encoding.UTF8.GetPreamble().Concat(Encoding.UTF8.GetBytes("O1\nG00 X1 (中文注释)\n")).ToArray();
        CheckBytes(utf8).Should().BeEmpty();
    }

    [Fact]
    public void Binary_input_says_binary_once_not_per_byte()
    {
        var rnd = new Random(7);
        var bytes = new byte[20000];
        rnd.NextBytes(bytes);
        bytes[5] = 0;
        bytes[9000] = 0;
        var diags = CheckBytes(bytes);
        diags.Count(d => d.Code == DiagnosticCodes.NulByte).Should().Be(1);
        diags.Should().Contain(d => d.Severity == Severity.Error);
    }

    [Fact]
    public void Cr_only_program_checks_clean_with_right_line_numbers()
    {
        var demo = File.ReadAllText(RepoRoot.DemoProgram).Replace("\r\n", "\n");
        var crOnly = demo.Replace('\n', '\r');
        var (summary, diags) = new Checker(MachineProfile.Default).CheckText(crOnly);
        diags.Should().BeEmpty();
        summary.Lines.Should().Be(demo.TrimEnd('\n').Split('\n').Length);

        var lines = demo.Split('\n');
        lines[9] = "N90 F-1200.";
        var (_, bad) = new Checker(MachineProfile.Default).CheckText(string.Join('\r', lines));
        bad.Should().ContainSingle().Which.Should().Match<Diagnostic>(d => d.Code == DiagnosticCodes.NegativeValue && d.Line == 10 && d.Column == 5);
    }

    [Fact]
    public void Demo_program_checks_clean_under_the_default_profile()
    {
        var (summary, diags) = new Checker(MachineProfile.Default).CheckText(File.ReadAllText(RepoRoot.DemoProgram));
        diags.Should().BeEmpty();
        summary.Blocks.Should().BeGreaterThan(3000);
        summary.EstimatedSeconds.Should().BeGreaterThan(0);
    }

    [Fact]
    public void Reports_every_problem_not_only_the_first()
    {
        var diags = Check("O1\nG00 G01 X1 X2 Q3 @\nG05\nM99\n", "paper-24g7m");
        diags.Select(d => d.Code).Should().Contain(new[]
        {
            DiagnosticCodes.ModalGroupConflict, DiagnosticCodes.DuplicateWord, DiagnosticCodes.UnsupportedLetter,
            DiagnosticCodes.IllegalCharacter, DiagnosticCodes.UnknownGCode, DiagnosticCodes.UnknownMCode,
        });
        diags.Select(d => d.Line).Should().BeInAscendingOrder();
    }

    [Fact]
    public void Messages_follow_the_culture()
    {
        var zh = DiagnosticText.Format(System.Globalization.CultureInfo.GetCultureInfo("zh-CN"), DiagnosticCodes.ModalGroupConflict, "G", "0", "1", "GA");
        zh.Should().Contain("同一组模态代码重用");
        var en = DiagnosticText.Format(System.Globalization.CultureInfo.GetCultureInfo("en"), DiagnosticCodes.ModalGroupConflict, "G", "0", "1", "GA");
        en.Should().Be("G0 and G1 are both in modal group GA: only one code of a group per block");
    }
}

/// <summary>The diagnostic language belongs to one operation, not to the process.</summary>
public class DiagnosticCultureTests
{
    [Fact]
    public async Task A_check_in_Chinese_does_not_change_the_messages_of_a_check_running_meanwhile()
    {
        var inChinese = new TaskCompletionSource();
        var englishChecked = new TaskCompletionSource();
        var chinese = Task.Run(async () =>
        {
            DiagnosticText.Culture = System.Globalization.CultureInfo.GetCultureInfo("zh-CN");
            inChinese.SetResult();
            await englishChecked.Task;
            return new Checker(MachineProfile.Default).CheckText("O1\nG05 X1\n").Diagnostics[0].Message;
        });
        await inChinese.Task;
        var english = await Task.Run(() =>
        {
            DiagnosticText.Culture = System.Globalization.CultureInfo.GetCultureInfo("en");
            return new Checker(MachineProfile.Default).CheckText("O1\nG05 X1\n").Diagnostics[0].Message;
        });
        englishChecked.SetResult();
        english.Should().StartWith("unknown G code G05");
        (await chinese).Should().Contain("G05").And.NotStartWith("unknown", "the Chinese check keeps its own language");
        DiagnosticText.Culture.Should().NotBeSameAs(System.Globalization.CultureInfo.GetCultureInfo("zh-CN"), "this test's own flow never set Chinese");
    }
}

/// <summary>Cases of a diagnostic: code, program, line, column and the profile it is checked under (the default when not given).</summary>
public sealed class DiagnosticCases : TheoryData<string, string, int, int, string>
{
    /// <summary>A case under the default profile.</summary>
    public void Add(string code, string program, int line, int column) => Add(code, program, line, column, MachineProfile.DefaultName);
}
