using PmacStream.GCode;
using PmacStream.GCode.Expansion;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// Issue 27 items 1 and 2: FANUC/Haas subprograms and Custom Macro B and LinuxCNC o-words expanded on the host into
/// flat lines, each mapped back to its file, line, call and iteration; and each refusal, a clear error.
/// </summary>
public sealed class ExpansionTests : IDisposable
{
    private readonly TestFolder _dir = new("expand");

    public void Dispose() => _dir.Dispose();

    private string Write(string name, string text)
    {
        var path = Path.Combine(_dir.Path, name);
        File.WriteAllText(path, text.Replace("\r\n", "\n"));
        return path;
    }

    private static (List<string> Lines, MacroExpander Expander) Expand(string path, ExpansionOptions options)
    {
        var e = new MacroExpander(path, options);
        using var s = new ExpandedStream(e);
        using var r = new StreamReader(s);
        var lines = new List<string>();
        while (r.ReadLine() is { } l)
        {
            lines.Add(l);
        }

        return (lines, e);
    }

    private static readonly ExpansionOptions Fanuc = new() { Dialect = MacroDialect.Fanuc };
    private static readonly ExpansionOptions Ngc = new() { Dialect = MacroDialect.LinuxCnc };

    private static List<string> Blocks(List<string> lines) =>
        lines.Where(l => l.Length > 0 && !l.StartsWith('%') && !l.StartsWith('(') && !l.StartsWith('O')).ToList();

    [Fact]
    public void Fanuc_subprograms_macro_arguments_loops_and_goto_expand_in_order_with_their_values()
    {
        var path = Write("main.nc", """
            %
            O0001 (MAIN)
            G21 G90 G17 G54
            #100 = 0
            M98 P1002 L2
            G65 P9100 A10. B-2.5 Z[3*2]
            #1 = 0
            WHILE [#1 LT 3] DO1
            G01 X[#1*2+1] Y[SIN[30]*4] F500
            #1 = #1 + 1
            END1
            IF [#100 EQ 2] GOTO 50
            G00 X99
            N50 G00 Z20
            M30
            %
            O1002 (SUB)
            G91 G01 X5. F300
            G90
            #100 = #100 + 1
            M99
            %
            O9100 (MACRO)
            G01 X#1 Y#2 F200
            G00 Z#26
            IF [#3 EQ #0] THEN #30 = 1
            M99
            %
            """);
        var (lines, e) = Expand(path, Fanuc);
        e.Error.Should().BeNull();
        Blocks(lines).Should().Equal(
            "G21 G90 G17 G54", "G91 G01 X5. F300", "G90", "G91 G01 X5. F300", "G90", "G1 X10 Y-2.5 F200", "G0 Z6",
            "G1 X1 Y2 F500", "G1 X3 Y2 F500", "G1 X5 Y2 F500", "N50 G00 Z20", "M30");
        var map = e.Map;
        var second = lines.FindIndex(4, l => l.StartsWith("G91", StringComparison.Ordinal)) + 1;
        map.Describe(second).Should().Be("O1002 line 18, call 2 of 2 from line 5");
        var third = lines.FindIndex(l => l == "G1 X5 Y2 F500") + 1;
        map.Describe(third).Should().Be("line 9, iteration 3");
        map.Find(third)!.Value.Line.Should().Be(9);
    }

    [Fact]
    public void Macro_functions_and_operators_compute_as_fanuc_does()
    {
        var path = Write("f.nc", """
            G21 G90
            #1 = ATAN[1]/[1]
            #2 = SQRT[16] + ABS[-2] * 2
            #3 = ROUND[2.5] + FIX[-1.5] + FUP[1.2]
            #4 = 7 MOD 3
            #5 = COS[60] + TAN[45] + EXP[0] + LN[1]
            #6 = [1 + 2] * 3 - 4 / 2
            #7 = #10 + 1
            G01 X#1 Y#2 Z#3 A#4 B#5 C#6 F#7
            G00 X#10
            M30
            """);
        var (lines, e) = Expand(path, Fanuc);
        e.Error.Should().BeNull();
        // ROUND 2.5 -> 3, FIX -1.5 -> -2, FUP 1.2 -> 2; a vacant #10 is 0 in arithmetic, and leaves its word out.
        Blocks(lines).Should().Equal("G21 G90", "G1 X45 Y8 Z3 A1 B2.5 C7 F1", "G0", "M30");
    }

