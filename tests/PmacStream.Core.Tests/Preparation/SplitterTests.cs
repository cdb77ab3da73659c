using System.Text;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

public class SplitterTests
{
    private static List<string> BodyOf(string source, SplitOptions? options = null)
    {
        options ??= new SplitOptions { ProgramTail = "" };
        using var tp = new TempProgram(source);
        var r = tp.Split(options);
        return ChunkText.Body(r, options);
    }

    [Fact]
    public void Chunk_starts_with_close_open_rot_and_ends_with_close()
    {
        using var tp = new TempProgram("G01 X1\nG01 X2\nG01 X3\n");
        var r = tp.Split(new SplitOptions { BlocksPerChunk = 2, ProgramTail = "M05" });
        r.Manifest.Chunks.Should().HaveCount(2);
        File.ReadAllText(r.ChunkPaths.First()).Should().Be("CLOSE\r\nOPEN ROT\r\nM0==1 G01 X1 F(P500)\r\nM0==2 G01 X2 F(P500)\r\nCLOSE\r\n");
        File.ReadAllText(r.ChunkPaths.Last()).Should().Be("CLOSE\r\nOPEN ROT\r\nM0==3 G01 X3 F(P500)\r\nM05\r\nCLOSE\r\n");
        r.Manifest.Chunks[0].FileName.Should().Be("prog_0001.pmc");
        r.Manifest.Chunks[1].FileName.Should().Be("prog_0002.pmc");
    }

    [Fact]
    public void G_codes_written_after_the_axis_words_go_first_so_the_move_runs_in_their_mode()
    {
        // "Z0.3 G00" is a rapid (a block's G codes apply to its move); on the controller G00 is a call that runs where it
        // stands, so written after Z it would feed Z at the old mode and make only the next move a rapid.
        var checkedSplit = new SplitOptions { ProgramTail = "", CheckProfile = MachineProfile.Default };
        BodyOf("O1\nG01 X1 F100\nZ0.3 G00\nX1 Y2 G01 G91\nG01 X3\n", checkedSplit).Should().Equal(
            "G99.9", "P500=100", "M0==2 G01 X1 F(P500)", "M0==3 G00 Z0.3 F(P500)", "M0==4 G01 G91 X1 Y2 F(P500)", "M0==5 G01 X3 F(P500)");

        // Blocks that write their G codes first are written as they are.
        BodyOf("G00 X1 Y2\nG01 G91 Z-1 F50\n").Should().Equal("M0==1 G00 X1 Y2 F(P500)", "P500=50", "M0==2 G01 G91 Z-1 F(P500)");
    }

    [Fact]
    public void Comments_with_chinese_text_are_removed_in_utf8_and_gbk()
    {
        BodyOf("G01 X1 (粗加工 刀具 T1) Y2 ; 注释\n(只有注释)\n").Should().Equal("M0==1 G01 X1 Y2 F(P500)");

        // GBK bytes of "粗加工" inside a comment.
        var gbk = new byte[] { 0xB4, 0xD6, 0xBC, 0xD3, 0xB9, 0xA4 };
        var bytes = Encoding.ASCII.GetBytes("G01 X1 (").Concat(gbk).Concat(Encoding.ASCII.GetBytes(")\n")).ToArray();
        using var tp = new TempProgram(bytes);
        var r = tp.Split(new SplitOptions { ProgramTail = "" });
        File.ReadAllBytes(r.ChunkPaths.Single()).Should().OnlyContain(b => b < 128);
        ChunkText.Body(r, new SplitOptions { ProgramTail = "" }).Should().Equal("M0==1 G01 X1 F(P500)");
    }

    [Fact]
    public void A_word_the_check_reports_unused_is_not_written_forced_or_not()
    {
        // A PMAC does not ignore a stray Q on a motion line (W003 says the block does not use it): it is left out.
        // (G99.9: the library's power-on state, sent before the first block when a profile's conversions run.)
        const string src = "O1\nG01 X2 Q7 F100\nG04 P200 Y3\nM05 P2\nG00 X1 R5\n";
        var checkedSplit = new SplitOptions { ProgramTail = "", CheckProfile = MachineProfile.Default };
        string[] expected = ["G99.9", "P500=100", "M0==2 G01 X2 F(P500)", "M0==3 G04 P200", "M05", "M0==5 G00 X1 F(P500)"];
        BodyOf(src, checkedSplit).Should().Equal(expected);
        BodyOf(src, checkedSplit with { AllowErrors = true }).Should().Equal(expected);

        // Without a profile nothing is checked and the words are written as they are.
        BodyOf(src).Should().Contain("M0==2 G01 X2 Q7 F(P500)");
    }

