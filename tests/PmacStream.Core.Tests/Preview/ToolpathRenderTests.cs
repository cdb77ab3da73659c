using PmacStream.GCode;
using PmacStream.Preview;
using SkiaSharp;
using static PmacStream.Core.Tests.Preview.PreviewTestKit;

namespace PmacStream.Core.Tests.Preview;

public class ToolpathRenderTests
{
    private static readonly SKColor Feed = Palette.Feed;
    private static readonly SKColor Rapid = Palette.Rapid;

    [Fact]
    public void Square_has_pixels_on_every_edge_and_none_inside()
    {
        using var pic = RenderGCode("G21 G17 G90\nG0 X0 Y0 Z0\nG1 X50 F100\nY50\nX0\nY0\n", PreviewView.XY, 300, 300);
        var img = pic.Image;
        var proj = pic.Projection;
        var (x0, y0) = proj.ToPixel(new Point3(0, 0, 0));
        var (x1, y1) = proj.ToPixel(new Point3(50, 50, 0));
        (x1 - x0).Should().BeApproximately(50 * proj.Scale, 1e-9);
        y1.Should().BeLessThan(y0, "Y points up in the XY view");

        for (var t = 0.0; t <= 1.0; t += 0.05)
        {
            foreach (var p in new[] { new Point3(50 * t, 0, 0), new Point3(50, 50 * t, 0), new Point3(50 * t, 50, 0), new Point3(0, 50 * t, 0) })
            {
                var (px, py) = proj.ToPixel(p);
                Is(img, (int)Math.Round(px), (int)Math.Round(py), Feed).Should().BeTrue($"the edge point {p} is drawn");
            }
        }

        // Nothing inside the square (one pixel in from each edge) and nothing outside it: the antialiased edges
        // show mostly in the pixels within half a pixel of the ideal line.
        var feedPixels = PixelsOf(img, Feed);
        feedPixels.Should().OnlyContain(p => Math.Abs(p.X - x0) < 0.6 || Math.Abs(p.X - x1) < 0.6 || Math.Abs(p.Y - y0) < 0.6 || Math.Abs(p.Y - y1) < 0.6);
        feedPixels.Should().OnlyContain(p => p.X >= x0 - 0.6 && p.X <= x1 + 0.6 && p.Y >= y1 - 0.6 && p.Y <= y0 + 0.6);
        PixelsOf(img, Rapid).Should().BeEmpty("the only rapid starts from an unknown position and is not drawn");
        pic.Extents.Min.Should().Be(new Point3(0, 0, 0));
        pic.Extents.Max.Should().Be(new Point3(50, 50, 0));
        pic.Extents.Lines.Should().Be(4);
    }

    public static TheoryData<string, PreviewView, string, double, double> FullCircles => new()
    {
        // plane, view, program (start on the circle, full turn), centre (u, v) in the view, radius
        { "G17 G2", PreviewView.XY, "G17\nG0 X30 Y5 Z7\nG2 X30 Y5 I-20 J0 F100\n", 10, 5 },
        { "G17 G3", PreviewView.XY, "G17\nG0 X30 Y5 Z7\nG3 X30 Y5 I-20 J0 F100\n", 10, 5 },
        { "G18 G2", PreviewView.XZ, "G18\nG0 X10 Y7 Z25\nG2 X10 Z25 I0 K-20 F100\n", 10, 5 },
        { "G18 G3", PreviewView.XZ, "G18\nG0 X30 Y7 Z5\nG3 X30 Z5 I-20 K0 F100\n", 10, 5 },
        { "G19 G2", PreviewView.YZ, "G19\nG0 X7 Y30 Z5\nG2 Y30 Z5 J-20 K0 F100\n", 10, 5 },
        { "G19 G3", PreviewView.YZ, "G19\nG0 X7 Y10 Z25\nG3 Y10 Z25 J0 K-20 F100\n", 10, 5 },
    };