    [Fact]
    public void A_subprogram_in_the_program_folder_is_found_and_an_error_in_it_names_its_file_and_line()
    {
        Write("O1002.nc", "O1002\nG91 G01 X1. F100\nG90\nM99\n");
        Write("1003.nc", "O1003\nG01 X[1/#33] F100\nM99\n");
        var path = Write("main.nc", "O0001\nG21 G90\nM98 P1002 L2\nM98 P1003\nM30\n");
        var (lines, e) = Expand(path, Fanuc);
        Blocks(lines).Should().Equal("G21 G90", "G91 G01 X1. F100", "G90", "G91 G01 X1. F100", "G90");
        e.Map.Describe(5).Should().Be("O1002 line 2, call 2 of 2 from line 3");
        e.Error.Should().NotBeNull();
        e.Error!.Code.Should().Be(ExpansionCodes.Value);
        e.Error.Format().Should().Contain("1003.nc:2:").And.Contain("error E158: division by zero").And.Contain("call 1 of 1 from line 4");
        e.Error.MainLine.Should().Be(4);
    }

    [Fact]
    public void Haas_m97_calls_a_local_subprogram_and_m99_p_returns_to_a_label()
    {
        var path = Write("haas.nc", """
            O0002
            G21 G90
            M97 P100 L2
            M98 P1002
            G00 X1
            N20 G00 X2
            M30
            N100 G01 X5 F100
            M99
            O1002
            G00 Y7
            M99 P20
            """);
        var (lines, e) = Expand(path, Fanuc);
        e.Error.Should().BeNull();
        Blocks(lines).Should().Equal("G21 G90", "N100 G01 X5 F100", "N100 G01 X5 F100", "G00 Y7", "N20 G00 X2", "M30");
    }

    [Fact]
    public void Linuxcnc_o_words_expand_subs_loops_branches_break_and_continue()
    {
        var path = Write("o.ngc", """
            G21 G90 G17
            o<square> sub
              G1 X[#1] Y0 F500
              G1 Y[#1]
            o<square> endsub [#1 * 2]
            #<size> = 10
            #2 = 0
            o100 while [#2 LT 3]
              o<square> call [#<size> + #2*5]
              #2 = [#2 + 1]
            o100 endwhile
            G0 Z[#<_value>]
            o200 repeat [2]
              G0 Z[5 + #2]
            o200 endrepeat
            o300 if [#2 EQ 4]
              G0 X1
            o300 elseif [#2 EQ 3]
              G0 X2
            o300 else
              G0 X3
            o300 endif
            #3 = 0
            o400 do
              #3 = [#3 + 1]
              o500 if [#3 EQ 2]
                o400 continue
              o500 endif
              o600 if [#3 GT 3]
                o400 break
              o600 endif
              G0 Y[#3]
            o400 while [#3 LT 10]
            M2
            """);
        var (lines, e) = Expand(path, Ngc);
        e.Error.Should().BeNull();
        Blocks(lines.Select(l => l.Trim()).ToList()).Should().Equal(
            "G21 G90 G17", "G1 X10 Y0 F500", "G1 Y10", "G1 X15 Y0 F500", "G1 Y15", "G1 X20 Y0 F500", "G1 Y20",
            "G0 Z40", "G0 Z8", "G0 Z8", "G0 X2", "G0 Y1", "G0 Y3", "M2");
        var fifth = lines.FindIndex(l => l.Trim() == "G1 Y15") + 1;
        e.Map.Describe(fifth).Should().Be("o<square> line 4, call 1 of 1 from line 9");
    }

    [Fact]
    public void A_linuxcnc_subroutine_file_on_the_search_path_takes_its_parameters()
    {
        var lib = Directory.CreateDirectory(Path.Combine(_dir.Path, "subs")).FullName;
        File.WriteAllText(Path.Combine(lib, "pocket.ngc"), "o<pocket> sub\n#<depth> = #2\nG1 X#1 Z[-#<depth>] F100\no<pocket> endsub\nM2\n");
        var path = Write("m.ngc", "G21 G90\n#<_safe> = 5\no<pocket> call [3] [1.5]\nG0 Z#<_safe>\nM2\n");
        var (lines, e) = Expand(path, Ngc with { ProgramFolders = [lib] });
        e.Error.Should().BeNull();
        Blocks(lines).Should().Equal("G21 G90", "G1 X3 Z-1.5 F100", "G0 Z5", "M2");
        e.Map.Files.Should().HaveCount(2);
        e.Map.Describe(2).Should().Be("o<pocket> line 3, call 1 of 1 from line 3");
    }

