using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preview;
using static PmacStream.Core.Tests.Preview.PreviewTestKit;

namespace PmacStream.Core.Tests.Preview;

public sealed class ExecutedOverlayTests : IDisposable
{
    private readonly TestFolder _temp = new("exec");

    // Lines: 1 G21.., 2 G0 to the corner (positioning), 3..6 the square's edges.
    private const string Square = "G21 G90 G17\nG0 X0 Y0 Z0\nG1 X40 F100\nG1 Y40\nG1 X0\nG1 Y0\n";

    public void Dispose() => _temp.Dispose();

    private string WriteLog(params (long Line, double X, double Y)[] rows)
    {
        var path = Path.Combine(_temp.Path, $"exec-{Guid.NewGuid():N}.csv");
        var lines = new List<string> { ExecutedLogReader.Header };
        var seq = 0;
        foreach (var (line, x, y) in rows)
        {
            lines.Add(string.Create(CultureInfo.InvariantCulture, $"{++seq},{line},{seq * 0.5},{(seq + 1) * 0.5},{x},{y},0,0,0,0,linear"));
        }

        File.WriteAllLines(path, lines);
        return path;
    }

    [Fact]
    public void Exact_log_covers_every_edge_with_the_executed_band_and_reports_nothing()
    {
        var log = WriteLog((2, 0, 0), (3, 40, 0), (4, 40, 40), (5, 0, 40), (6, 0, 0));
        using var pic = RenderGCode(Square, PreviewView.XY, 300, 300, log: log);
        pic.Execution!.IsExact.Should().BeTrue();
        pic.Execution.LogRows.Should().Be(5);
        PixelsOf(pic.Image, Palette.Missing).Should().BeEmpty();
        PixelsOf(pic.Image, Palette.Repeated).Should().BeEmpty();

        // The band lies under the program line: 2 pixels beside each edge's middle is executed green,
        // while the edge itself stays in the feed colour on top.
        var (mx, my) = pic.Projection.ToPixel(new Point3(20, 0, 0));
        Is(pic.Image, (int)Math.Round(mx), (int)Math.Round(my), Palette.Feed, Palette.Executed).Should().BeTrue("the edge is drawn over the band");
        Is(pic.Image, (int)Math.Round(mx), (int)Math.Round(my) - 2, Palette.Executed).Should().BeTrue("the band is wider than the line");
        Is(pic.Image, (int)Math.Round(mx), (int)Math.Round(my) + 2, Palette.Executed).Should().BeTrue();
    }

    [Fact]
    public void Gap_and_double_are_coloured_and_listed()
    {
        // Line 4 (the right edge) never ran; line 5 ran again after line 6, as after a resume from the wrong line.
        var log = WriteLog((2, 0, 0), (3, 40, 0), (5, 0, 40), (6, 0, 0), (5, 0, 40));
        using var pic = RenderGCode(Square, PreviewView.XY, 300, 300, log: log);
        var report = pic.Execution!;
        report.IsExact.Should().BeFalse();
        report.MissingLines.Should().Be(1);
        report.Missing.Should().Equal(new LineRun(4, 4, 0));
        report.RepeatedLines.Should().Be(1);
        report.Repeated.Should().Equal(new LineRun(5, 5, 2));

        // The never-executed right edge is drawn in the missing colour.
        var (rx, ry) = pic.Projection.ToPixel(new Point3(40, 20, 0));
        Is(pic.Image, (int)Math.Round(rx), (int)Math.Round(ry), Palette.Missing).Should().BeTrue();
        // Having skipped line 4, the machine went straight from (40, 0) to (0, 40) for line 5: that executed
        // move, of a line run twice, is a repeated-colour band across the square where the program has nothing.
        var (tx, ty) = pic.Projection.ToPixel(new Point3(20, 20, 0));
        Is(pic.Image, (int)Math.Round(tx), (int)Math.Round(ty), Palette.Repeated).Should().BeTrue();
        // The bottom edge ran once.
        var (bx, by) = pic.Projection.ToPixel(new Point3(20, 0, 0));
        Is(pic.Image, (int)Math.Round(bx), (int)Math.Round(by) + 2, Palette.Executed).Should().BeTrue();
    }

