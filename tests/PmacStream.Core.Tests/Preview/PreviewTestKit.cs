using PmacStream.Preview;

namespace PmacStream.Core.Tests.Preview;

/// <summary>Renders G-code text and finds pixels.</summary>
internal static class PreviewTestKit
{
    public static readonly PreviewPalette Palette = new();

    public static PreviewPicture RenderGCode(string gcode, PreviewView view, int width = 400, int height = 400, bool legend = false, string? log = null)
    {
        var path = Path.Combine(Path.GetTempPath(), $"pmacstream-preview-{Guid.NewGuid():N}.nc");
        File.WriteAllText(path, gcode);
        try
        {
            return PreviewRenderer.Render(new GCodeToolpathSource(path), new PreviewOptions { Width = width, Height = height, View = view, Legend = legend }, log);
        }
        finally
        {
            File.Delete(path);
        }
    }

    public static List<(int X, int Y)> PixelsOf(RgbaImage image, Rgba colour)
    {
        var list = new List<(int, int)>();
        for (var y = 0; y < image.Height; y++)
        {
            for (var x = 0; x < image.Width; x++)
            {
                if (image[x, y] == colour)
                {
                    list.Add((x, y));
                }
            }
        }

        return list;
    }

    /// <summary>True when a pixel of <paramref name="colour"/> lies within <paramref name="r"/> pixels (square) of (x, y).</summary>
    public static bool Near(RgbaImage image, double x, double y, Rgba colour, int r = 1)
    {
        var cx = (int)Math.Round(x);
        var cy = (int)Math.Round(y);
        for (var dy = -r; dy <= r; dy++)
        {
            for (var dx = -r; dx <= r; dx++)
            {
                var px = cx + dx;
                var py = cy + dy;
                if (px >= 0 && py >= 0 && px < image.Width && py < image.Height && image[px, py] == colour)
                {
                    return true;
                }
            }
        }

        return false;
    }
}