    [Theory]
    [MemberData(nameof(FullCircles))]
    public void Full_circle_in_each_plane_lies_on_its_radius_all_the_way_round(string name, PreviewView view, string program, double cu, double cv)
    {
        const double radius = 20;
        using var pic = RenderGCode("G21 G90\n" + program, view, 400, 400);
        var proj = pic.Projection;
        var centreWorld = view switch
        {
            PreviewView.XY => new Point3(cu, cv, 7),
            PreviewView.XZ => new Point3(cu, 7, cv),
            _ => new Point3(7, cu, cv),
        };
        var (cx, cy) = proj.ToPixel(centreWorld);
        var rpx = radius * proj.Scale;
        rpx.Should().BeGreaterThan(100, name);

        var pixels = PixelsOf(pic.Image, Feed);
        pixels.Should().NotBeEmpty(name);
        foreach (var (x, y) in pixels)
        {
            var d = Math.Sqrt(((x - cx) * (x - cx)) + ((y - cy) * (y - cy)));
            d.Should().BeApproximately(rpx, 1.0, $"{name}: pixel ({x},{y}) lies on the circle");
        }

        // All the way round: every 5 degrees of the circle has a drawn pixel next to it (an arc, not a chord).
        for (var deg = 0; deg < 360; deg += 5)
        {
            var a = deg * Math.PI / 180;
            Near(pic.Image, cx + (rpx * Math.Cos(a)), cy + (rpx * Math.Sin(a)), Feed).Should().BeTrue($"{name}: the circle passes {deg} degrees");
        }

        pic.Extents.Arcs.Should().Be(1);
    }

    public static TheoryData<string, PreviewView, string, Point3, Point3> HalfCircles => new()
    {
        // A half turn from +r to -r on the plane's first axis must pass the side its direction says.
        // G17 (X, Y) about +Z: G3 from X+ goes through Y+, G2 through Y-.
        { "G17 G3", PreviewView.XY, "G17\nG0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F100\n", new Point3(0, 10, 0), new Point3(0, -10, 0) },
        { "G17 G2", PreviewView.XY, "G17\nG0 X10 Y0 Z0\nG2 X-10 Y0 I-10 J0 F100\n", new Point3(0, -10, 0), new Point3(0, 10, 0) },
        // G18 (Z, X) about +Y: G3 from X+ turns toward Z-.
        { "G18 G3", PreviewView.XZ, "G18\nG0 X10 Y0 Z0\nG3 X-10 Z0 I-10 K0 F100\n", new Point3(0, 0, -10), new Point3(0, 0, 10) },
        { "G18 G2", PreviewView.XZ, "G18\nG0 X10 Y0 Z0\nG2 X-10 Z0 I-10 K0 F100\n", new Point3(0, 0, 10), new Point3(0, 0, -10) },
        // G19 (Y, Z) about +X: G3 from Y+ turns toward Z+.
        { "G19 G3", PreviewView.YZ, "G19\nG0 X0 Y10 Z0\nG3 Y-10 Z0 J-10 K0 F100\n", new Point3(0, 0, 10), new Point3(0, 0, -10) },
        { "G19 G2", PreviewView.YZ, "G19\nG0 X0 Y10 Z0\nG2 Y-10 Z0 J-10 K0 F100\n", new Point3(0, 0, -10), new Point3(0, 0, 10) },
    };

    [Theory]
    [MemberData(nameof(HalfCircles))]
    public void Half_circle_turns_the_way_its_plane_and_direction_say(string name, PreviewView view, string program, Point3 through, Point3 notThrough)
    {
        using var pic = RenderGCode("G21 G90\n" + program, view, 300, 300);
        var (tx, ty) = pic.Projection.ToPixel(through);
        var (nx, ny) = pic.Projection.ToPixel(notThrough);
        Near(pic.Image, tx, ty, Feed).Should().BeTrue($"{name} passes {through}");
        Near(pic.Image, nx, ny, Feed, 3).Should().BeFalse($"{name} does not pass {notThrough}");
        var ends = view == PreviewView.YZ ? new[] { new Point3(0, 10, 0), new Point3(0, -10, 0) } : new[] { new Point3(10, 0, 0), new Point3(-10, 0, 0) };
        var all = ends.Append(through).ToList();
        pic.Extents.Min.Should().Be(new Point3(all.Min(p => p.X), all.Min(p => p.Y), all.Min(p => p.Z)), $"{name}: the extents include the arc's extreme, not just its ends");
        pic.Extents.Max.Should().Be(new Point3(all.Max(p => p.X), all.Max(p => p.Y), all.Max(p => p.Z)), name);
    }