    [Fact]
    public void Executed_arc_band_follows_the_arc_not_the_chord_of_the_logged_end_points()
    {
        // Line 3: a half circle of radius 20 about (0, 0) from (20, 0) to (-20, 0) through (0, 20).
        var log = WriteLog((2, 20, 0), (3, -20, 0));
        using var pic = RenderGCode("G21 G90 G17\nG0 X20 Y0 Z0\nG3 X-20 Y0 I-20 J0 F100\n", PreviewView.XY, 300, 300, log: log);
        var proj = pic.Projection;
        var (cx, cy) = proj.ToPixel(new Point3(0, 0, 0));
        var rpx = 20 * proj.Scale;
        foreach (var deg in new[] { 30, 60, 90, 120, 150 })
        {
            var a = deg * Math.PI / 180;
            // Two pixels outside the arc is band; the chord's middle (the centre) has none.
            var (bx, by) = (cx + ((rpx + 2) * Math.Cos(a)), cy - ((rpx + 2) * Math.Sin(a)));
            Near(pic.Image, bx, by, Palette.Executed, 1).Should().BeTrue($"the band runs along the arc at {deg} degrees");
        }

        pic.Image.GetPixel((int)Math.Round(cx), (int)Math.Round(cy) - 2).Should().Be(Palette.Background, "no chord is drawn through the centre");
        pic.Execution!.IsExact.Should().BeTrue();
    }

    [Fact]
    public void Runs_merge_consecutive_lines()
    {
        var program = "G21 G90\nG0 X0 Y0 Z0\n" + string.Concat(Enumerable.Range(1, 10).Select(i => $"G1 X{i} F100\n"));
        // Program lines 3..12 are the feeds. Execute 3..5, skip 6..9, execute 10..12, then 11 again, then 11 and 12
        // again; 4 split into two controller moves (consecutive rows) is still one execution.
        var rows = new List<(long, double, double)>();
        foreach (var line in new[] { 3, 4, 4, 5, 10, 11, 12, 11, 10, 11, 12 })
        {
            rows.Add((line, line - 2, 0));
        }

        var log = WriteLog(rows.ToArray());
        using var pic = RenderGCode(program, PreviewView.XY, 200, 200, log: log);
        pic.Execution!.Missing.Should().Equal(new LineRun(6, 9, 0));
        pic.Execution.MissingLines.Should().Be(4);
        pic.Execution.Repeated.Should().Equal(new LineRun(10, 10, 2), new LineRun(11, 11, 3), new LineRun(12, 12, 2));
        pic.Execution.RepeatedLines.Should().Be(3);
        pic.Execution.Missing[0].ToString().Should().Be("lines 6-9");
    }

    [Fact]
    public void Executed_moves_off_the_program_are_inside_the_picture()
    {
        var log = WriteLog((3, 40, 0), (4, 200, 200));
        using var pic = RenderGCode(Square, PreviewView.XY, 300, 300, log: log);
        var (x, y) = pic.Projection.ToPixel(new Point3(200, 200, 0));
        x.Should().BeInRange(0, 299);
        y.Should().BeInRange(0, 299);
        Near(pic.Image, x, y, Palette.Executed, 2).Should().BeTrue();
    }

