using PmacStream.Preview;

namespace PmacStream.Core.Tests.Preview;

public class PngAndRasterTests
{
    [Fact]
    public void Crc32_matches_the_standard_check_value()
    {
        Crc32.Compute("123456789"u8).Should().Be(0xCBF43926u);
        Crc32.Compute("IEND"u8).Should().Be(0xAE426082u); // the CRC every PNG ends with
    }

    [Fact]
    public void Png_round_trips_random_pixels_with_valid_chunks()
    {
        var rng = new Random(1234);
        var image = new RgbaImage(37, 23, new Rgba(0, 0, 0));
        rng.NextBytes(image.Pixels);
        var png = PngEncoder.Encode(image);

        var decoded = TestPng.Decode(png);
        decoded.Width.Should().Be(37);
        decoded.Height.Should().Be(23);
        decoded.BitDepth.Should().Be(8);
        decoded.ColourType.Should().Be(6);
        decoded.Interlace.Should().Be(0);
        decoded.ChunkTypes.Should().Equal("IHDR", "IDAT", "IEND");
        decoded.Pixels.Should().Equal(image.Pixels);
    }

    [Fact]
    public void WriteFile_leaves_a_complete_png_and_no_temporary_file()
    {
        var dir = Directory.CreateTempSubdirectory("pmacstream-png-");
        try
        {
            var image = new RgbaImage(10, 5, new Rgba(1, 2, 3));
            image.Set(9, 4, new Rgba(200, 100, 50));
            var path = Path.Combine(dir.FullName, "a.png");
            PngEncoder.WriteFile(image, path);
            Directory.GetFiles(dir.FullName).Should().ContainSingle().Which.Should().Be(path);
            var decoded = TestPng.Decode(File.ReadAllBytes(path));
            decoded.At(9, 4).Should().Be(new Rgba(200, 100, 50));
            decoded.At(0, 0).Should().Be(new Rgba(1, 2, 3));
        }
        finally
        {
            dir.Delete(true);
        }
    }

    [Theory]
    [InlineData(2, 3, 40, 17)]
    [InlineData(40, 17, 2, 3)]
    [InlineData(5, 5, 5, 30)]
    [InlineData(0, 30, 30, 0)]
    public void Bresenham_line_is_connected_and_hits_both_ends(int x0, int y0, int x1, int y1)
    {
        var image = new RgbaImage(50, 50, new Rgba(255, 255, 255));
        var ink = new Rgba(0, 0, 0);
        image.DrawLine(x0, y0, x1, y1, ink);
        var pixels = PreviewTestKit.PixelsOf(image, ink);
        pixels.Should().Contain((x0, y0)).And.Contain((x1, y1));
        pixels.Count.Should().Be(Math.Max(Math.Abs(x1 - x0), Math.Abs(y1 - y0)) + 1, "one pixel per step of the major axis");
        foreach (var (x, y) in pixels)
        {
            // Every pixel is within half a pixel (plus rounding) of the ideal line.
            var d = Math.Abs(((y1 - y0) * (x - x0)) - ((x1 - x0) * (y - y0))) / Math.Sqrt(Math.Pow(x1 - x0, 2) + Math.Pow(y1 - y0, 2));
            d.Should().BeLessThan(0.75);
        }
    }

    [Fact]
    public void Dashed_line_alternates_on_and_off_runs_of_the_pattern_length()
    {
        var image = new RgbaImage(100, 5, new Rgba(255, 255, 255));
        var ink = new Rgba(0, 0, 0);
        var dash = new DashPattern(6, 4);
        image.DrawLine(0, 2, 99, 2, ink, 1, ref dash);
        var row = Enumerable.Range(0, 100).Select(x => image[x, 2] == ink).ToArray();
        var runs = new List<(bool On, int Length)>();
        foreach (var on in row)
        {
            if (runs.Count > 0 && runs[^1].On == on)
            {
                runs[^1] = (on, runs[^1].Length + 1);
            }
            else
            {
                runs.Add((on, 1));
            }
        }

        runs.Should().HaveCount(20);
        runs.Where(r => r.On).Should().OnlyContain(r => r.Length == 6);
        runs.Where(r => !r.On).Should().OnlyContain(r => r.Length == 4);
    }

