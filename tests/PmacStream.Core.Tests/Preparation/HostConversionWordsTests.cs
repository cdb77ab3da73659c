using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>
/// The host conversion hands the splitter the words of the move line it wrote instead of having it lexed again: those
/// words must be exactly what the lexer reads from the line (letters, values, columns, number spans).
/// </summary>
public class HostConversionWordsTests
{
    private static readonly string[] Inch =
    [
        "O1", "G20 G90 G17 G54", "G00 X0 Y0 Z0.2", "G01 Z-0.05 F12.5", "X1.23456 Y-0.5", "Y0.00001", "X-12.3456789 Y987.654321",
        "G02 X2. Y0.5 I0.5 J0", "G03 X1.5 Y1. R0.5", "G91 G01 X0.1 Y-0.1", "G90", "G53 G00 Z0", "G01 X100000. F1.", "X-0.0000001",
        "G17 G02 X3. Y3. I0.5 J0.5 F7.", "G90.1 G02 X4. Y3. I3.5 J3.", "G91.1", "G01 X1234567.891 Y0", "X99999999999999. Y0",
        "G18 G03 X1. Z0.1 I0.2 K0.1", "G17", "G95 S1000 M03", "G01 X2. F0.002", "G94", "G93 G01 X3. F2.", "G94 G01 X4. F20.", "M30",
    ];

    [Fact]
    public void The_words_of_a_converted_move_are_the_lexers_words_of_its_text()
    {
        var interpreter = new Interpreter(MachineProfile.Default) { MeasureMoves = false, RecordBlocks = false };
        var host = new HostConversion(interpreter);
        var recorded = 0;
        var lexed = 0;
        for (var n = 0; n < Inch.Length; n++)
        {
            var block = GCodeReader.LexLine(Inch[n], n + 1);
            interpreter.StepCore(block, null);
            if (host.TakeLines() is not { } lines)
            {
                continue;
            }

            for (var i = 0; i < lines.Count; i++)
            {
                var expected = GCodeReader.LexLine(lines[i], n + 1).Words.ToArray();
                if (host.TryWordsOf(i, out var words))
                {
                    words.ToArray().Should().Equal(expected, $"line {n + 1} '{Inch[n]}' converted to '{lines[i]}'");
                    recorded++;
                }
                else
                {
                    lexed++;
                }
            }
        }

        recorded.Should().BeGreaterThanOrEqualTo(15, "the moves of an inch program carry their words");
        lexed.Should().BeGreaterThan(0, "a number the lexer reads its own way (16 characters and more), and lines other than the move, are lexed");
    }
}
