using PmacStream.Plc;

namespace PmacStream.Core.Tests.Plc;

public class LadderParserTests
{
    private const string Decls = """
        input  SB1 0
        input  SB2 1
        input  SB3 2
        input  KR  3
        output KM1 0
        output KM2 1

        """;

    private static IReadOnlyList<LadderDiagnostic> Errors(string text)
    {
        LadderParser.TryParse(text, out var d).Should().BeNull("the text has errors");
        return d;
    }

    [Fact]
    public void Seed_motor_circuit_parses_into_symbols_and_rungs()
    {
        var p = LadderParser.Parse(Decls + "KM1 = !SB1 & (SB2 | KM1) & !KM2 & !KR\nKM2 = !SB1 & (SB3 | KM2) & !KM1 & !KR\n");
        p.Symbols.Select(s => (s.Name, s.MVariable)).Should().Equal(
            ("SB1", 800), ("SB2", 801), ("SB3", 802), ("KR", 803), ("KM1", 900), ("KM2", 901));
        p.Rungs.Should().HaveCount(2);
        var series = p.Rungs[0].Network.Should().BeOfType<LadderSeries>().Subject;
        series.Items.Should().HaveCount(4);
        series.Items[0].Should().Be(new LadderContact(p.Find("sb1")!, true));
        series.Items[1].Should().BeOfType<LadderParallel>().Which.Items.Should().HaveCount(2);
        p.Rungs[1].Line.Should().Be(8);
    }

    [Fact]
    public void Comments_blank_lines_and_both_comment_characters_are_ignored()
    {
        var p = LadderParser.Parse("# header\n\n; other style\n" + Decls + "KM1 = SB2 ; trailing\nKM2 = SB3 # trailing\n");
        p.Rungs.Should().HaveCount(2);
        p.Find("SB1")!.Comment.Should().BeNull();
    }

    [Fact]
    public void Declaration_comment_is_kept_for_the_generated_program()
    {
        var p = LadderParser.Parse("input SB1 0 # stop button\noutput K 0\nK = !SB1\n");
        p.Find("SB1")!.Comment.Should().Be("stop button");
    }

    [Fact]
    public void A_rung_continues_while_a_bracket_is_open_or_after_a_trailing_operator()
    {
        var p = LadderParser.Parse(Decls + "KM1 = !SB1 &\n   (SB2 |\n    KM1)\n   & !KM2 & !KR\nKM2 = SB3\n");
        p.Rungs.Should().HaveCount(2);
        PlcGenerator.Format(p.Rungs[0].Network).Should().Be("(M800^1)&(M801|M900)&(M901^1)&(M803^1)");
    }

    [Fact]
    public void Nested_series_and_parallel_groups_are_flattened_and_double_negation_cancels()
    {
        var p = LadderParser.Parse(Decls + "KM1 = (SB1 & SB2) & (SB3 & KR)\nKM2 = (SB1 | SB2) | !!SB3\n");
        p.Rungs[0].Network.Should().BeOfType<LadderSeries>().Which.Items.Should().HaveCount(4);
        var par = p.Rungs[1].Network.Should().BeOfType<LadderParallel>().Subject;
        par.Items.Should().HaveCount(3);
        par.Items[2].Should().Be(new LadderContact(p.Find("SB3")!, false));
    }

    [Fact]
    public void Negated_group_becomes_a_not_node()
    {
        var p = LadderParser.Parse(Decls + "KM1 = !(SB1 | SB2)\n");
        p.Rungs[0].Network.Should().BeOfType<LadderNot>().Which.Inner.Should().BeOfType<LadderParallel>();
    }

    [Fact]
    public void Names_are_case_insensitive()
    {
        var p = LadderParser.Parse(Decls + "km1 = !sb1 & Sb2\n");
        p.Rungs[0].Coil.Name.Should().Be("KM1");
    }

    [Fact]
    public void Directives_move_words_images_and_variable_bases()
    {
        var p = LadderParser.Parse("""
            plc 7
            inputs word=X:$078C00,8,16 image=Y:$0010F4 word-var=M2000 image-var=M2001 bits=M2100
            outputs word=Y:$078C01 bits=M2200
            internals image=Y:$0010F8 bits=M2300
            input A 15
            output B 3
            internal C
            C = A
            B = C
            """);
        p.PlcNumber.Should().Be(7);
        p.Inputs.Should().Be(new IoWordConfig(0x078C00, 'X', 8, 16, 0x0010F4, 2000, 2001, 2100));
        p.Outputs.WordAddress.Should().Be(0x078C01);
        p.Outputs.BitBase.Should().Be(2200);
        p.Find("A")!.MVariable.Should().Be(2115);
        p.Find("B")!.MVariable.Should().Be(2203);
        p.Find("C")!.MVariable.Should().Be(2300);
        p.Internals.Address.Should().Be(0x0010F8);
    }

