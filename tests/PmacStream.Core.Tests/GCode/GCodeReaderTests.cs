using System.Text;
using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

public class GCodeReaderTests
{
    private static List<(int Line, string Words, int Diags)> ReadAll(string text)
    {
        using var reader = new GCodeReader(new MemoryStream(Encoding.UTF8.GetBytes(text)));
        var result = new List<(int, string, int)>();
        while (reader.Read())
        {
            result.Add((reader.Current.LineNumber, reader.Current.TextWithoutComments(), reader.Current.LexicalDiagnostics.Count));
        }

        return result;
    }

    [Fact]
    public void Reads_packed_words_signs_and_bare_points()
    {
        var b = GCodeReader.LexLine("G0X1.Y-2.5z+.5");
        b.Words.Select(w => (w.Letter, w.Value)).Should().Equal(('G', 0), ('X', 1.0), ('Y', -2.5), ('Z', 0.5));
        b.Words[3].WasLowercase.Should().BeTrue();
        b.Words[1].Column.Should().Be(3);
        b.LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.LowercaseLetter && d.Column == 11);
    }

    [Fact]
    public void Accepts_spaces_between_letter_and_number()
    {
        var b = GCodeReader.LexLine("G0Z  0.1000 Y 0.25");
        b.Words.Select(w => (w.Letter, w.Value)).Should().Equal(('G', 0), ('Z', 0.1), ('Y', 0.25));
        b.LexicalDiagnostics.Should().BeEmpty();
    }

    [Theory]
    [InlineData("a\nb\nc", 3)]
    [InlineData("a\r\nb\r\nc\r\n", 3)]
    [InlineData("a\rb\rc\r", 3)]
    [InlineData("a\n\nc", 3)]
    public void Numbers_lines_for_every_line_end(string text, int lines)
    {
        ReadAll(text.Replace("a", "G1").Replace("b", "G2").Replace("c", "G3")).Should().HaveCount(lines)
            .And.Subject.Select(x => x.Line).Should().Equal(Enumerable.Range(1, lines));
    }

    [Fact]
    public void Crlf_split_across_buffer_boundary_is_one_line_end()
    {
        // A 4-byte buffer puts the CR and LF of "G1X1\r\n" into different reads.
        var bytes = Encoding.ASCII.GetBytes("G1X1\r\nG1X2\r\n");
        using var reader = new GCodeReader(new MemoryStream(bytes), bufferSize: 5);
        var lines = new List<string>();
        while (reader.Read())
        {
            lines.Add($"{reader.Current.LineNumber}:{reader.Current.TextWithoutComments()}");
        }

        lines.Should().Equal("1:G1 X1", "2:G1 X2");
    }

    [Fact]
    public void Comments_with_chinese_text_are_kept_apart_from_words()
    {
        var b = GCodeReader.LexLine("G1 X5 (刀具 1 号) F100.0(Penetrate) ; 注释");
        b.TextWithoutComments().Should().Be("G1 X5 F100.0");
        b.CommentTexts().Should().Equal("(刀具 1 号)", "(Penetrate)", "; 注释");
    }

    [Fact]
    public void Gbk_comment_is_decoded()
    {
        var gbk = CodePagesEncoding().GetBytes("(刀具)");
        var line = Encoding.ASCII.GetBytes("G0 X1 ").Concat(gbk).ToArray();
        using var reader = new GCodeReader(new MemoryStream(line));
        reader.Read().Should().BeTrue();
        reader.Current.CommentTexts().Single().Should().Be("(刀具)");
    }

    [Fact]
    public void Unclosed_comment_illegal_character_and_malformed_number_are_reported_with_columns()
    {
        GCodeReader.LexLine("G1 X1 (open").LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.UnclosedComment && d.Column == 7);
        GCodeReader.LexLine("G1 $X1").LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.IllegalCharacter && d.Column == 4);
        GCodeReader.LexLine("G1 X1..2").LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.MalformedNumber && d.Column == 4);
        GCodeReader.LexLine("G1 X-").LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.MalformedNumber);
    }

    [Theory]
    [InlineData("O100 sub", "O100 sub", 6)]
    [InlineData("o100 CALL [1.5]", "O100 call", 6)]
    [InlineData("O101 endsub", "O101 endsub", 6)]
    [InlineData("O7 endwhile", "O7 endwhile", 4)]
    public void A_LinuxCNC_o_word_construct_is_named_as_one_not_as_a_malformed_number(string line, string construct, int column)
    {
        var d = GCodeReader.LexLine(line).LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.MalformedNumber).Subject;
        d.Column.Should().Be(column);
        d.Message.Should().StartWith($"'{construct}' is a LinuxCNC o-word (subroutine or flow control)")
            .And.Contain("does not run").And.NotContain("expected digits");
    }

    [Fact]
    public void A_double_slash_after_a_word_is_named_as_an_older_dialects_tool_table_entry_once()
    {
        var block = GCodeReader.LexLine("T1//15.98");
        block.LexicalDiagnostics.Should().ContainSingle().Which.Should().Match<Diagnostic>(d =>
            d.Code == DiagnosticCodes.IllegalCharacter && d.Column == 3 && d.Message.Contains("tool-table entry of an older ISO dialect"));
        block.Words.Select(w => w.Letter).Should().Equal('T');
        GCodeReader.LexLine("G1 X1 /2 Y2").LexicalDiagnostics.Should().BeEmpty("a single slash with a level is block skip");
    }

    [Fact]
    public void A_letter_run_that_is_no_o_word_keyword_stays_a_malformed_number() =>
        GCodeReader.LexLine("G1 Xabc").LexicalDiagnostics.Should().ContainSingle(d => d.Code == DiagnosticCodes.MalformedNumber)
            .Which.Message.Should().Contain("expected digits").And.NotContain("o-word");

    [Fact]
    public void Tape_marks_block_delete_program_numbers()
    {
        GCodeReader.LexLine("%").IsTapeMark.Should().BeTrue();
        var del = GCodeReader.LexLine("/G1 X1");
        del.BlockDelete.Should().BeTrue();
        del.Words.Should().HaveCount(2);
        GCodeReader.LexLine("O0002").ProgramNumber.Should().Be(2);
        GCodeReader.LexLine(":1234").ProgramNumber.Should().Be(1234);
    }

    private static Encoding CodePagesEncoding()
    {
        Encoding.RegisterProvider(CodePagesEncodingProvider.Instance);
        return Encoding.GetEncoding(936);
    }
}