    [Fact]
    public void Tape_marks_program_numbers_and_empty_lines_are_dropped()
    {
        BodyOf("%\nO1001 (PART)\n:1002\n\n   \nG90\n%\n").Should().Equal("G90");
    }

    [Fact]
    public void Block_delete_skips_slash_blocks_when_on_and_runs_them_when_off()
    {
        const string src = "G01 X1\n/G01 X2\n/1 M08\nG01 X3\n";
        BodyOf(src).Should().Equal("M0==1 G01 X1 F(P500)", "M0==4 G01 X3 F(P500)");
        BodyOf(src, new SplitOptions { BlockDelete = false, ProgramTail = "" })
            .Should().Equal("M0==1 G01 X1 F(P500)", "M0==2 G01 X2 F(P500)", "M08", "M0==4 G01 X3 F(P500)");
    }

    [Fact]
    public void N_numbers_are_dropped_by_default_and_kept_first_with_keep_n()
    {
        const string src = "N10 G01 X1\nN20\nG90 N30\n";
        BodyOf(src).Should().Equal("M0==1 G01 X1 F(P500)", "G90");
        BodyOf(src, new SplitOptions { KeepN = true, ProgramTail = "" }).Should().Equal("N10 M0==1 G01 X1 F(P500)", "N30 G90");
    }

    [Fact]
    public void Exact_tracking_precedes_the_move_and_paper_tracking_follows_it()
    {
        const string src = "G90\nG01 X1 Y2\nG04 P500\n";
        BodyOf(src).Should().Equal("G90", "M0==2 G01 X1 Y2 F(P500)", "M0==3 G04 P500");
        BodyOf(src, new SplitOptions { Tracking = TrackingPlacement.Paper, TrackVariable = "M100", ProgramTail = "" })
            .Should().Equal("G90", "G01 X1 Y2 F(P500) M100==2", "G04 P500 M100==3");
    }

    [Fact]
    public void Paper_feed_carries_programmed_f_into_the_feed_variable()
    {
        BodyOf("G01 X1 F300.\nF1200\nG01 X2\nG00 Z5\n").Should().Equal(
            "P500=300.", "M0==1 G01 X1 F(P500)", "P500=1200", "M0==3 G01 X2 F(P500)", "M0==4 G00 Z5 F(P500)");
    }

    [Fact]
    public void Paper_feed_sets_the_feed_variable_only_where_the_feed_changes()
    {
        // CAM posts repeat F on every feed move; a P500= line for each doubled the chunk's lines.
        BodyOf("G01 X1 F300.\nG01 X2 F300\nF300.0\nG01 X3 F300.\nG01 X4 F250\nG01 X5 F300\n").Should().Equal(
            "P500=300.", "M0==1 G01 X1 F(P500)", "M0==2 G01 X2 F(P500)", "M0==4 G01 X3 F(P500)",
            "P500=250", "M0==5 G01 X4 F(P500)", "P500=300", "M0==6 G01 X5 F(P500)");
        using var tp = new TempProgram("G01 X1 F300.\nF300\nG01 X2\n");
        tp.Split(new SplitOptions { ProgramTail = "" }).Manifest.TotalBlocks.Should().Be(2, "an F-only line that repeats the feed is no block");
    }

    [Fact]
    public void Block_skip_inside_a_block_and_the_end_of_the_tape_follow_the_reader()
    {
        const string src = "%\nG01 X1 /Y2 F100\nG01 X3\nM30\n%\nG01 X999 (after the end of the tape)\n";
        BodyOf(src).Should().Equal("M0==2 G01 X1 F(P500)", "M0==3 G01 X3 F(P500)", "M30");
        BodyOf(src, new SplitOptions { BlockDelete = false, ProgramTail = "" })
            .Should().Equal("P500=100", "M0==2 G01 X1 Y2 F(P500)", "M0==3 G01 X3 F(P500)", "M30");
    }

    [Fact]
    public void Override_feed_keeps_f_words()
    {
        BodyOf("G01 X1 F300.\nF1200\n", new SplitOptions { Feed = FeedMode.Override, ProgramTail = "" })
            .Should().Equal("M0==1 G01 X1 F300.", "F1200");
    }

    [Fact]
    public void Words_are_upper_case_packed_plus_signs_dropped()
    {
        BodyOf("g0x1.y+2.5z  -.5\n").Should().Equal("M0==1 G0 X1. Y2.5 Z-.5 F(P500)");
    }

