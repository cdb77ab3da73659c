using PmacStream.GCode;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.GCode;

/// <summary>The twelve real CAM programs in ../shared/gcode-corpus (reported SKIPPED, with the reason, when the folder is absent).</summary>
public class CorpusTests(ITestOutputHelper output)
{
    [SkippableFact]
    public void Checker_reads_every_corpus_program_without_throwing_and_with_lines_in_range()
    {
        var files = Requires.Corpus();
        files.Should().HaveCount(12);
        var checker = new Checker(MachineProfile.Default);
        foreach (var file in files)
        {
            var diags = new List<Diagnostic>();
            long blocks = 0;
            var summary = checker.CheckFile(file, diags.Add, _ => blocks++);
            var text = File.ReadAllText(file).Replace("\r\n", "\n").Replace('\r', '\n');
            var lineCount = text.Count(c => c == '\n') + (text.EndsWith('\n') ? 0 : 1);
            summary.Lines.Should().Be(lineCount, Path.GetFileName(file));
            summary.Blocks.Should().Be(blocks).And.BeGreaterThan(0);
            diags.All(d => d.Line >= 1 && d.Line <= summary.Lines && d.Column >= 1).Should().BeTrue();
            output.WriteLine($"{Path.GetFileName(file)}: {summary} ({string.Join(", ", diags.GroupBy(d => d.Code).Select(g => $"{g.Key}x{g.Count()}"))})");
        }
    }
}

/// <summary>The splitter's check skips measuring straight moves; it must not change what is reported.</summary>
public class UnmeasuredCheckTests
{
    [SkippableFact]
    public void Not_measuring_straight_moves_reports_the_same_diagnostics_on_every_corpus_program()
    {
        var files = Requires.Corpus();
        foreach (var file in files)
        {
            var measured = new List<Diagnostic>();
            var unmeasured = new List<Diagnostic>();
            var a = new Checker(MachineProfile.Default).CheckFile(file, measured.Add);
            var b = new Checker(MachineProfile.Default) { MeasureMoves = false }.CheckFile(file, unmeasured.Add);
            unmeasured.Should().Equal(measured, Path.GetFileName(file));
            b.Blocks.Should().Be(a.Blocks);
            b.EstimatedSeconds.Should().BeLessThan(a.EstimatedSeconds, "straight moves were left out of the estimate");
        }
    }

    [Fact]
    public void Not_measuring_keeps_feed_errors_and_arc_checks()
    {
        const string program = "O1\nN1 G90 G01 X10 Y0\nN2 G02 X0 Y10 R-0.001\nN3 F100 X20\n";
        var (a, da) = new Checker(MachineProfile.Default).CheckText(program);
        var checker = new Checker(MachineProfile.Default) { MeasureMoves = false };
        var diags = new List<Diagnostic>();
        using var ms = new MemoryStream(System.Text.Encoding.ASCII.GetBytes(program));
        var b = checker.Check(ms, "<text>", diags.Add);
        diags.Select(d => d.Code).Should().Equal(da.Select(d => d.Code)).And.NotBeEmpty();
        b.Errors.Should().Be(a.Errors).And.BeGreaterThan(0);
    }
}