    [Theory]
    [InlineData(PreviewView.XY)]
    [InlineData(PreviewView.XZ)]
    [InlineData(PreviewView.Iso)]
    public void Helix_pixels_follow_the_helix_in_every_view(PreviewView view)
    {
        // Two G17 turns of radius 15 about (0, 0) descending from Z0 to Z-8.
        using var pic = RenderGCode("G21 G90 G17\nG0 X15 Y0 Z0\nG3 X15 Y0 Z-4 I-15 J0 F100\nG3 X15 Y0 Z-8 I-15 J0\n", view, 400, 400);
        var reference = new List<(double X, double Y)>();
        for (var i = 0; i <= 4000; i++)
        {
            var t = i / 4000.0;
            var a = 4 * Math.PI * t;
            reference.Add(pic.Projection.ToPixel(new Point3(15 * Math.Cos(a), 15 * Math.Sin(a), -8 * t)));
        }

        var pixels = PixelsOf(pic.Image, Feed);
        pixels.Should().NotBeEmpty();
        foreach (var (x, y) in pixels)
        {
            reference.Min(r => ((r.X - x) * (r.X - x)) + ((r.Y - y) * (r.Y - y))).Should().BeLessThan(1.1 * 1.1, $"pixel ({x},{y}) lies on the helix");
        }

        foreach (var (rx, ry) in reference.Where((_, i) => i % 20 == 0))
        {
            Near(pic.Image, rx, ry, Feed).Should().BeTrue($"the helix point at ({rx:0.0},{ry:0.0}) is drawn");
        }

        pic.Extents.Min.Z.Should().Be(-8);
        pic.Extents.Max.Z.Should().Be(0);
    }

    [Fact]
    public void Rapids_are_dashed_in_their_own_colour_and_feeds_are_solid()
    {
        using var pic = RenderGCode("G21 G90 G17\nG0 X0 Y0 Z0\nG0 X100\nG0 Y20\nG1 X0 F500\n", PreviewView.XY, 400, 300);
        Rapid.Should().NotBe(Feed);
        var proj = pic.Projection;
        var (ax, ay) = proj.ToPixel(new Point3(0, 0, 0));
        var (bx, _) = proj.ToPixel(new Point3(100, 0, 0));
        var (_, fy) = proj.ToPixel(new Point3(0, 20, 0));
        // Columns inside the ends (the round caps and the corner joins blur the first and last pixels).
        var columns = Enumerable.Range((int)Math.Round(ax) + 2, (int)Math.Round(bx - ax) - 3).ToList();
        var rapidRow = columns.Select(x => ColumnCoverage(pic.Image, x, ay, Rapid)).ToList();
        var feedRow = columns.Select(x => ColumnCoverage(pic.Image, x, fy, Feed)).ToList();

        rapidRow.Average().Should().BeApproximately(0.6, 0.05, "a 6 on / 4 off dash");
        rapidRow.Should().OnlyContain(c => c <= 1.1, "the rapid is one line, in the rapid colour only");
        var gaps = 0;
        for (var i = 1; i < rapidRow.Count; i++)
        {
            if (rapidRow[i] < 0.5 && rapidRow[i - 1] >= 0.5)
            {
                gaps++;
            }
        }

        gaps.Should().BeGreaterThan(20, "the rapid is dashed");
        feedRow.Should().OnlyContain(c => c >= 0.9, "the feed is solid from end to end");
        pic.Extents.Rapids.Should().Be(2);
        pic.Extents.Lines.Should().Be(1);
    }

    [Fact]
    public void R_form_arcs_place_the_centre_on_the_side_their_sign_says()
    {
        // G2 R+ (< 180 deg) from (0,0) to (10,10): centre right of the chord at (10,0); R- takes the long way round.
        using var shortArc = RenderGCode("G21 G90 G17\nG0 X0 Y0 Z0\nG2 X10 Y10 R10 F100\n", PreviewView.XY, 300, 300);
        shortArc.Extents.Min.X.Should().BeApproximately(0, 1e-9);
        shortArc.Extents.Max.Y.Should().BeApproximately(10, 1e-9);
        var (mx, my) = shortArc.Projection.ToPixel(new Point3(10 - (10 / Math.Sqrt(2)), 10 / Math.Sqrt(2), 0));
        Near(shortArc.Image, mx, my, Feed).Should().BeTrue("the short G2 arc bulges up-left around (10, 0)");

        using var longArc = RenderGCode("G21 G90 G17\nG0 X0 Y0 Z0\nG2 X10 Y10 R-10 F100\n", PreviewView.XY, 300, 300);
        // R- puts the centre left of the chord, at (0, 10): the 270 degree CW arc passes (-10, 10) and (0, 20).
        longArc.Extents.Min.X.Should().BeApproximately(-10, 1e-9);
        longArc.Extents.Max.Y.Should().BeApproximately(20, 1e-9);
        longArc.Extents.Min.Y.Should().BeApproximately(0, 1e-9);
        var (lx, ly) = longArc.Projection.ToPixel(new Point3(-10, 10, 0));
        Near(longArc.Image, lx, ly, Feed).Should().BeTrue();
    }

