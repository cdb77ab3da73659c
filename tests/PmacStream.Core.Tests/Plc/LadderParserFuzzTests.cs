using PmacStream.Plc;

namespace PmacStream.Core.Tests.Plc;

public class LadderParserFuzzTests
{
    /// <summary>
    /// Seeded mutations of the sample (deleted, duplicated and replaced characters): the parser either accepts the
    /// text or reports errors whose positions lie inside the text; it never throws.
    /// </summary>
    [Fact]
    public void Mutated_ladders_give_errors_inside_the_text_and_never_crash()
    {
        var sample = File.ReadAllText(Path.Combine(PlcTestPaths.Samples, "sand-mould-spindle.ladder"));
        const string alphabet = "()&|!=#;$:,.^ \n\tAKMSY0123456789_";
        var rng = new Random(3003);
        var rejected = 0;
        for (var trial = 0; trial < 1500; trial++)
        {
            var chars = sample.ToCharArray().ToList();
            for (var k = rng.Next(1, 4); k > 0; k--)
            {
                var at = rng.Next(chars.Count);
                switch (rng.Next(3))
                {
                    case 0:
                        chars.RemoveAt(at);
                        break;
                    case 1:
                        chars.Insert(at, chars[at]);
                        break;
                    default:
                        chars[at] = alphabet[rng.Next(alphabet.Length)];
                        break;
                }
            }

            var text = new string(chars.ToArray());
            var lines = text.Replace("\r\n", "\n", StringComparison.Ordinal).Split('\n');
            var result = LadderParser.TryParse(text, out var diagnostics);
            if (result is null)
            {
                rejected++;
                diagnostics.Should().NotBeEmpty();
                foreach (var d in diagnostics)
                {
                    d.Line.Should().BeInRange(1, lines.Length, text);
                    d.Column.Should().BeInRange(1, lines[d.Line - 1].Length + 1, $"{d.Format("fuzz")} in line '{lines[d.Line - 1]}'");
                }
            }
            else
            {
                diagnostics.Should().BeEmpty();
                PlcGenerator.Generate(result).Statements.Should().HaveCount(result.Rungs.Count);
            }
        }

        rejected.Should().BeInRange(100, 1499, "the mutations produce both valid and invalid files");
    }
}