    [Theory]
    [InlineData("seq,line,x\n1,2,3\n", "1:1", "expected the header")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,kind\n1,2,0,1,abc,0,0,linear\n", "2:", "column 'x' expects a number, found 'abc'")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,kind\n1,2,0,1,0,0\n", "2:1", "expected 8 comma-separated fields")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,a,b,c,kind\n1,2,0,1,0,0,0,linear\n", "2:1", "expected 11 comma-separated fields")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,a,b,c,kind\n1,2,0,1,0,0,0,0,x,0,linear\n", "2:", "column 'b' expects a number, found 'x'")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,kind\n-1,2,0,1,0,0,0,linear\n", "2:1", "column 'sequence' expects a whole number >= 0")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,kind\n1,2.5,0,1,0,0,0,linear\n", "2:3", "column 'line' expects a whole number")]
    [InlineData("sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block\n1,2,0,1,0,0,0,0,0,0,linear,yes\n", "2:", "column 'block' expects 1 or 0, found 'yes'")]
    public void Malformed_log_names_file_line_and_column(string content, string where, string what)
    {
        var path = Path.Combine(_temp.Path, "badlog.csv");
        File.WriteAllText(path, content);
        var act = () => ExecutedLogReader.Read(path).ToList();
        act.Should().Throw<InvalidDataException>()
            .Which.Message.Should().StartWith(Path.GetFileName(path) + ":" + where).And.Contain(what);
    }

    [Fact]
    public void Log_rows_parse_with_invariant_numbers()
    {
        var row = ExecutedLogReader.ParseRow("12,345,1.5,2.25,-1.5e1,2,3.125,circle", "log", 2, rotary: false);
        row.Should().Be(new ExecutedLogRow(12, 345, 1.5, 2.25, new Point3(-15, 2, 3.125), "circle"));
        ExecutedLogReader.ParseRow("12,345,1.5,2.25,-1.5e1,2,3.125,90,-45.5,0.25,circle", "log", 2)
            .Should().Be(new ExecutedLogRow(12, 345, 1.5, 2.25, new Point3(-15, 2, 3.125), "circle") { Rotary = (90, -45.5, 0.25) });
    }

    [Fact]
    public void A_log_with_the_block_column_is_read_with_each_move_s_block_mark()
    {
        using var folder = new TestFolder("block-log");
        var path = Path.Combine(folder.Path, "executed.csv");
        File.WriteAllText(path, ExecutedLogReader.BlockHeader + "\n1,7,0,1,1,2,3,0,0,0,Linear,1\n2,7,1,2,1,2,3,0,0,0,Dwell,0\n");
        ExecutedLogReader.Read(path).Select(r => (r.Line, r.Kind, r.BlockStart)).Should().Equal((7L, "Linear", (bool?)true), (7L, "Dwell", (bool?)false));
    }

    [Fact]
    public void Block_marks_count_a_one_move_block_run_twice_in_a_row_twice_and_a_block_s_further_moves_not()
    {
        var counts = new ExecutionCounts(new Dictionary<int, int> { [9] = 3 });
        counts.Add(5, true);
        counts.Add(5, true); // the same block again, straight after: its tracking assignment fired again
        counts.Add(7, true);
        counts.Add(7, false); // a further move of block 7 (a dwell, a library move)
        counts.Add(9, true); // a block the host sends as three controller lines, each with its assignment
        counts.Add(9, true);
        counts.Add(9, true);
        counts.Add(9, true); // then the block again
        counts[5].Should().Be(2);
        counts[7].Should().Be(1);
        counts[9].Should().Be(2);

        var old = new ExecutionCounts();
        old.Add(5);
        old.Add(5);
        old[5].Should().Be(1, "a log without the block column cannot tell a block run twice in a row from one block of two moves");
    }

    [Fact]
    public void The_preview_counts_a_block_run_twice_in_a_row_from_the_block_column_and_folds_an_old_log()
    {
        using var folder = new TestFolder("exec-block");
        var rows = new[] { (2, 0, 0, 1), (3, 40, 0, 1), (4, 40, 40, 1), (4, 40, 40, 1), (5, 0, 40, 1), (6, 0, 0, 1) };
        var withBlock = Path.Combine(folder.Path, "block.csv");
        File.WriteAllLines(withBlock, new[] { ExecutedLogReader.BlockHeader }.Concat(rows.Select((r, i) =>
            string.Create(CultureInfo.InvariantCulture, $"{i + 1},{r.Item1},{i},{i + 1},{r.Item2},{r.Item3},0,0,0,0,Linear,{r.Item4}"))));
        var old = Path.Combine(folder.Path, "old.csv");
        File.WriteAllLines(old, File.ReadAllLines(withBlock).Select((l, i) => i == 0 ? ExecutedLogReader.Header : l[..l.LastIndexOf(',')]));

        using (var pic = RenderGCode(Square, PreviewView.XY, 300, 300, log: withBlock))
        {
            pic.Execution!.Repeated.Should().Equal(new LineRun(4, 4, 2));
            pic.Execution.MissingLines.Should().Be(0);
        }

        using (var pic = RenderGCode(Square, PreviewView.XY, 300, 300, log: old))
        {
            pic.Execution!.IsExact.Should().BeTrue("consecutive rows of one line fold in a log without the block column");
        }
    }

    [Fact]
    public void A_canned_cycle_whose_controller_lines_each_mark_a_block_start_counts_once()
    {
        // Line 3 is a drilling cycle the program draws as several moves; the host sends each as a line with the
        // block's tracking assignment, so every one of its moves is marked.
        const string Cycle = "G21 G90 G17\nG0 X0 Y0 Z10\nG81 X10 Y0 Z-5 R2 F100\nG80\n";
        using var folder = new TestFolder("exec-cycle");
        var log = Path.Combine(folder.Path, "cycle.csv");
        File.WriteAllLines(log, [
            ExecutedLogReader.BlockHeader, "1,2,0,1,0,0,10,0,0,0,Rapid,1", "2,3,1,2,10,0,10,0,0,0,Rapid,1",
            "3,3,2,3,10,0,2,0,0,0,Rapid,1", "4,3,3,4,10,0,-5,0,0,0,Linear,1", "5,3,4,5,10,0,10,0,0,0,Rapid,1",
        ]);
        using var pic = RenderGCode(Cycle, PreviewView.XY, 300, 300, log: log);
        pic.Execution!.RepeatedLines.Should().Be(0);
        pic.Execution.MissingLines.Should().Be(0);
    }

    [Fact]
    public void Counts_saturate_and_grow_with_line_numbers()
    {
        var counts = new ExecutionCounts();
        for (var i = 0; i < 300; i++)
        {
            counts.Add(5);
            counts.Add(6);
        }

        counts.Add(1_000_000);
        counts.Add(1_000_000); // consecutive rows of one line: one execution
        counts.Add(0);
        counts.Add(-3);
        counts[5].Should().Be(255);
        counts[6].Should().Be(255);
        counts[1_000_000].Should().Be(1);
        counts[999_999].Should().Be(0);
        counts[0].Should().Be(0);
        counts[-3].Should().Be(0);
        counts.Rows.Should().Be(604);
        counts.MaxLine.Should().Be(1_000_000);
    }
}

