using PmacStream.Preview;
using SkiaSharp;

namespace PmacStream.Core.Tests.Preview;

/// <summary>
/// Renders G-code text and finds pixels. The picture is antialiased, so a pixel "is" a colour when it is a mix of
/// that colour over what lies under it (the background unless said otherwise) with at least a given share.
/// </summary>
internal static class PreviewTestKit
{
    public static readonly PreviewPalette Palette = new();

    public static PreviewPicture RenderGCode(string gcode, PreviewView view, int width = 400, int height = 400, bool legend = false, string? log = null)
    {
        using var temp = new TestFolder("preview");
        var path = Path.Combine(temp.Path, "program.nc");
        File.WriteAllText(path, gcode);
        return PreviewRenderer.Render(new GCodeToolpathSource(path), new PreviewOptions { Width = width, Height = height, View = view, Legend = legend }, log);
    }

    /// <summary>
    /// The share (0..1) of <paramref name="colour"/> in a pixel that is <paramref name="colour"/> blended over
    /// <paramref name="under"/>; 0 when the pixel is not such a mix (another colour is in it).
    /// </summary>
    public static double Coverage(SKColor pixel, SKColor colour, SKColor under)
    {
        double dr = colour.Red - under.Red, dg = colour.Green - under.Green, db = colour.Blue - under.Blue;
        double vr = pixel.Red - under.Red, vg = pixel.Green - under.Green, vb = pixel.Blue - under.Blue;
        var dd = (dr * dr) + (dg * dg) + (db * db);
        if (dd == 0)
        {
            return pixel == colour ? 1 : 0;
        }

        var a = ((vr * dr) + (vg * dg) + (vb * db)) / dd;
        var rr = vr - (a * dr);
        var rg = vg - (a * dg);
        var rb = vb - (a * db);
        // Off the line between the two colours by more than rounding: some third colour is mixed in.
        return (rr * rr) + (rg * rg) + (rb * rb) > 4 * 4 || a < -0.05 || a > 1.05 ? 0 : Math.Clamp(a, 0, 1);
    }

    public static SKColor At(SKBitmap image, int x, int y) => image.GetPixel(x, y);

    /// <summary>True when the pixel at (x, y) shows at least <paramref name="min"/> of <paramref name="colour"/> over <paramref name="under"/>.</summary>
    public static bool Is(SKBitmap image, int x, int y, SKColor colour, SKColor? under = null, double min = 0.4) =>
        x >= 0 && y >= 0 && x < image.Width && y < image.Height && Coverage(image.GetPixel(x, y), colour, under ?? Palette.Background) >= min;

    /// <summary>Every pixel that shows at least <paramref name="min"/> of <paramref name="colour"/> over the background.</summary>
    public static List<(int X, int Y)> PixelsOf(SKBitmap image, SKColor colour, double min = 0.4)
    {
        var list = new List<(int, int)>();
        var pixels = image.Pixels;
        for (var y = 0; y < image.Height; y++)
        {
            for (var x = 0; x < image.Width; x++)
            {
                if (Coverage(pixels[(y * image.Width) + x], colour, Palette.Background) >= min)
                {
                    list.Add((x, y));
                }
            }
        }

        return list;
    }

    /// <summary>True when a pixel showing <paramref name="colour"/> lies within <paramref name="r"/> pixels (square) of (x, y).</summary>
    public static bool Near(SKBitmap image, double x, double y, SKColor colour, int r = 1)
    {
        var cx = (int)Math.Round(x);
        var cy = (int)Math.Round(y);
        for (var dy = -r; dy <= r; dy++)
        {
            for (var dx = -r; dx <= r; dx++)
            {
                if (Is(image, cx + dx, cy + dy, colour))
                {
                    return true;
                }
            }
        }

        return false;
    }

    /// <summary>
    /// How much of <paramref name="colour"/> column <paramref name="x"/> holds within a pixel and a half of row
    /// <paramref name="y"/>: about 1 where a horizontal line runs, whichever rows its antialiasing spread it over.
    /// </summary>
    public static double ColumnCoverage(SKBitmap image, int x, double y, SKColor colour)
    {
        var sum = 0.0;
        for (var row = (int)Math.Floor(y - 1.5); row <= (int)Math.Ceiling(y + 1.5); row++)
        {
            if (row >= 0 && row < image.Height)
            {
                sum += Coverage(image.GetPixel(x, row), colour, Palette.Background);
            }
        }

        return sum;
    }
}
