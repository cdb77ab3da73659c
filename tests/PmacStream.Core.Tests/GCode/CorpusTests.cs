using PmacStream.GCode;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.GCode;

/// <summary>The twelve real CAM programs in ../shared/gcode-corpus (skipped, saying so, when the folder is absent).</summary>
public class CorpusTests(ITestOutputHelper output)
{
    [Fact]
    public void Checker_reads_every_corpus_program_without_throwing_and_with_lines_in_range()
    {
        if (RepoRoot.Corpus is not { } dir)
        {
            output.WriteLine("SKIPPED: ../shared/gcode-corpus is absent; nothing to check.");
            return;
        }

        var files = Directory.GetFiles(dir).Where(f => !f.EndsWith(".md") && !f.EndsWith(".tsv")).OrderBy(f => f).ToList();
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