public class ToolpathSourceTests
{
    private static List<PathSegment> Segments(string gcode, out GCodeToolpathSource source)
    {
        using var temp = new TestFolder("src");
        var path = Path.Combine(temp.Path, "src.nc");
        File.WriteAllText(path, gcode);
        source = new GCodeToolpathSource(path);
        return source.ReadSegments().ToList();
    }

    [Fact]
    public void Positioning_from_an_unknown_place_is_not_drawn()
    {
        var segs = Segments("G21 G90\nG0 Z10\nG0 X5 Y5\nG1 Z0 F100\n", out _);
        segs.Should().ContainSingle().Which.Should().Be(PathSegment.Line(new Point3(5, 5, 10), new Point3(5, 5, 0), false, 4));
    }

    [Fact]
    public void Inch_programs_are_drawn_in_millimetres_and_say_so()
    {
        var segs = Segments("G20 G90\nG0 X0 Y0 Z0\nG91 G1 X1 Y-2 F10\n", out var source);
        segs.Should().ContainSingle();
        segs[0].End.X.Should().BeApproximately(25.4, 1e-9);
        segs[0].End.Y.Should().BeApproximately(-50.8, 1e-9);
        source.Units.Should().Be(LengthUnits.Inches);
        source.MixedUnits.Should().BeFalse();
    }

    [Fact]
    public void Arc_segments_carry_plane_direction_and_centre()
    {
        var segs = Segments("G21 G90 G18\nG0 X10 Y1 Z0\nG2 X-10 Z0 I-10 K0 F100\nG19 G3 Y-19 Z0 J-10 K0\n", out var source);
        source.IssueCount.Should().Be(0);
        segs.Should().HaveCount(2);
        segs[0].Should().Be(PathSegment.Arc(new Point3(10, 1, 0), new Point3(-10, 1, 0), new Point3(0, 1, 0), ArcPlane.ZX, true, 3));
        segs[1].Plane.Should().Be(ArcPlane.YZ);
        segs[1].Motion.Should().Be(PathMotion.ArcCcw);
        segs[1].Center.Y.Should().Be(-9);
    }

    [Fact]
    public void Errors_are_reported_with_line_and_code_and_the_bad_arc_is_not_drawn()
    {
        var segs = Segments("G21 G90\nG0 X0 Y0 Z0\nG2 X10 Y10 F100\nG1 X20\n", out var source);
        source.IssueCount.Should().BeGreaterThan(0);
        source.Issues.Should().Contain(d => d.Line == 3 && d.Code == DiagnosticCodes.ArcWithoutCenter);
        segs.Should().ContainSingle().Which.SourceLine.Should().Be(4);
    }
}
