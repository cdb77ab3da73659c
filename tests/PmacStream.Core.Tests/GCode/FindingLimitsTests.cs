using System.Text;
using PmacStream.GCode;
using PmacStream.Preview;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// Issue 20 item 3: a line of junk, or a file of them, costs the memory of a clean program. At most 64 findings a line
/// are listed and at most 256 words a line are read; every finding is still counted and the summary says how many
/// were not listed. Before, a 1 MB line of "X " held half a million diagnostics (420 MB in check).
/// </summary>
public class FindingLimitsTests
{
    private static readonly byte[] OneMegabyteOfX = Encoding.ASCII.GetBytes(new StringBuilder().Insert(0, "X ", 1 << 19).Append('\n').ToString());

    private static (CheckSummary Summary, List<Diagnostic> Listed) Check(byte[] bytes)
    {
        var listed = new List<Diagnostic>();
        var summary = new Checker(MachineProfile.Default).Check(new MemoryStream(bytes), "junk.nc", listed.Add);
        return (summary, listed);
    }

    [Fact]
    public void A_megabyte_line_of_findings_lists_64_and_counts_every_one()
    {
        var (summary, listed) = Check(OneMegabyteOfX);

        listed.Where(d => d.Line == 1 && d.Code == DiagnosticCodes.MalformedNumber).Should().HaveCount(FindingLimits.PerLine);
        summary.Errors.Should().Be((1 << 19) + 1, "every X is a malformed number, and the file holds no block (E120)");
        summary.UnlistedErrors.Should().Be((1 << 19) - FindingLimits.PerLine);
        summary.ToString().Should().Be("524289 errors, 0 warnings, 0 blocks; 524224 more not listed (at most 64 a line)");
    }

    [Fact]
    public void A_line_of_more_than_256_words_is_cut_there_and_the_interpreter_sees_no_more()
    {
        var text = "G01 F100 " + string.Join(string.Empty, Enumerable.Repeat("X1", 100_000));
        var block = GCodeReader.LexLine(text);
        block.Words.Should().HaveCount(FindingLimits.WordsPerLine);
        block.LexicalDiagnostics.Should().ContainSingle().Which.Code.Should().Be(DiagnosticCodes.TooManyWords);

        var (summary, listed) = Check(Encoding.ASCII.GetBytes("O1\n" + text + "\n"));
        listed.Count(d => d.Line == 2).Should().Be(FindingLimits.PerLine);
        summary.Errors.Should().Be(254, "E128 and an E111 for each of the 253 X words read after the first");
        summary.UnlistedErrors.Should().Be(254 - FindingLimits.PerLine);
    }

    [Fact]
    public void Findings_held_until_the_first_N_are_bounded_a_program_full_of_them_is_taken_as_unnumbered()
    {
        // 3000 un-numbered lines with two findings each, then a numbered block: before, all 9000 findings (W002s too)
        // were held until line 3002; now the hold ends at FindingLimits.Held and the program counts as un-numbered.
        var sb = new StringBuilder("O1\nG00 X0\n");
        for (var i = 0; i < 3000; i++)
        {
            sb.Append("G00 X1 X2 @\n");
        }

        var (summary, listed) = Check(Encoding.ASCII.GetBytes(sb.Append("N10 G00 X3\nG00 X4\n").ToString()));

        listed.Where(d => d.Code == DiagnosticCodes.NoSequenceNumber).Select(d => d.Line).Should().Equal([3004], "only the un-numbered block after the first N");
        listed.Where(d => d.Code == DiagnosticCodes.DuplicateWord).Should().HaveCount(3000);
        listed.Select(d => d.Line).Should().BeInAscendingOrder("still listed in line order");
        summary.UnlistedErrors.Should().Be(0);
    }

    [Fact]
    public void Split_refuses_with_the_count_of_every_error_and_lists_a_bounded_few()
    {
        using var temp = new TestFolder("limits");
        var folder = temp.Path;
        var src = Path.Combine(folder, "junk.nc");
        File.WriteAllBytes(src, OneMegabyteOfX);
        var act = () => Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(folder, "chunks"), CheckProfile = MachineProfile.Default });
        var refused = act.Should().Throw<SplitException>().Which;
        refused.ErrorCount.Should().Be((1 << 19) + 1);
        refused.Diagnostics.Count.Should().BeLessThanOrEqualTo(FindingLimits.PerLine + 1);

        var preview = new GCodeToolpathSource(src);
        preview.ReadSegments().Should().BeEmpty();
        preview.IssueCount.Should().Be(1 << 19, "the preview counts every lexical error too");
        preview.Issues.Should().HaveCount(GCodeToolpathSource.MaxIssuesKept);
    }
}