    private List<Diagnostic> Check(string name, string text, string profile = "fanuc-mill", ExpansionOptions? options = null)
    {
        var path = Write(name, text);
        var list = new List<Diagnostic>();
        new Checker(MachineProfile.Named(profile)!) { MacroExpansion = options }.CheckFile(path, list.Add);
        return list;
    }

    [Fact]
    public void Reading_a_probe_result_is_refused_at_check_naming_the_variable()
    {
        var d = Check("probe.nc", "O0001\nG21 G90\nG31 Z-10 F100\n#1 = #5063\nG00 Z#1\nM30\n");
        d.Should().ContainSingle(x => x.Code == ExpansionCodes.MachineOnly)
            .Which.Should().Match<Diagnostic>(x => x.Line == 4 && x.Message.Contains("#5063") && x.Message.Contains("probe result"));
        Check("probe.ngc", "G21 G90\nG38.2 Z-10 F100\nG0 Z[#5063 + 1]\nM2\n", "linuxcnc-mill")
            .Should().Contain(x => x.Code == ExpansionCodes.MachineOnly && x.Line == 3 && x.Message.Contains("#5063"));
        Check("input.nc", "O0001\nG21\nIF [#1004 EQ 1] GOTO 10\nN10 M30\n")
            .Should().Contain(x => x.Code == ExpansionCodes.MachineOnly && x.Message.Contains("#1004") && x.Message.Contains("input"));
    }

    [Fact]
    public void An_endless_loop_is_refused_at_the_loop_limit_not_run()
    {
        var d = Check("loop.nc", "O0001\nG21 G90\n#1 = 0\nWHILE [1 EQ 1] DO1\n#1 = #1 + 1\nEND1\nM30\n");
        d.Should().ContainSingle(x => x.Code == ExpansionCodes.LoopLimit).Which.Line.Should().Be(4);
        Check("goto.nc", "O0001\nG21\nN10 #1 = #1 + 1\nGOTO 10\nM30\n", options: new ExpansionOptions { MaxLoopIterations = 1000 })
            .Should().ContainSingle(x => x.Code == ExpansionCodes.LoopLimit).Which.Line.Should().Be(4);
        Check("rec.nc", "O0001\nG21\nM98 P1002\nM30\nO1002\nM98 P1002\nM99\n")
            .Should().ContainSingle(x => x.Code == ExpansionCodes.DepthLimit).Which.Message.Should().Contain("deeper than 32");
    }

    [Fact]
    public void A_too_large_expansion_is_refused_at_the_size_limit()
    {
        var d = Check("big.nc", "O0001\nG21 G90 G01 F100\n#1 = 0\nWHILE [#1 LT 5000] DO1\nX#1\n#1 = #1 + 1\nEND1\nM30\n",
            options: new ExpansionOptions { MaxExpandedLines = 1000 });
        d.Should().ContainSingle(x => x.Code == ExpansionCodes.SizeLimit).Which.Should().Match<Diagnostic>(x => x.Line == 5 && x.Message.Contains("1000 lines"));
    }

    [Fact]
    public void Alarm_3000_is_refused_at_check_with_its_text_and_3006_is_a_program_stop()
    {
        var d = Check("alarm.nc", "O0001\nG21\nIF [#1 NE #0] GOTO 10\n#3000 = 1 (TOOL NOT SET)\nN10 M30\n");
        d.Should().ContainSingle(x => x.Code == ExpansionCodes.Alarm).Which.Should().Match<Diagnostic>(x => x.Line == 4 && x.Message.Contains("TOOL NOT SET"));

        var path = Write("stop.nc", "O0001\nG21\n#3006 = 1 (TURN PART)\nG00 X1\nM30\n");
        var (lines, e) = Expand(path, Fanuc);
        e.Error.Should().BeNull();
        lines.Should().Contain("M00 (TURN PART)");
    }

