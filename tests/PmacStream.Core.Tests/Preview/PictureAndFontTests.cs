using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preview;
using SkiaSharp;
using static PmacStream.Core.Tests.Preview.PreviewTestKit;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.Preview;

/// <summary>PNG output, the legend's fonts and its Chinese labels.</summary>
public class PictureAndFontTests(ITestOutputHelper output)
{
    private const string Square = "G21 G90 G17\nG0 X0 Y0 Z0\nG1 X40 F100\nG1 Y40\nG1 X0\nG1 Y0\n";

    [Fact]
    public void WritePng_leaves_a_complete_png_and_no_temporary_file()
    {
        using var temp = new TestFolder("png");
        var dir = temp.Path;
        using var pic = RenderGCode(Square, PreviewView.XY, 64, 48);
        var path = Path.Combine(dir, "a.png");
        pic.WritePng(path);
        Directory.GetFiles(dir).Should().ContainSingle().Which.Should().Be(path);
        var bytes = File.ReadAllBytes(path);
        bytes.Take(8).Should().Equal(0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A);
        using var decoded = SKBitmap.Decode(bytes);
        decoded.Width.Should().Be(64);
        decoded.Height.Should().Be(48);
        decoded.Pixels.Should().Equal(pic.Image.Pixels, "PNG is lossless");
    }

    [Fact]
    public void Picture_size_is_bounded()
    {
        var act = () => PreviewRenderer.Render(new SegmentListSource([]), new PreviewOptions { Width = 9000, Height = 8000 });
        act.Should().Throw<ArgumentOutOfRangeException>().Which.Message.Should().Contain("9000x8000");
    }

    [Fact]
    public void Legend_font_is_a_real_font_that_draws_latin_text()
    {
        using var font = new LegendFont(20);
        output.WriteLine($"legend font: {font.Family}");
        font.CanDraw("X -5.000 .. 115.000 mm").Should().BeTrue("a Latin font is installed ({0})", font.Family);
        font.Measure("mmmm").Should().BeGreaterThan(font.Measure("ii"), "a proportional font");
        font.CanDraw("\u0378").Should().BeFalse("U+0378 is unassigned: no font has it, and CanDraw says so");
    }

    [SkippableFact]
    public void Chinese_text_falls_back_to_a_font_with_chinese_glyphs()
    {
        using var font = new LegendFont(20);
        Skip.If(!font.CanDraw("进给"), "no installed font has Chinese glyphs (apt-get install fonts-noto-cjk; .ci/run installs it)");

        font.Fallbacks.Should().NotBeEmpty("the Latin family lacks CJK glyphs, so a fallback was matched");
        output.WriteLine($"legend font {font.Family}, Chinese from {string.Join(", ", font.Fallbacks)}");
        font.CanDraw(LegendTextAll()).Should().BeTrue();
        font.Measure("进给").Should().BeGreaterThan(font.Measure("ii"));
    }

    [Fact]
    public void Chinese_legend_is_drawn_when_a_chinese_font_is_installed_and_english_with_a_warning_otherwise()
    {
        var path = RepoRoot.DemoProgram;
        using var en = PreviewRenderer.Render(new GCodeToolpathSource(path), new PreviewOptions { Width = 600, Height = 450 });
        using var zh = PreviewRenderer.Render(new GCodeToolpathSource(path), new PreviewOptions { Width = 600, Height = 450, Culture = CultureInfo.GetCultureInfo("zh-CN") });
        using var font = new LegendFont(20);
        var (_, bottom) = en.Projection.ToPixel(new Point3(0, -5, 0));
        var legendRows = Enumerable.Range((int)bottom + 2, 450 - (int)bottom - 2);
        var differing = legendRows.Sum(y => Enumerable.Range(0, 600).Count(x => en.Image.GetPixel(x, y) != zh.Image.GetPixel(x, y)));
        var plotSame = Enumerable.Range(0, (int)bottom).All(y => Enumerable.Range(0, 600).All(x => en.Image.GetPixel(x, y) == zh.Image.GetPixel(x, y)));
        plotSame.Should().BeTrue("the language changes the legend only");
        en.Warnings.Should().BeEmpty();
        if (font.CanDraw("进给"))
        {
            zh.Warnings.Should().BeEmpty();
            differing.Should().BeGreaterThan(500, "the legend is written in Chinese");
            PixelsOf(zh.Image, Palette.Text).Should().OnlyContain(p => p.Y > bottom).And.HaveCountGreaterThan(200);
        }
        else
        {
            output.WriteLine("no Chinese font installed: checking the English fallback");
            zh.Warnings.Should().ContainSingle().Which.Should().Contain("fonts-noto-cjk");
            differing.Should().Be(0, "without Chinese glyphs the legend stays English");
        }
    }

    [Fact]
    public void Program_positions_in_inches_become_millimetres()
    {
        new Point3(1, -2, 0.5).InMillimetres(LengthUnits.Inches)
            .Should().Be(new Point3(25.4, -50.8, 12.7));
        new Point3(1, -2, 0.5).InMillimetres(LengthUnits.Millimetres)
            .Should().Be(new Point3(1, -2, 0.5));
    }

    private static string LegendTextAll() => LegendText.AllChinese();
}