    [Theory]
    [InlineData("KM1 = !SB1 & SB9\n", 7, 14, "'SB9' is not declared")]
    [InlineData("KM1 = !SB1 & (SB2 | KM1\nKM2 = SB3\n", 7, 24, "expected ')' to close the '(' at column 14, found the end of the rung")]
    [InlineData("KM1 = !SB1 & SB2)\n", 7, 17, "unmatched ')'")]
    [InlineData("KM1 = !SB1 SB2\n", 7, 12, "expected '&', '|' or the end of the rung, found 'SB2'")]
    [InlineData("KM1 = SB1 & | SB2\n", 7, 13, "expected a contact name, '!' or '(', found '|'")]
    [InlineData("KM1 = (SB1^1)\n", 7, 11, "unexpected character '^'")]
    [InlineData("SB1 = SB2\n", 7, 1, "'SB1' is an input (line 1)")]
    [InlineData("KM9 = SB2\n", 7, 1, "coil 'KM9' is not declared")]
    [InlineData("KM1 = SB2\nKM1 = SB3\n", 8, 1, "already driven by the rung on line 7 (double coil)")]
    [InlineData("input SB1 4\nKM1 = SB1\n", 7, 7, "'SB1' is already declared on line 1")]
    [InlineData("input X 3\nKM1 = X\n", 7, 9, "input bit 3 is already 'KR' (line 4)")]
    [InlineData("input X 8\nKM1 = X\n", 7, 9, "expected a bit number 0..7")]
    [InlineData("output X\nKM1 = SB2\n", 7, 8, "expected 'output NAME BIT'")]
    [InlineData("input 9X 5\nKM1 = SB2\n", 7, 7, "'9X' is not a valid name")]
    [InlineData("plc 40\nKM1 = SB2\n", 7, 5, "PLC program number 0..31")]
    [InlineData("inputs word=Y:078800\nKM1 = SB2\n", 7, 13, "expected an address like Y:$078800")]
    [InlineData("inputs word=Y:$078800,20,8\nKM1 = SB2\n", 7, 13, "goes past bit 23")]
    [InlineData("inputs bits=M9000\nKM1 = SB2\n", 7, 13, "expected an M-variable M0..M8191")]
    [InlineData("inputs colour=red\nKM1 = SB2\n", 7, 8, "unknown setting 'colour'")]
    [InlineData("outputs bits=M803\nKM1 = SB2\n", 5, 1, "M803 would be used twice")]
    [InlineData("hello world\nKM1 = SB2\n", 7, 1, "expected a rung 'COIL = contacts' or a declaration")]
    [InlineData("KM1 = SB1 &\n", 7, 11, "the rung is not finished at the end of the file")]
    public void Errors_name_the_line_and_column(string tail, int line, int column, string message)
    {
        var errors = Errors(Decls + tail);
        errors.Should().Contain(e => e.Line == line && e.Column == column && e.Message.Contains(message),
            $"got: {string.Join(" | ", errors.Select(e => e.Format("f")))}");
    }

    [Fact]
    public void Every_error_in_the_file_is_reported_in_line_order()
    {
        var errors = Errors(Decls + "KM1 = SB9\nKM2 = (SB1\n\nbogus\n");
        errors.Select(e => e.Line).Should().BeInAscendingOrder();
        errors.Should().HaveCountGreaterThanOrEqualTo(2);
        errors[0].Should().Be(new LadderDiagnostic(7, 7, "'SB9' is not declared; declare it with input, output or internal"));
    }

    [Fact]
    public void A_file_with_no_rungs_is_an_error()
    {
        Errors(Decls).Should().ContainSingle().Which.Message.Should().Contain("no rungs");
    }

    [Fact]
    public void Parse_throws_with_formatted_messages()
    {
        var act = () => LadderParser.Parse(Decls + "KM1 = SB9\n", "motor.ladder");
        act.Should().Throw<LadderParseException>().WithMessage("motor.ladder:7:7: error: 'SB9' is not declared*")
            .Which.Diagnostics.Should().ContainSingle();
    }

    [Fact]
    public void Internal_relays_that_collide_with_an_image_word_are_rejected()
    {
        var errors = Errors("internals image=Y:$0010F1\ninternal A\noutput B 0\nA = B\nB = A\n");
        errors.Should().Contain(e => e.Message.Contains("overlap the outputs image"));
    }

    [Fact]
    public void Samples_parse_without_errors()
    {
        foreach (var file in new[] { "motor-fwd-rev.ladder", "sand-mould-spindle.ladder" })
        {
            var path = Path.Combine(PlcTestPaths.Samples, file);
            LadderParser.TryParse(File.ReadAllText(path), out var d).Should().NotBeNull(string.Join("; ", d.Select(x => x.Format(file))));
        }
    }
}

internal static class PlcTestPaths
{
    public static string Samples => RepoRoot.Sample("plc");
}