    [Fact]
    public void Persistent_variables_are_kept_for_the_machine_between_programs()
    {
        var file = Path.Combine(_dir.Path, "machine.vars");
        var first = Write("a.nc", "O0001\nG21\n#500 = [#500 + 1]\n#501 = 2.5\nM30\n");
        var (_, e1) = Expand(first, Fanuc with { PersistentVariablesFile = file });
        e1.SavePersistentVariables();
        var (_, e2) = Expand(first, Fanuc with { PersistentVariablesFile = file });
        e2.SavePersistentVariables();
        var second = Write("b.nc", "O0002\nG21\nG00 X#500 Y#501 Z#100\nM30\n");
        Blocks(Expand(second, Fanuc with { PersistentVariablesFile = file }).Lines).Should().Equal("G21", "G0 X2 Y2.5", "M30");
    }

    [Fact]
    public void Positions_offsets_and_tools_the_host_knows_are_read()
    {
        var d = Check("pos.nc", "O0001\nG21 G90 G54\nG00 X12. Y-3. Z40.\n#1 = #5001\n#2 = #5002 + #5221\n#3 = #4003\nG01 X[#1 + 1] Y#2 Z#3 F100\nM30\n");
        d.Where(x => x.Severity == Severity.Error).Should().BeEmpty();
        var path = Write("pos2.nc", "O0001\nG21 G90 G54\nG00 X12. Y-3. Z40.\nG01 X[#5001 + 1] Y#5002 Z#4003 F100\nM30\n");
        Blocks(Expand(path, Fanuc).Lines).Should().Contain("G1 X13 Y-3 Z90 F100");
    }

    [Fact]
    public void A_program_without_subprograms_or_macros_is_not_expanded()
    {
        ProgramExpansion.Applies(RepoRoot.DemoProgram, MachineProfile.Default).Should().BeFalse("demo.nc is split and tracked exactly as before");
        var plain = Write("plain.nc", "%\nO0001 (NO MACROS #1 IN A COMMENT)\nG21 G90\nG00 X1 M09\nM30\n%\n");
        ProgramExpansion.Applies(plain, MachineProfile.Default).Should().BeFalse();
        var sub = Write("sub.nc", "O0001\nG21\nM98 P2\nM30\nO0002\nG0 X1\nM99\n");
        ProgramExpansion.Applies(sub, MachineProfile.Default).Should().BeTrue();
        ProgramExpansion.Applies(sub, MachineProfile.Named("grbl")).Should().BeFalse("grbl expands nothing");
    }

    [SkippableFact]
    public void The_corpus_is_expanded_only_where_it_uses_o_words_and_enclosure_checks_clean_under_linuxcnc_mill()
    {
        var files = Requires.Corpus();
        foreach (var file in files)
        {
            var name = Path.GetFileName(file);
            var isEnclosure = name.Contains("Enclosure", StringComparison.Ordinal);
            ProgramExpansion.Applies(file, MachineProfile.Default).Should().BeFalse($"{name} has no FANUC macros");
            ProgramExpansion.Applies(file, MachineProfile.Named("linuxcnc-mill")).Should().Be(isEnclosure, name);
        }

        var enclosure = files.Single(f => f.Contains("Enclosure", StringComparison.Ordinal));
        var diags = new List<Diagnostic>();
        var summary = new Checker(MachineProfile.Named("linuxcnc-mill")!).CheckFile(enclosure, diags.Add);
        diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
        summary.Blocks.Should().BeGreaterThan(1700);
    }

    /// <summary>The macro both programs call: a peck at the point the move reached, #26 deep (Z argument), #18 up (R).</summary>
    private const string Peck = """
        %
        O9200 (PECK)
        G91 G01 Z-#26 F100.
        G00 Z#18
        G90
        M99
        %
        """;

