using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>The lexer's one-pass number conversion against double.Parse, bit for bit, wherever the word stands.</summary>
public class NumberValueTests
{
    [Fact]
    public void Lexed_values_equal_double_parse_for_random_numbers_in_every_position()
    {
        var rng = new Random(1234);
        for (var trial = 0; trial < 50_000; trial++)
        {
            var intDigits = rng.Next(0, 19);
            var fracDigits = rng.Next(0, 19);
            var sb = new StringBuilder();
            sb.Append(rng.Next(3) switch { 0 => "-", 1 => "+", _ => string.Empty });
            for (var i = 0; i < intDigits; i++)
            {
                sb.Append((char)('0' + rng.Next(10)));
            }

            var point = fracDigits > 0 || rng.Next(2) == 0;
            if (point)
            {
                sb.Append('.');
            }

            for (var i = 0; i < fracDigits; i++)
            {
                sb.Append((char)('0' + rng.Next(10)));
            }

            var number = sb.ToString();
            var before = rng.Next(2) == 0 ? "G1 " : string.Empty;
            var after = rng.Next(3) switch { 0 => string.Empty, 1 => " Y7", _ => "Z1.5 (c)" };
            var text = $"{before}X{number}{after}";

            // Through a reader (a reused 256-byte line buffer holding the previous, longer line) and alone.
            var stream = new MemoryStream(Encoding.ASCII.GetBytes(new string('9', 200) + "\n" + text + "\n"));
            using var reader = new GCodeReader(stream);
            reader.Read().Should().BeTrue();
            reader.Read().Should().BeTrue();
            foreach (var block in new[] { reader.Current, GCodeReader.LexLine(text) })
            {
                var x = block.Words.Where(w => w.Letter == 'X').ToList();
                var digits = intDigits + fracDigits;
                if (digits == 0)
                {
                    x.Should().BeEmpty(text);
                    block.LexicalDiagnostics.Should().Contain(d => d.Code == DiagnosticCodes.MalformedNumber, text);
                    continue;
                }

                var expected = double.Parse(number, NumberStyles.Float, CultureInfo.InvariantCulture);
                if (digits > 15 && Math.Abs(expected) > 1e15)
                {
                    x.Should().BeEmpty(text);
                    continue;
                }

                x.Should().ContainSingle(text);
                BitConverter.DoubleToInt64Bits(x[0].Value).Should().Be(BitConverter.DoubleToInt64Bits(expected), $"{text}: {x[0].Value:R} vs {expected:R}");
                Encoding.ASCII.GetString(block.NumberText(x[0])).Should().Be(number, text);
            }
        }
    }
}

/// <summary>Lines are lexed where they lie in the read buffer, or copied when they straddle two reads: the result must not depend on which.</summary>
public class ReadBufferIndependenceTests
{
    [Theory]
    [InlineData(1)]
    [InlineData(3)]
    [InlineData(7)]
    [InlineData(64)]
    [InlineData(4096)]
    public void Every_read_buffer_size_lexes_a_program_the_same(int bufferSize)
    {
        var rng = new Random(99);
        var sb = new StringBuilder();
        string[] pieces = ["G1", "X-12.5", "Y.25", "Z+3.", "(comment 注释)", ";tail", "  ", "\t", "%", "/", "N10", "f1500", "X1.2.3", "#", "M30"];
        for (var line = 0; line < 400; line++)
        {
            var n = rng.Next(0, 8);
            for (var i = 0; i < n; i++)
            {
                sb.Append(pieces[rng.Next(pieces.Length)]).Append(rng.Next(3) == 0 ? " " : string.Empty);
            }

            sb.Append(rng.Next(3) switch { 0 => "\n", 1 => "\r\n", _ => "\r" });
        }

        var bytes = Encoding.UTF8.GetBytes(sb.ToString());
        Read(bytes, bufferSize).Should().Equal(Read(bytes, 1 << 16));
    }

    private static List<string> Read(byte[] bytes, int bufferSize)
    {
        using var reader = new GCodeReader(new MemoryStream(bytes), bufferSize: bufferSize);
        var result = new List<string>();
        while (reader.Read())
        {
            var b = reader.Current;
            var words = string.Join(" ", b.Words.Select(w => $"{w.Letter}{w.Value.ToString("R", CultureInfo.InvariantCulture)}@{w.Column}:{Encoding.UTF8.GetString(b.NumberText(w))}"));
            var diags = string.Join(",", b.LexicalDiagnostics.Select(d => $"{d.Code}@{d.Column}"));
            result.Add($"{b.LineNumber}|{b.ByteOffset}|{Encoding.UTF8.GetString(b.Line)}|{words}|{string.Join("/", b.CommentTexts())}|{diags}|{b.BlockDelete}|{b.IsTapeMark}");
        }

        return result;
    }
}
