using System.Text;

namespace PmacStream.Sim.Tests.Performance;

/// <summary>
/// The allocation-free line storage path (reused token/statement lists, the line itself kept as LIST text when it
/// needs no clean-up) must store exactly what the straightforward path stored.
/// </summary>
public sealed class LineStorageTests
{
    [Theory]
    [InlineData("X1 Y2 Z3", "X1 Y2 Z3")]
    [InlineData("x1 y2 z3", "X1 Y2 Z3")]
    [InlineData("  X1   Y2\tZ3  ", "X1 Y2 Z3")]
    [InlineData("X1 \t Y2", "X1 Y2")]
    [InlineData("M0==12 X0.5 Y.25 Z-0.003", "M0==12 X0.5 Y.25 Z-0.003")]
    [InlineData("X1 Y2 ; a comment", "X1 Y2")]
    [InlineData("X1Y2F(P500)", "X1Y2F(P500)")]
    public void Listed_text_is_the_trimmed_upper_case_line_with_blank_runs_collapsed(string sent, string listed)
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 4 CLEAR", sent, "CLOSE");
        h.Ok("LIST PROG 4").Should().Be(listed);
    }

    [Fact]
    public void Online_commands_before_program_statements_are_not_part_of_the_stored_text()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 4 CLEAR", "&2 X1  Y2", "CLOSE");
        h.Ok("LIST PROG 4").Should().Be("X1 Y2");
        h.Port.CoordinateSystem.Should().Be(2, "the online part still ran");
    }

    [Fact]
    public void A_refused_line_does_not_disturb_the_lines_after_it()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 4 CLEAR", "X1");
        h.Send("X1 @").Should().Be("<BEL>ERR003<CR>");
        h.Download("M0==2 X2", "CLOSE");
        h.Ok("LIST PROG 4").Should().Be("X1\nM0==2 X2");
    }

    [Fact]
    public void Random_spacing_stores_what_the_reference_clean_up_gives()
    {
        var random = new Random(20261122);
        var letters = "XYZIJKF";
        using var h = new SimHarness();
        h.Send("OPEN PROG 9 CLEAR").Should().Be("<ACK>");
        var expected = new List<string>();
        for (var n = 0; n < 300; n++)
        {
            var sb = new StringBuilder();
            sb.Append(Blank(random));
            var words = random.Next(1, 5);
            for (var w = 0; w < words; w++)
            {
                sb.Append(letters[random.Next(letters.Length)]);
                sb.Append(random.Next(2) == 0 ? "-" : string.Empty);
                sb.Append((random.Next(0, 100000) / 1000.0).ToString(System.Globalization.CultureInfo.InvariantCulture));
                sb.Append(w + 1 < words ? Blank(random) + (random.Next(3) == 0 ? string.Empty : " ") : Blank(random));
            }

            var line = sb.ToString();
            h.Send(line).Should().Be("<ACK>", $"'{line}' is a program line");
            expected.Add(Reference(line));
        }

        h.Send("CLOSE").Should().Be("<ACK>");
        h.Ok("LIST PROG 9").Split('\n').Should().Equal(expected);
    }

    private static string Blank(Random random) => random.Next(4) switch
    {
        0 => string.Empty,
        1 => " ",
        2 => "\t",
        _ => "  \t ",
    };

    /// <summary>What LIST showed before the fast path: trim, then every blank run as one space.</summary>
    private static string Reference(string line)
    {
        var parts = line.ToUpperInvariant().Split([' ', '\t'], StringSplitOptions.RemoveEmptyEntries);
        return string.Join(' ', parts);
    }
}