    [Fact]
    public void Data_settings_are_not_motion_blocks()
    {
        using var tp = new TempProgram("G92 X0 Y0\nG10 L20 P1 X0\nG01 X1\nG04 X1.5\nM03 S1000\n");
        var r = tp.Split(new SplitOptions { ProgramTail = "" });
        r.Manifest.TotalBlocks.Should().Be(5);
        r.Manifest.TotalMotionBlocks.Should().Be(2);
        ChunkText.Body(r, new SplitOptions { ProgramTail = "" }).Should().Equal(
            "G92 X0 Y0", "G10 L20 P1 X0", "M0==3 G01 X1 F(P500)", "M0==4 G04 X1.5", "M03 S1000");
    }

    [Fact]
    public void Program_tail_goes_before_the_end_code_or_at_the_end()
    {
        using var tp = new TempProgram("G01 X1\nM30\n%\n");
        var r = tp.Split(new SplitOptions { ProgramTail = "M03 M05" });
        ChunkText.Lines(r.ChunkPaths.Single()).Should().Equal("CLOSE", "OPEN ROT", "M0==1 G01 X1 F(P500)", "M03 M05", "M30", "CLOSE");
        r.Manifest.ProgramTail.Should().Be("M03 M05");

        using var tp2 = new TempProgram("G01 X1\n");
        var r2 = tp2.Split();
        ChunkText.Lines(r2.ChunkPaths.Single()).Should().Equal("CLOSE", "OPEN ROT", "M0==1 G01 X1 F(P500)", "M05", "CLOSE");
    }

    [Fact]
    public void Single_block_too_big_is_an_error_naming_its_line_and_writes_nothing()
    {
        var longLine = "G01 " + string.Join(' ', Enumerable.Range(0, 40).Select(i => $"X{i}.123456"));
        using var tp = new TempProgram($"G90\nG01 X1\n{longLine}\n");
        var act = () => tp.Split(new SplitOptions { RotWords = 30, BytesPerWord = 8 });
        var e = act.Should().Throw<SplitException>().Which;
        e.Message.Should().Contain(":3:");
        e.Diagnostics.Should().ContainSingle().Which.Should().Match<Diagnostic>(d => d.Line == 3 && d.Code == SplitDiagnosticCodes.BlockTooBig);
        Directory.Exists(tp.OutDir).Should().BeFalse();
        Directory.GetFileSystemEntries(tp.Folder).Should().Equal(tp.SourcePath);
    }

    [Fact]
    public void Word_budget_also_closes_chunks()
    {
        // 5 blocks of 8 values each (M0, G, X, Y, Z, I, J, F) with 20 words per chunk: 2 per chunk.
        var src = string.Concat(Enumerable.Range(1, 5).Select(i => $"G02 X{i} Y{i} Z0 I1 J1\n"));
        using var tp = new TempProgram(src);
        var r = tp.Split(new SplitOptions { RotWords = 20, BytesPerWord = 100, ProgramTail = "" });
        r.Manifest.Chunks.Select(c => c.BlockCount).Should().Equal(2, 2, 1);
        r.Manifest.Chunks.Should().OnlyContain(c => c.EstimatedWords <= 20);
    }

    [Fact]
    public void Program_with_errors_is_refused_with_its_errors_unless_forced()
    {
        using var tp = new TempProgram("G01 X1\nG01 X1#2\nG01 Y2..5\nG01 X3\n");
        var act = () => tp.Split();
        var e = act.Should().Throw<SplitException>().Which;
        e.ErrorCount.Should().Be(2);
        e.Diagnostics.Select(d => (d.Line, d.Code)).Should().Equal((2, DiagnosticCodes.IllegalCharacter), (3, DiagnosticCodes.MalformedNumber));
        Directory.Exists(tp.OutDir).Should().BeFalse();

        var r = tp.Split(new SplitOptions { AllowErrors = true, ProgramTail = "" });
        var body = ChunkText.Body(r, new SplitOptions { ProgramTail = "" });
        body.Should().HaveCount(4);
        body.Should().OnlyContain(l => !l.Contains('#') && !l.Contains(".."));
    }

    [Fact]
    public void Failure_injected_mid_way_leaves_no_chunk_folder()
    {
        var src = string.Concat(Enumerable.Range(1, 50).Select(i => $"G01 X{i}\n"));
        using var tp = new TempProgram(src);
        var act = () => tp.Split(new SplitOptions { BlocksPerChunk = 5, AfterChunkWritten = i => { if (i == 3) { throw new IOException("disk full (injected)"); } } });
        act.Should().Throw<IOException>().WithMessage("*injected*");
        Directory.GetFileSystemEntries(tp.Folder).Should().Equal(tp.SourcePath);
    }

