using System.Text;
using PmacStream.Preparation;

namespace PmacStream.IntegrationTests.Split;

/// <summary>The split and prog1000 commands, run in process through the CLI's parser and handlers.</summary>
public sealed class SplitCliTests : IDisposable
{
    private readonly TestFolder _temp = new("split-cli");

    public void Dispose() => _temp.Dispose();

    /// <summary>Runs the command line in process (<see cref="CliRun"/>): the same parser, handler and exit codes as the binary.</summary>
    private static (int Code, string Out, string Err) Run(params string[] args) => CliRun.InProcess(args);

    private string Write(string name, string text)
    {
        var path = Path.Combine(_temp.Path, name);
        File.WriteAllText(path, text, new UTF8Encoding(false));
        return path;
    }

    [Fact]
    public void Split_prints_the_summary_writes_chunks_and_exits_0()
    {
        var src = Write("part.nc", "%\nO1000 (零件)\nG21 G90 G17\n" + string.Concat(Enumerable.Range(1, 25).Select(i => $"N{i}0 G01 X{i}. Y{i}. F500.\n")) + "M30\n%\n");
        var outDir = Path.Combine(_temp.Path, "chunks");
        var (code, stdout, stderr) = Run("split", src, "--out", outDir, "--lines", "10", "--tracking", "paper", "--tail", "M03 M05");
        code.Should().Be(0, stderr);
        stdout.Should().Contain("3 chunks, 27 blocks, largest chunk ");
        var manifest = ChunkManifest.Load(Path.Combine(outDir, "manifest.json"));
        manifest.Tracking.Should().Be(TrackingPlacement.Paper);
        manifest.Chunks.Select(c => c.BlockCount).Should().Equal(10, 10, 7);
        manifest.TotalMotionBlocks.Should().Be(25);
        var last = File.ReadAllText(Path.Combine(outDir, "part_0003.pmc"));
        last.Should().EndWith("M03 M05\r\nM30\r\nCLOSE\r\n");
        File.ReadAllText(Path.Combine(outDir, "part_0001.pmc")).Should().Contain("G01 X1. Y1. F(P500) M0==4\r\n");
    }

    [Fact]
    public void Split_names_the_codes_the_controller_cannot_run_yet_and_sets_the_feed_only_where_it_changes()
    {
        var src = Write("real.nc", "%\nO1\nN10 (FACE1)\nG90 G94 G17 G49 G40 G80\nT1 M41\nS5000 M03\nG43 H1 Z15.\n" +
            string.Concat(Enumerable.Range(1, 6).Select(i => $"G01 X{i}. F{(i < 4 ? 800 : 400)}.\n")) + "G28 G91 Z0.\nM30\n%\n");
        var outDir = Path.Combine(_temp.Path, "real_chunks");
        var (code, stdout, stderr) = Run("split", src, "--out", outDir);
        code.Should().Be(0, stderr);
        stdout.Should().Contain("not runnable on the controller yet under profile 'fanuc-mill'").And.Contain("M41 (line 5)");
        var manifest = ChunkManifest.Load(Path.Combine(outDir, "manifest.json"));
        manifest.CheckedProfile.Should().StartWith("fanuc-mill@");
        manifest.NotYetCodes.Should().Equal(new Dictionary<string, int> { ["M41"] = 5 }, "G43 runs in the library and G28 is expanded by the host");
        var chunk = File.ReadAllText(Path.Combine(outDir, "real_0001.pmc"));
        chunk.Split("\r\n").Where(l => l.StartsWith("P500=", StringComparison.Ordinal)).Should().Equal("P500=800.", "P500=400.");
    }

    [Fact]
    public void Split_refuses_a_program_with_errors_naming_them_and_exits_1_unless_forced()
    {
        var src = Write("bad.nc", "G21 G90\nG01 X1 F100\nG01 X$2\nG01 X3\nM30\n");
        var outDir = Path.Combine(_temp.Path, "bad_chunks");
        var (code, _, stderr) = Run("split", src, "--out", outDir);
        code.Should().Be(1);
        stderr.Should().Contain("bad.nc:3:").And.Contain("not split");
        Directory.Exists(outDir).Should().BeFalse();

        var forced = Run("split", src, "--out", outDir, "--force");
        forced.Code.Should().Be(0, forced.Err);
        Directory.Exists(outDir).Should().BeTrue();
    }

    [Fact]
    public void Split_checks_in_its_own_pass_refusing_checker_errors_with_line_and_column_and_leaving_nothing()
    {
        // Lexically fine, so chunks get written before the checker's errors (an unknown G code, a letter the
        // profile does not use) are known: the hidden folder must go too, and the messages are the checker's.
        var body = string.Concat(Enumerable.Range(2, 3000).Select(i => $"N{i} G01 X{i}.5 F100\n"));
        var src = Write("late.nc", "O1\n" + body + "N3002 G05 X2\nN3003 G00 X1 Q5\nM30\n");
        var outDir = Path.Combine(_temp.Path, "late_chunks");
        var (code, _, stderr) = Run("split", src, "--out", outDir, "--lines", "100", "--profile", "paper-24g7m");
        code.Should().Be(1, stderr);
        stderr.Should().Contain("late.nc:3002:7").And.Contain("E104").And.Contain("late.nc:3003:14").And.Contain("E118")
            .And.Contain("2 error(s) under profile 'paper-24g7m'; not split (--force splits anyway)");
        Directory.GetFileSystemEntries(_temp.Path).Should().Equal(src);

        var forced = Run("split", src, "--out", outDir, "--lines", "100", "--force", "--profile", "paper-24g7m");
        forced.Code.Should().Be(0, forced.Err);
        forced.Out.Should().Contain("31 chunks, 3003 blocks");
    }

