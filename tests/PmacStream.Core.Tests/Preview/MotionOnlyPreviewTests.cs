using PmacStream.GCode;
using PmacStream.Preview;

namespace PmacStream.Core.Tests.Preview;

/// <summary>
/// What the preview draws is motion only, where the interpreter puts it: data blocks (G10, G52, G92) are not moves,
/// work offsets and the G52/G92 shifts apply, cycle holes are drawn hole by hole, rotary axes are named as not drawn.
/// </summary>
public sealed class MotionOnlyPreviewTests : IDisposable
{
    private readonly TestFolder _temp = new("preview-motion");

    public void Dispose() => _temp.Dispose();

    private GCodeToolpathSource Source(string program, MachineProfile? profile = null)
    {
        var path = Path.Combine(_temp.Path, "p.nc");
        File.WriteAllText(path, program);
        return new GCodeToolpathSource(path, profile);
    }

    private static List<PathSegment> Read(GCodeToolpathSource s) => s.ReadSegments().ToList();

    [Fact]
    public void A_work_offset_set_by_G10_is_where_the_path_is_drawn_and_the_G10_is_no_move()
    {
        var segments = Read(Source("G21 G90 G17\nG10 L2 P2 X0 Y-101.6 Z0\nG55\nG00 X10 Y10 Z5\nG01 Z-1 F100\nG01 X20\nM30\n"));

        segments.Should().HaveCount(2, "the G10 line sets an offset and the first G00 only says where the tool is");
        segments[0].Should().Be(PathSegment.Line(new Point3(10, -91.6, 5), new Point3(10, -91.6, -1), rapid: false, sourceLine: 5));
        segments[1].End.Should().Be(new Point3(20, -91.6, -1), "G55 is 101.6 mm down in Y");
        segments.Should().NotContain(s => s.SourceLine == 2, "a data block draws nothing");
    }

    [Fact]
    public void G52_and_G92_shift_what_follows_and_their_words_are_not_positions()
    {
        // G92 makes the tool at X20 read as X0: X5 is then machine X25. G52 then shifts by 100 in Y.
        var segments = Read(Source("G21 G90\nG00 X0 Y0 Z0\nG01 X20 F100\nG92 X0 Y0\nG01 X5\nG92.1\nG52 Y100\nG01 X0 Y0\nG52 Y0\nM30\n"));

        segments.Select(s => (s.SourceLine, s.End)).Should().Equal(
            (3L, new Point3(20, 0, 0)),
            (5L, new Point3(25, 0, 0)),
            (8L, new Point3(0, 100, 0)));
    }

    [Fact]
    public void A_drilling_cycle_is_drawn_hole_by_hole_down_to_its_bottom()
    {
        var segments = Read(Source("G21 G90 G17\nG00 X0 Y0 Z10\nG99 G81 X10 Y10 Z-5 R2 F100\nX20\nG80\nM30\n"));

        var holes = segments.Where(s => s.SourceLine is 3 or 4).ToList();
        holes.Should().HaveCount(8, "two holes, four strokes each");
        holes.Where(s => s.Motion == PathMotion.Linear).Select(s => (s.Start, s.End)).Should().Equal(
            (new Point3(10, 10, 2), new Point3(10, 10, -5)),
            (new Point3(20, 10, 2), new Point3(20, 10, -5)));
        holes.Should().OnlyContain(s => s.Motion == PathMotion.Linear || s.Motion == PathMotion.Rapid);
        holes[^1].End.Should().Be(new Point3(20, 10, 2), "G99 returns to the R level");
        holes[0].Start.Should().Be(new Point3(0, 0, 10), "from where the tool was, at its height");
    }

    [Fact]
    public void Rotary_words_are_named_and_the_moves_are_drawn_in_X_Y_Z()
    {
        var source = Source("G21 G90\nG00 X0 Y0 Z0 A0\nG01 X10 A90 F100\nG01 Y10 B5\nM30\n");
        var segments = Read(source);
        segments.Should().HaveCount(2);
        source.RotaryAxes.Should().Be("AB");
        Read(Source("G21 G90\nG00 X0 Y0\nG01 X10 F100\n")).Should().HaveCount(1);
    }

    [Fact]
    public void The_legend_says_how_rotary_axes_are_drawn()
    {
        // The same path with and without an A axis: the legend's first line is longer by the note.
        int LegendInk(string program)
        {
            var source = Source(program);
            using var picture = PreviewRenderer.Render(source, new PreviewOptions { Width = 900, Height = 600 });
            picture.Extents.Moves.Should().Be(2);
            var ink = 0;
            for (var y = 600 - 80; y < 600; y++)
            {
                for (var x = 0; x < 900; x++)
                {
                    var c = picture.Image.GetPixel(x, y);
                    ink += c.Red + c.Green + c.Blue < 300 ? 1 : 0;
                }
            }

            return ink;
        }

        var plain = LegendInk("G21 G90\nG00 X0 Y0 Z0\nG01 X10 F100\nG01 Y10\nM30\n");
        var rotary = LegendInk("G21 G90\nG00 X0 Y0 Z0 A0\nG01 X10 A90 F100\nG01 Y10\nM30\n");
        rotary.Should().BeGreaterThan(plain + 100, "the legend names the rotary axis it does not draw");
        string.Format(System.Globalization.CultureInfo.InvariantCulture, LegendText.Get(LegendTextId.Rotary, chinese: false), "A").Should().Be("A: rotary, not drawn (X Y Z shown)");
        LegendText.Get(LegendTextId.Rotary, chinese: true).Should().Contain("旋转轴");
    }
}