    [Fact]
    public void Cancellation_mid_way_leaves_no_chunk_folder()
    {
        var src = string.Concat(Enumerable.Range(1, 50).Select(i => $"G01 X{i}\n"));
        using var tp = new TempProgram(src);
        using var cts = new CancellationTokenSource();
        var act = () => Splitter.Split(tp.SourcePath, new SplitOptions { OutDir = tp.OutDir, BlocksPerChunk = 5, AfterChunkWritten = i => { if (i == 2) { cts.Cancel(); } } },
            null, cts.Token);
        act.Should().Throw<OperationCanceledException>();
        Directory.GetFileSystemEntries(tp.Folder).Should().Equal(tp.SourcePath);
    }

    [Fact]
    public void Failed_resplit_keeps_the_previous_set_and_a_good_one_replaces_it()
    {
        using var tp = new TempProgram("G01 X1\nG01 X2\nG01 X3\n");
        var first = tp.Split(new SplitOptions { BlocksPerChunk = 1 });
        first.Manifest.Chunks.Should().HaveCount(3);

        var act = () => tp.Split(new SplitOptions { BlocksPerChunk = 1, AfterChunkWritten = _ => throw new IOException("injected") });
        act.Should().Throw<IOException>();
        ChunkManifest.Load(first.ManifestPath).Chunks.Should().HaveCount(3);
        Directory.GetFiles(tp.OutDir).Should().HaveCount(4);

        var second = tp.Split(new SplitOptions { BlocksPerChunk = 2 });
        second.Manifest.Chunks.Should().HaveCount(2);
        Directory.GetFiles(tp.OutDir).Should().HaveCount(3, "the old chunk files are gone");
        Directory.GetFileSystemEntries(tp.Folder).Should().BeEquivalentTo([tp.SourcePath, tp.OutDir]);
    }

    [Fact]
    public void Output_folder_holding_other_files_is_not_overwritten()
    {
        using var tp = new TempProgram("G01 X1\n");
        Directory.CreateDirectory(tp.OutDir);
        File.WriteAllText(Path.Combine(tp.OutDir, "precious.txt"), "x");
        var act = () => tp.Split();
        act.Should().Throw<IOException>().WithMessage("*precious.txt*");
        File.Exists(Path.Combine(tp.OutDir, "precious.txt")).Should().BeTrue();
    }

    [Fact]
    public void Default_output_folder_is_beside_the_source()
    {
        using var tp = new TempProgram("G01 X1\n", "part.nc");
        var r = Splitter.Split(tp.SourcePath);
        r.OutputDirectory.Should().Be(Path.Combine(tp.Folder, "part_chunks"));
        File.Exists(Path.Combine(tp.Folder, "part_chunks", "part_0001.pmc")).Should().BeTrue();
        File.Exists(Path.Combine(tp.Folder, "part_chunks", "manifest.json")).Should().BeTrue();
    }

    [Fact]
    public void Empty_program_is_an_error()
    {
        using var tp = new TempProgram("%\n(nothing)\n%\n");
        var act = () => tp.Split();
        act.Should().Throw<SplitException>().WithMessage("*no program blocks*");
    }

    [Theory]
    [InlineData("M0", "P500", 0)]
    [InlineData("P1", "P500", 2)]
    [InlineData("M0", "X500", 0)]
    public void Invalid_options_are_rejected(string track, string feed, int lines)
    {
        var o = new SplitOptions { TrackVariable = track, FeedVariable = feed, BlocksPerChunk = lines };
        o.Invoking(x => x.Validate()).Should().Throw<ArgumentException>();
    }

    [Fact]
    public void Demo_sample_splits_into_chunks_of_at_most_1000_blocks()
    {
        var sample = RepoRoot.DemoProgram;
        using var tp = new TempProgram(File.ReadAllBytes(sample), "demo.nc");
        var r = tp.Split();
        r.Manifest.Chunks.Should().OnlyContain(c => c.BlockCount <= 1000 && c.ByteSize <= 51200);
        r.Manifest.TotalBlocks.Should().BeGreaterThan(3000);
        r.Manifest.TotalMotionBlocks.Should().Be(ChunkText.Body(r, new SplitOptions()).Count(l => l.StartsWith("M0==", StringComparison.Ordinal)));
    }
}