    [Fact]
    public void Dash_phase_carries_over_between_short_segments()
    {
        var image = new RgbaImage(100, 5, new Rgba(255, 255, 255));
        var ink = new Rgba(0, 0, 0);
        var dash = new DashPattern(6, 4);
        for (var x = 0; x < 99; x += 2)
        {
            // Many 2-pixel moves: the shared end pixel is drawn twice but the pattern still runs 6 on, 4 off overall.
            image.DrawLine(x, 2, x + 2, 2, ink, 1, ref dash);
        }

        var on = Enumerable.Range(0, 100).Count(x => image[x, 2] == ink);
        on.Should().BeInRange(45, 75, "a dash pattern, not a solid line, survives many tiny moves");
    }

    [Fact]
    public void Lines_far_outside_are_clipped_without_cost_or_wraparound()
    {
        var image = new RgbaImage(20, 20, new Rgba(255, 255, 255));
        var ink = new Rgba(0, 0, 0);
        image.DrawLine(-100_000_000, 10, 100_000_000, 10, ink);
        image.DrawLine(-50, -50, -10, 30, ink);
        var pixels = PreviewTestKit.PixelsOf(image, ink);
        pixels.Should().HaveCount(20).And.OnlyContain(p => p.Y == 10);
    }

    [Fact]
    public void Thick_line_covers_its_width_across_the_line()
    {
        var image = new RgbaImage(30, 30, new Rgba(255, 255, 255));
        var ink = new Rgba(0, 0, 0);
        image.DrawLine(5, 15, 25, 15, ink, 5);
        for (var y = 13; y <= 17; y++)
        {
            image[15, y].Should().Be(ink);
        }

        image[15, 12].Should().NotBe(ink);
        image[15, 18].Should().NotBe(ink);
    }

    [Fact]
    public void Font_draws_known_glyph_bits()
    {
        var image = new RgbaImage(20, 10, new Rgba(255, 255, 255));
        var ink = new Rgba(0, 0, 0);
        var width = image.DrawText(0, 0, "1L", ink);
        width.Should().Be(12);
        // '1' = 00 42 7F 40 00: its stem is column 2 (all seven rows), its foot row 6 spans columns 1..3.
        Enumerable.Range(0, 7).Should().OnlyContain(y => image[2, y] == ink);
        image[0, 3].Should().NotBe(ink);
        image[1, 6].Should().Be(ink);
        image[3, 6].Should().Be(ink);
        // 'L' = 7F 40 40 40 40 at x = 6: column 6 full, bottom row 6..10.
        Enumerable.Range(0, 7).Should().OnlyContain(y => image[6, y] == ink);
        Enumerable.Range(6, 5).Should().OnlyContain(x => image[x, 6] == ink);
        image[8, 3].Should().NotBe(ink);
    }

    [Fact]
    public void Bgra_copy_swaps_red_and_blue_only()
    {
        var image = new RgbaImage(2, 1, new Rgba(10, 20, 30, 40));
        image.Set(1, 0, new Rgba(1, 2, 3));
        image.ToBgra().Should().Equal(30, 20, 10, 40, 3, 2, 1, 255);
    }

    [Fact]
    public void Program_positions_in_inches_become_millimetres()
    {
        Point3D.FromProgram(new PmacStream.GCode.Point3(1, -2, 0.5), PmacStream.GCode.LengthUnits.Inches)
            .Should().Be(new Point3D(25.4, -50.8, 12.7));
        Point3D.FromProgram(new PmacStream.GCode.Point3(1, -2, 0.5), PmacStream.GCode.LengthUnits.Millimetres)
            .Should().Be(new Point3D(1, -2, 0.5));
    }
}
