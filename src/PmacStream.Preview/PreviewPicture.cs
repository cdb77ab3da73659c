using PmacStream.GCode;
using SkiaSharp;

namespace PmacStream.Preview;

/// <summary>A rendered preview: the image, how it maps coordinates, and what was found. Dispose it to free the pixels.</summary>
public sealed class PreviewPicture : IDisposable
{
    internal PreviewPicture(SKBitmap image, ViewProjection projection, PreviewExtents extents, LengthUnits units, ExecutionReport? execution, PreviewPalette palette, IReadOnlyList<string> warnings)
    {
        Image = image;
        Projection = projection;
        Extents = extents;
        Units = units;
        Execution = execution;
        Palette = palette;
        Warnings = warnings;
    }

    /// <summary>The picture: 32 bits a pixel in the platform's order, opaque (draw on <see cref="WithMarker"/>'s copy to keep it clean).</summary>
    public SKBitmap Image { get; }

    /// <summary>Coordinates to pixels, for markers and hit tests.</summary>
    public ViewProjection Projection { get; }

    /// <summary>Extents and move counts.</summary>
    public PreviewExtents Extents { get; }

    /// <summary>The program's units (the legend shows extents in them).</summary>
    public LengthUnits Units { get; }

    /// <summary>The executed-log comparison, when a log was given.</summary>
    public ExecutionReport? Execution { get; }

    /// <summary>The colours used.</summary>
    public PreviewPalette Palette { get; }

    /// <summary>What the picture lacks and why, e.g. a Chinese legend drawn in English for want of a font with Chinese glyphs.</summary>
    public IReadOnlyList<string> Warnings { get; }

    /// <summary>A copy of the picture with a cross-hair marker at <paramref name="position"/> (e.g. the executing position); the caller disposes it.</summary>
    public SKBitmap WithMarker(Point3 position)
    {
        var copy = Image.Copy();
        DrawMarker(copy, position);
        return copy;
    }

    /// <summary>Draws the marker on <paramref name="target"/> (same size as <see cref="Image"/>).</summary>
    public void DrawMarker(SKBitmap target, Point3 position)
    {
        var (x, y) = Projection.ToPixel(position);
        var c = PathPen.ToCanvas(x, y);
        using var canvas = new SKCanvas(target);
        using var paint = new SKPaint { Color = Palette.Marker, IsAntialias = true, Style = SKPaintStyle.Stroke, StrokeWidth = 2 };
        const float r = 9;
        canvas.DrawCircle(c, r, paint);
        canvas.DrawLine(c.X - r - 4, c.Y, c.X - 3, c.Y, paint);
        canvas.DrawLine(c.X + 3, c.Y, c.X + r + 4, c.Y, paint);
        canvas.DrawLine(c.X, c.Y - r - 4, c.X, c.Y - 3, paint);
        canvas.DrawLine(c.X, c.Y + 3, c.X, c.Y + r + 4, paint);
    }

    /// <summary>The picture as PNG bytes.</summary>
    public byte[] ToPng() => Encode(Image);

    /// <summary>The picture with a marker at <paramref name="position"/>, as PNG bytes.</summary>
    public byte[] ToPng(Point3 position)
    {
        using var marked = WithMarker(position);
        return Encode(marked);
    }

    /// <summary>Writes the picture as a PNG file atomically (a temporary file renamed into place), so no half picture is left.</summary>
    public void WritePng(string path)
    {
        var full = Path.GetFullPath(path);
        var temp = full + ".tmp" + Environment.ProcessId.ToString(System.Globalization.CultureInfo.InvariantCulture);
        try
        {
            File.WriteAllBytes(temp, ToPng());
            File.Move(temp, full, overwrite: true);
        }
        finally
        {
            if (File.Exists(temp))
            {
                File.Delete(temp);
            }
        }
    }

    /// <inheritdoc />
    public void Dispose() => Image.Dispose();

    private static byte[] Encode(SKBitmap bitmap)
    {
        using var data = bitmap.Encode(SKEncodedImageFormat.Png, 100)
            ?? throw new InvalidOperationException($"Skia could not encode a {bitmap.Width}x{bitmap.Height} picture as PNG");
        return data.ToArray();
    }
}