    [Fact]
    public void Sample_program_draws_with_its_known_extents_and_legend()
    {
        var path = RepoRoot.DemoProgram;
        var source = new GCodeToolpathSource(path);
        using var pic = PreviewRenderer.Render(source, new PreviewOptions { Width = 600, Height = 450 });
        source.IssueCount.Should().Be(0);
        pic.Extents.Min.X.Should().Be(-5);
        pic.Extents.Max.X.Should().Be(115);
        pic.Extents.Min.Y.Should().Be(-5);
        pic.Extents.Max.Y.Should().Be(105);
        pic.Extents.Max.Z.Should().Be(10);
        pic.Extents.Arcs.Should().Be(224);
        pic.Units.Should().Be(LengthUnits.Millimetres);
        PixelsOf(pic.Image, Palette.Text).Count.Should().BeGreaterThan(200, "the legend is written");
        var (_, bottom) = pic.Projection.ToPixel(new Point3(0, -5, 0));
        PixelsOf(pic.Image, Palette.Text).Should().OnlyContain(p => p.Y > bottom, "the legend sits below the drawing");
    }

    [Fact]
    public void Renderer_walks_the_source_exactly_twice_and_keeps_no_points()
    {
        var source = new CountingSource();
        using var pic = PreviewRenderer.Render(source, new PreviewOptions { Width = 200, Height = 200, Legend = false });
        source.Passes.Should().Be(2);
        pic.Extents.Lines.Should().Be(CountingSource.Count);
    }

    [Fact]
    public void Marker_is_drawn_on_a_copy_at_the_projected_position()
    {
        using var pic = RenderGCode("G21 G90 G17\nG0 X0 Y0 Z0\nG1 X50 Y50 F100\n", PreviewView.XY, 200, 200);
        var before = pic.Image.Bytes;
        using var marked = pic.WithMarker(new Point3(25, 25, 0));
        pic.Image.Bytes.Should().Equal(before, "the rendered picture stays clean for the next marker");
        var (mx, my) = pic.Projection.ToPixel(new Point3(25, 25, 0));
        var markerPixels = PixelsOf(marked, Palette.Marker);
        markerPixels.Should().NotBeEmpty();
        markerPixels.Average(p => p.X).Should().BeApproximately(mx, 1.5);
        markerPixels.Average(p => p.Y).Should().BeApproximately(my, 1.5);
        markerPixels.Should().OnlyContain(p => Math.Abs(p.X - mx) <= 15 && Math.Abs(p.Y - my) <= 15);

        using var decoded = SKBitmap.Decode(pic.ToPng(new Point3(25, 25, 0)));
        decoded.Width.Should().Be(200);
        decoded.Pixels.Should().Equal(marked.Pixels, "the PNG holds exactly the marked picture");
    }

    [Fact]
    public void Empty_program_renders_a_blank_picture_with_a_note()
    {
        using var pic = RenderGCode("%\nO1\nM30\n%\n", PreviewView.XY, 600, 450, legend: true);
        pic.Extents.IsEmpty.Should().BeTrue();
        var text = PixelsOf(pic.Image, Palette.Text);
        text.Should().NotBeEmpty();
        var legendTop = text.Min(p => p.Y);
        PixelsOf(pic.Image, Feed).Should().OnlyContain(p => p.Y >= legendTop, "only the legend's key uses the feed colour");
    }

    private sealed class CountingSource : IToolpathSource
    {
        public const int Count = 100_000;

        public int Passes { get; private set; }

        public LengthUnits Units => LengthUnits.Millimetres;

        public bool MixedUnits => false;

        public double PassFraction { get; private set; }

        public string Name => "counting";

        public IEnumerable<PathSegment> ReadSegments(CancellationToken cancellationToken = default)
        {
            Passes++;
            var rng = new Random(7);
            var p = new Point3(0, 0, 0);
            for (var i = 0; i < Count; i++)
            {
                var q = new Point3(rng.NextDouble() * 100, rng.NextDouble() * 100, rng.NextDouble());
                PassFraction = (double)i / Count;
                yield return PathSegment.Line(p, q, false, i + 1);
                p = q;
            }
        }
    }
}
