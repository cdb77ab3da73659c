using PmacStream.Plc;

namespace PmacStream.Core.Tests.Plc;

/// <summary>The ladder reader's parts on their own: the lexer and the placement directives.</summary>
public class LadderPartsTests
{
    private static List<LadderWord> Words(string line) => LadderLexer.SplitWords(line, 7);

    [Fact]
    public void Tokens_carry_their_line_and_column_and_a_stray_character_is_reported_with_a_hint()
    {
        var errors = new List<(int Line, int Column, string Message)>();
        var tokens = new List<LadderToken>();
        LadderLexer.Tokenize("KM1 = !SB1 + (SB2)", 4, tokens, (l, c, m) => errors.Add((l, c, m)));

        tokens.Select(t => (t.Kind, t.Text, t.Column)).Should().Equal(
            (LadderTokenKind.Name, "KM1", 1), (LadderTokenKind.Assign, "=", 5), (LadderTokenKind.Not, "!", 7), (LadderTokenKind.Name, "SB1", 8),
            (LadderTokenKind.Open, "(", 14), (LadderTokenKind.Name, "SB2", 15), (LadderTokenKind.Close, ")", 18));
        tokens.Should().OnlyContain(t => t.Line == 4);
        errors.Should().ContainSingle().Which.Should().Match<(int Line, int Column, string Message)>(e => e.Line == 4 && e.Column == 12 && e.Message.Contains("parallel branches with |"));
    }

    [Theory]
    [InlineData("KM1 = SB1 &", true)]
    [InlineData("KM1 = (SB1 | SB2", true)]
    [InlineData("KM1 = !", true)]
    [InlineData("KM1 = (SB1 | SB2) & !KR", false)]
    public void A_rung_goes_on_while_a_bracket_is_open_or_it_ends_with_an_operator(string code, bool more)
    {
        var tokens = new List<LadderToken>();
        LadderLexer.Tokenize(code, 1, tokens, (_, _, _) => { });
        LadderLexer.NeedsContinuation(tokens.Skip(2).ToList()).Should().Be(more);
    }

    [Fact]
    public void Comments_start_at_hash_or_semicolon_and_words_keep_their_columns()
    {
        LadderLexer.SplitComment("input SB1 0  # start button").Should().Be(("input SB1 0  ", "start button"));
        LadderLexer.SplitComment("KM1 = SB1 ;").Should().Be(("KM1 = SB1 ", (string?)null));
        Words("  output  KM1 3").Select(w => (w.Text, w.Column, w.Line)).Should().Equal(("output", 3, 7), ("KM1", 11, 7), ("3", 15, 7));
    }

    [Fact]
    public void Directives_set_the_placement_once_and_declarations_are_left_to_the_parser()
    {
        var errors = new List<(int Line, int Column, string Message)>();
        var d = new LadderDirectives((l, c, m) => errors.Add((l, c, m)));

        d.Apply(Words("plc 5")).Should().BeTrue();
        d.Apply(Words("inputs word=X:$078802,8,4 image=Y:$0010F5 bits=M2000")).Should().BeTrue();
        d.Apply(Words("internal K1")).Should().BeFalse("a declaration");
        errors.Should().BeEmpty();
        d.Plc.Should().Be(5);
        d.Inputs.Should().Be(IoWordConfig.DefaultInputs with { Memory = 'X', WordAddress = 0x078802, Offset = 8, Width = 4, ImageAddress = 0x0010F5, BitBase = 2000 });
        d.Outputs.Should().Be(IoWordConfig.DefaultOutputs);
        d.LineOf("inputs").Should().Be(7);
        d.LineOf("outputs", 42).Should().Be(42, "not given");

        d.Apply(Words("inputs bits=M10")).Should().BeTrue();
        d.Apply(Words("plc 6")).Should().BeTrue();
        errors.Select(e => e.Message).Should().Equal("'inputs' is already given on line 7", "the PLC number is already set on line 7");
        d.Inputs.BitBase.Should().Be(2000, "a repeated directive changes nothing");
    }

    [Theory]
    [InlineData("outputs word=Z:$078801", 14, "memory must be X or Y, found 'Z'")]
    [InlineData("outputs word=Y:$GG", 17, "expected a hexadecimal address after '$' (at most $FFFFFF), found 'GG'")]
    [InlineData("outputs word=Y:$078801,20,8", 14, "offset 20 + width 8 goes past bit 23 of a 24-bit word")]
    [InlineData("outputs image=Y:$0010F1,0", 15, "expected an address like Y:$0010F0 (the image width follows the physical word), found 'Y:$0010F1,0'")]
    [InlineData("internals bits=M9000", 16, "expected an M-variable M0..M8191, found 'M9000'")]
    [InlineData("internals size=3", 11, "unknown setting 'size'; expected image= or bits=")]
    public void A_bad_address_or_setting_is_reported_where_it_is_written(string line, int column, string message)
    {
        var errors = new List<(int Line, int Column, string Message)>();
        new LadderDirectives((l, c, m) => errors.Add((l, c, m))).Apply(Words(line)).Should().BeTrue();
        errors.Should().Equal((7, column, message));
    }
}
