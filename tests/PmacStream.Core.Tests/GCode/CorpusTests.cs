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

/// <summary>
/// Issue 16's measure: every corpus program checks without errors under the default profile (fanuc-mill), or its
/// remaining errors are named here with the reason the program really is wrong for that machine.
/// </summary>
public class CorpusUnderDefaultProfileTests(ITestOutputHelper output)
{
    /// <summary>The errors a program keeps under fanuc-mill, as code x count, and why they are right.</summary>
    private static readonly Dictionary<string, (string Errors, string Why)> Remaining = new()
    {
        ["pete-restall__Cluck2Sesame-Prototype__Enclosure.nc"] = ("E102x8",
            "LinuxCNC o-word subroutines: 'O100 sub', 'O100 endsub', 'O100 call' (lines 816-829, 1020, 1022). A FANUC control reads " +
            "O100 as a program number and 'sub' as three addresses without values; no profile here reads o-words (the message says so)."),
        ["enier290188__cnc__mill_hp_2.nc"] = ("E132x1",
            "G41 D01 (line 27) names a cutter radius the default profile has no table for: a machine's profile gives toolRadii. " +
            "With one it checks clean: its entry (line 27) is followed by an inside corner (line 28), which the host takes as " +
            "rs274ngc does, moving the entry's end back."),
        ["danheeks__voxelcut__gr105.tap"] = ("E101x4, E104x4, E115x92, E116x3, E124x7",
            "an older ISO dialect, not FANUC: 'T1//15.98' tool-table lines (E101, named so), G71 for millimetres (E104: FANUC milling has " +
            "G21), and G74 meaning single-quadrant arcs whose I/J are unsigned, so FANUC's incremental signed centres miss the end " +
            "point (E115); FANUC's G74 is the left-hand tapping cycle, so the positioning blocks after it are holes without Z and feed (E124, E116)."),
    };

    [SkippableFact]
    public void Every_corpus_program_checks_clean_under_the_default_profile_or_its_errors_are_named()
    {
        var files = Requires.Corpus();
        files.Should().HaveCount(12);
        var checker = new Checker(MachineProfile.Default);
        foreach (var file in files)
        {
            var name = Path.GetFileName(file);
            var diags = new List<Diagnostic>();
            var summary = checker.CheckFile(file, diags.Add);
            var errors = string.Join(", ", diags.Where(d => d.Severity == Severity.Error).GroupBy(d => d.Code).OrderBy(g => g.Key, StringComparer.Ordinal).Select(g => $"{g.Key}x{g.Count()}"));
            output.WriteLine($"{name}: {summary}; not yet on the controller: {string.Join(' ', summary.NotYetCodes.Keys)}");
            if (Remaining.TryGetValue(name, out var expected))
            {
                errors.Should().Be(expected.Errors, $"{name}: {expected.Why}");
                if (name.Contains("Enclosure", StringComparison.Ordinal))
                {
                    diags.Where(d => d.Severity == Severity.Error).Should().OnlyContain(d => d.Message.Contains("is a LinuxCNC o-word (subroutine or flow control)"),
                        "each error names the o-word construct, not a malformed number");
                }
                else if (name.Contains("gr105", StringComparison.Ordinal))
                {
                    diags.Where(d => d.Code == DiagnosticCodes.IllegalCharacter).Should().OnlyContain(d => d.Message.Contains("tool-table entry of an older ISO dialect"),
                        "each T1//15.98 line is named for what it is");
                }
            }
            else
            {
                errors.Should().BeEmpty($"{name} is a real program for a FANUC-style mill: " +
                    string.Join(" | ", diags.Where(d => d.Severity == Severity.Error).Take(5).Select(d => d.Format(name))));
            }
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