    [Fact]
    public void Split_takes_the_chunk_shape_of_a_settings_file_as_stream_does_and_options_override_it()
    {
        var src = Write("part.nc", "G21 G90 G17\n" + string.Concat(Enumerable.Range(1, 25).Select(i => $"G01 X{i}. Y{i}. F500.\n")) + "M30\n");
        var settings = Write("settings.json", """{ "blocksPerChunk": 10, "tracking": "paper", "programTail": "M03 M05", "windowStart": 0.5 }""");
        var outDir = Path.Combine(_temp.Path, "chunks");
        var (code, _, stderr) = Run("split", src, "--out", outDir, "--settings", settings);
        code.Should().Be(0, stderr);
        stderr.Should().BeEmpty();
        var manifest = ChunkManifest.Load(Path.Combine(outDir, "manifest.json"));
        manifest.Shape.Should().Be(ChunkShape.Default with { BlocksPerChunk = 10, Tracking = TrackingPlacement.Paper, ProgramTail = "M03 M05" });
        manifest.Chunks.Select(c => c.BlockCount).Should().Equal(10, 10, 7);
        File.ReadAllText(Path.Combine(outDir, "part_0003.pmc")).Should().EndWith("M03 M05\r\nM30\r\nCLOSE\r\n");

        // An option given on the command line wins over the file; the old name --lines still works, with a warning.
        (code, _, stderr) = Run("split", src, "--out", outDir, "--settings", settings, "--lines", "20");
        code.Should().Be(0, stderr);
        stderr.Should().Contain("warning: --lines is now --blocks-per-chunk");
        manifest = ChunkManifest.Load(Path.Combine(outDir, "manifest.json"));
        (manifest.Shape!.BlocksPerChunk, manifest.Shape.Tracking).Should().Be((20, TrackingPlacement.Paper));
        manifest.Chunks.Select(c => c.BlockCount).Should().Equal(20, 7);

        // A bad shape in the file is reported where it is, as stream reports it.
        var bad = Write("bad.json", "{\n  \"blocksPerChunk\": 0\n}");
        (code, _, stderr) = Run("split", src, "--out", outDir, "--settings", bad, "--blocks-per-chunk", "5");
        code.Should().Be(2);
        stderr.Should().StartWith($"{bad}:2:21: error R003: blocks per chunk must be at least 1");
    }

    [Fact]
    public void Split_usage_and_io_errors_exit_2()
    {
        Run("split", Path.Combine(_temp.Path, "missing.nc")).Code.Should().Be(2);
        var src = Write("ok.nc", "G01 X1\n");
        Run("split", src, "--lines", "0").Code.Should().Be(2);
        Run("split", src, "--tracking", "sideways").Code.Should().Be(2);
        Run("split", src, "--track-var", "P7").Code.Should().Be(2);
    }

    [Fact]
    public void Split_of_a_block_bigger_than_a_chunk_exits_1_naming_the_line()
    {
        var src = Write("big.nc", "G21 G90\nG01 X1.123456 Y2.123456 Z3.123456 F100\n");
        var (code, _, stderr) = Run("split", src, "--rot-words", "6", "--words-per-block", "1", "--out", Path.Combine(_temp.Path, "big_chunks"));
        code.Should().Be(1);
        stderr.Should().Contain("big.nc:2:").And.Contain("does not fit one chunk");
        Directory.Exists(Path.Combine(_temp.Path, "big_chunks")).Should().BeFalse();
    }

    [Fact]
    public void Prog1000_writes_the_library_file()
    {
        var target = Path.Combine(_temp.Path, "lib.pmc");
        var (code, stdout, stderr) = Run("prog1000", "--out", target);
        code.Should().Be(0, stderr);
        stdout.Should().Contain("routines");
        var text = File.ReadAllText(target);
        text.Should().Contain("OPEN PROG 1000 CLEAR\r\n").And.Contain("OPEN PROG 1001 CLEAR\r\n").And.Contain("N1000 LINEAR Q31=1 RET\r\n").And.Contain("N54000 Q20=1 GOSUB99100 RET\r\n");
        text.TrimEnd().Split("\r\n")[^1].Should().MatchRegex(@"^P7000=1 P7001=\d+$", "the library ends by recording which it is");
        Run("prog1000", "--profile", Path.Combine(_temp.Path, "nope.json")).Code.Should().Be(2);
    }

    [Fact]
    public void Machine_shows_the_tables_with_their_variables_and_writes_the_lines_that_download_them()
    {
        var profile = Path.Combine(_temp.Path, "machine.json");
        File.WriteAllText(profile, Streaming.PositionProofTests.Machine().ToJson());
        var (code, stdout, stderr) = Run("machine", "--profile", profile);
        code.Should().Be(0, stderr);
        stdout.Should().Contain("  G55  X100 Y50 Z-10  (P7106-P7108)\n").And.Contain("  H3  47.5  (P7303)\n")
            .And.Contain("  G30  X-100 Y-50 Z-20\n").And.Contain("tool change position: X-150 Y-80 Z0  (P7010-P7012)\n");
        Run("machine").Out.Should().Contain("tool lengths: none", "the built-in profile has no tool table");

        var target = Path.Combine(_temp.Path, "tables.pmc");
        Run("machine", "--profile", profile, "--lines", "--out", target).Code.Should().Be(0);
        var lines = File.ReadAllLines(target);
        lines.Should().Contain("P7106=100 P7107=50 P7108=-10").And.Contain("P7303=47.5").And.Contain("P7010=-150 P7011=-80 P7012=0");
        File.Exists(target + ".tmp").Should().BeFalse();
        Run("machine", "--profile", Path.Combine(_temp.Path, "nope.json")).Code.Should().Be(2);
    }
}