    [Fact]
    public void A_G66_modal_call_runs_the_macro_after_every_move_block_as_the_hand_expanded_G65_program_does()
    {
        // rs274 does not run G66: the proof is the same program written with a G65 after each move (FANUC's meaning).
        var modal = Write("modal.nc", """
            %
            O0001
            G21 G90 G17 G54 G00 X0 Y0 Z5.
            G66 P9200 Z2. R2.
            X10.
            Y10. (a move block)
            M08
            X20. Y5.
            G67
            X30.
            M30
            """ + "\n" + Peck);
        var hand = Write("hand.nc", """
            %
            O0001
            G21 G90 G17 G54 G00 X0 Y0 Z5.
            X10.
            G65 P9200 Z2. R2.
            Y10. (a move block)
            G65 P9200 Z2. R2.
            M08
            X20. Y5.
            G65 P9200 Z2. R2.
            X30.
            M30
            """ + "\n" + Peck);
        var (modalLines, me) = Expand(modal, Fanuc);
        var (handLines, he) = Expand(hand, Fanuc);
        me.Error.Should().BeNull();
        he.Error.Should().BeNull();
        Blocks(modalLines).Should().Equal(Blocks(handLines), "G66 calls after X10, Y10 and X20 Y5, not after M08 nor after G67");
        Blocks(modalLines).Count(l => l.StartsWith("G91", StringComparison.Ordinal)).Should().Be(3);
        Positions(modalLines).Should().Equal(Positions(handLines));
        var second = modalLines.FindIndex(modalLines.FindIndex(l => l.StartsWith("G91", StringComparison.Ordinal)) + 1, l => l.StartsWith("G91", StringComparison.Ordinal)) + 1;
        me.Map.Describe(second).Should().Be("O9200 line 14, call 1 of 1 from line 6", "the call is the move block's");

        var everyBlock = Write("g661.nc", "O0001\nG66.1 P9200 Z2.\nX1.\nM30\n" + Peck);
        var (_, refused) = Expand(everyBlock, Fanuc);
        refused.Error!.Code.Should().Be(ExpansionCodes.Syntax);
        refused.Error.Message.Should().Contain("G66.1");
    }

    [Fact]
    public void A_G66_inside_a_subprogram_calls_after_the_subprograms_own_moves_as_the_hand_expanded_program_does()
    {
        const string Main = "%\nO0001\nG21 G90 G17 G54 G00 X0 Y0 Z5.\nM98 P0100 L2\nX30.\nM30\n";
        var modal = Write("sub-modal.nc", Main + "%\nO0100\nG66 P9200 Z2. R2.\nX10.\nY10.\nG67\nX5.\nM99\n" + Peck);
        var hand = Write("sub-hand.nc", Main + "%\nO0100\nX10.\nG65 P9200 Z2. R2.\nY10.\nG65 P9200 Z2. R2.\nX5.\nM99\n" + Peck);
        var (modalLines, me) = Expand(modal, Fanuc);
        var (handLines, he) = Expand(hand, Fanuc);
        me.Error.Should().BeNull();
        he.Error.Should().BeNull();
        Blocks(modalLines).Count(l => l.StartsWith("G91", StringComparison.Ordinal)).Should().Be(4, "two moves call the macro, in each of two calls: " + string.Join(" | ", modalLines));
        Positions(modalLines).Should().Equal(Positions(handLines), "the modal call inside O0100 pecks after its own moves only, not after X5. nor the caller's X30.");
        Positions(modalLines).Should().Contain(new Point3(30, 10, 5));
    }

    [Theory]
    [InlineData("G66 P9200 Z2. R2.\nM98 P0100\nG67\n", "%\nO0100\nX10.\nM99\n", "G67 before the call")]
    [InlineData("M98 P0100\n", "%\nO0100\nG66 P9200 Z2. R2.\nX10.\nM99\n", "G67 before M99")]
    public void A_G66_carried_into_or_out_of_a_subprogram_is_refused_with_the_reason(string main, string sub, string reason)
    {
        var file = Write("sub-refused.nc", "%\nO0001\nG21 G90 G00 X0 Y0 Z5.\n" + main + "M30\n" + sub + Peck);
        var (_, refused) = Expand(file, Fanuc);
        refused.Error!.Code.Should().Be(ExpansionCodes.Flow);
        refused.Error.Message.Should().Contain("G66").And.Contain(reason);
    }

    /// <summary>Where the interpreter's canonical moves end over expanded lines.</summary>
    private static List<Point3> Positions(List<string> lines)
    {
        using var reader = new GCodeReader(new MemoryStream(System.Text.Encoding.ASCII.GetBytes(string.Join('\n', lines))));
        return CanonBlockEnds.Of(reader, MachineProfile.Default, amend: false).Select(m => m.End).ToList();
    }
}
