namespace PmacStream.Preview;

/// <summary>An 8-bit RGBA colour.</summary>
/// <param name="R">Red.</param>
/// <param name="G">Green.</param>
/// <param name="B">Blue.</param>
/// <param name="A">Alpha (255 opaque).</param>
public readonly record struct Rgba(byte R, byte G, byte B, byte A = 255)
{
    /// <summary>Parses <c>#RRGGBB</c>.</summary>
    public static Rgba FromHex(string hex) =>
        new(Convert.ToByte(hex.Substring(1, 2), 16), Convert.ToByte(hex.Substring(3, 2), 16), Convert.ToByte(hex.Substring(5, 2), 16));

    /// <inheritdoc />
    public override string ToString() => $"#{R:X2}{G:X2}{B:X2}{(A == 255 ? string.Empty : A.ToString("X2", System.Globalization.CultureInfo.InvariantCulture))}";
}

/// <summary>
/// A plain RGBA pixel buffer (row-major, top row first, 4 bytes a pixel) with the few drawing operations the preview
/// needs: pixels, spans, Bresenham lines (solid, thick or dashed), rectangles and bitmap text. Aliased on purpose:
/// every drawn pixel has exactly the drawing colour, which keeps thin toolpaths crisp and tests exact.
/// </summary>
public sealed class RgbaImage
{
    /// <summary>Creates an image filled with <paramref name="background"/>.</summary>
    public RgbaImage(int width, int height, Rgba background)
    {
        if (width <= 0 || height <= 0 || (long)width * height > 64L * 1024 * 1024)
        {
            throw new ArgumentOutOfRangeException(nameof(width), $"image size {width}x{height} is outside 1x1..64 megapixels");
        }

        Width = width;
        Height = height;
        Pixels = new byte[width * height * 4];
        Clear(background);
    }

    private RgbaImage(int width, int height, byte[] pixels)
    {
        Width = width;
        Height = height;
        Pixels = pixels;
    }

    /// <summary>Width in pixels.</summary>
    public int Width { get; }

    /// <summary>Height in pixels.</summary>
    public int Height { get; }

    /// <summary>The pixels: R, G, B, A per pixel, rows top to bottom.</summary>
    public byte[] Pixels { get; }

    /// <summary>A deep copy (e.g. to draw a marker on without touching the rendered toolpath).</summary>
    public RgbaImage Clone() => new(Width, Height, (byte[])Pixels.Clone());

    /// <summary>
    /// The pixels in B, G, R, A order (what a WinForms <c>Bitmap</c> of <c>Format32bppArgb</c> holds in memory), for
    /// copying into a bitmap's locked bits row by row (stride <c>Width * 4</c>).
    /// </summary>
    public byte[] ToBgra()
    {
        var bgra = new byte[Pixels.Length];
        for (var o = 0; o < bgra.Length; o += 4)
        {
            bgra[o] = Pixels[o + 2];
            bgra[o + 1] = Pixels[o + 1];
            bgra[o + 2] = Pixels[o];
            bgra[o + 3] = Pixels[o + 3];
        }

        return bgra;
    }

    /// <summary>The colour at (x, y).</summary>
    public Rgba this[int x, int y]
    {
        get
        {
            var o = ((y * Width) + x) * 4;
            return new Rgba(Pixels[o], Pixels[o + 1], Pixels[o + 2], Pixels[o + 3]);
        }
    }

    /// <summary>Fills the whole image.</summary>
    public void Clear(Rgba c)
    {
        var p = Pixels;
        for (var o = 0; o < p.Length; o += 4)
        {
            p[o] = c.R;
            p[o + 1] = c.G;
            p[o + 2] = c.B;
            p[o + 3] = c.A;
        }
    }

    /// <summary>Sets a pixel; outside the image nothing happens. A translucent colour is blended over the pixel.</summary>
    public void Set(int x, int y, Rgba c)
    {
        if ((uint)x >= (uint)Width || (uint)y >= (uint)Height)
        {
            return;
        }

        var o = ((y * Width) + x) * 4;
        var p = Pixels;
        if (c.A == 255)
        {
            p[o] = c.R;
            p[o + 1] = c.G;
            p[o + 2] = c.B;
            p[o + 3] = 255;
            return;
        }

        var a = c.A;
        var ia = 255 - a;
        p[o] = (byte)(((c.R * a) + (p[o] * ia) + 127) / 255);
        p[o + 1] = (byte)(((c.G * a) + (p[o + 1] * ia) + 127) / 255);
        p[o + 2] = (byte)(((c.B * a) + (p[o + 2] * ia) + 127) / 255);
        p[o + 3] = (byte)Math.Min(255, p[o + 3] + a);
    }

    /// <summary>Fills a rectangle (clipped).</summary>
    public void FillRect(int x, int y, int w, int h, Rgba c)
    {
        var x0 = Math.Max(0, x);
        var y0 = Math.Max(0, y);
        var x1 = Math.Min(Width, x + w);
        var y1 = Math.Min(Height, y + h);
        for (var yy = y0; yy < y1; yy++)
        {
            for (var xx = x0; xx < x1; xx++)
            {
                Set(xx, yy, c);
            }
        }
    }

    /// <summary>Outlines a rectangle one pixel wide.</summary>
    public void DrawRect(int x, int y, int w, int h, Rgba c)
    {
        FillRect(x, y, w, 1, c);
        FillRect(x, y + h - 1, w, 1, c);
        FillRect(x, y, 1, h, c);
        FillRect(x + w - 1, y, 1, h, c);
    }

    /// <summary>A solid line <paramref name="width"/> pixels wide between two pixel centres.</summary>
    public void DrawLine(int x0, int y0, int x1, int y1, Rgba c, int width = 1)
    {
        var dash = DashPattern.Solid;
        DrawLine(x0, y0, x1, y1, c, width, ref dash);
    }

    /// <summary>
    /// A Bresenham line whose pixels are on or off as <paramref name="dash"/> says; the pattern's phase carries over
    /// to the next call, so a path of many short moves keeps an even dash. Lines are clipped to the image first, so
    /// a far-off point costs nothing.
    /// </summary>
    public void DrawLine(int x0, int y0, int x1, int y1, Rgba c, int width, ref DashPattern dash)
    {
        var dx = Math.Abs((long)x1 - x0);
        var dy = Math.Abs((long)y1 - y0);
        var major = Math.Max(dx, dy);
        // Pixel distance per step along the major axis, so diagonal dashes are as long as straight ones.
        var stepLength = major == 0 ? 1.0 : Math.Sqrt((double)(dx * dx) + (dy * dy)) / major;
        if (!Clip(ref x0, ref y0, ref x1, ref y1, width, ref dash, stepLength))
        {
            return;
        }

        dx = Math.Abs((long)x1 - x0);
        dy = -Math.Abs((long)y1 - y0);
        var sx = x0 < x1 ? 1 : -1;
        var sy = y0 < y1 ? 1 : -1;
        var err = dx + dy;
        var horizontalish = dx >= -dy;
        var half = (width - 1) / 2;
        var x = x0;
        var y = y0;
        while (true)
        {
            if (dash.IsOn)
            {
                if (width <= 1)
                {
                    Set(x, y, c);
                }
                else if (horizontalish)
                {
                    for (var k = 0; k < width; k++)
                    {
                        Set(x, y - half + k, c);
                    }
                }
                else
                {
                    for (var k = 0; k < width; k++)
                    {
                        Set(x - half + k, y, c);
                    }
                }
            }

            if (x == x1 && y == y1)
            {
                break;
            }

            dash.Advance(stepLength);
            var e2 = 2 * err;
            if (e2 >= dy)
            {
                err += dy;
                x += sx;
            }

            if (e2 <= dx)
            {
                err += dx;
                y += sy;
            }
        }
    }

    /// <summary>Draws text in the built-in 5x7 font at <paramref name="scale"/>; returns the width used.</summary>
    public int DrawText(int x, int y, string text, Rgba c, int scale = 1) => BitmapFont.Draw(this, x, y, text, c, scale);

    /// <summary>
    /// Liang-Barsky clip of the segment to the image (grown by the line width). The dash phase is advanced by the
    /// part cut off at the start so dashes do not shift when the view is clipped.
    /// </summary>
    private bool Clip(ref int x0, ref int y0, ref int x1, ref int y1, int width, ref DashPattern dash, double stepLength)
    {
        var m = width;
        if (x0 >= -m && y0 >= -m && x0 < Width + m && y0 < Height + m && x1 >= -m && y1 >= -m && x1 < Width + m && y1 < Height + m)
        {
            return true;
        }

        double fx0 = x0, fy0 = y0, fdx = (double)x1 - x0, fdy = (double)y1 - y0;
        double t0 = 0, t1 = 1;
        if (!ClipEdge(-fdx, fx0 + m, ref t0, ref t1) || !ClipEdge(fdx, Width - 1 + m - fx0, ref t0, ref t1) ||
            !ClipEdge(-fdy, fy0 + m, ref t0, ref t1) || !ClipEdge(fdy, Height - 1 + m - fy0, ref t0, ref t1))
        {
            dash.Advance(Math.Max(Math.Abs(fdx), Math.Abs(fdy)) * stepLength);
            return false;
        }

        var nx0 = (int)Math.Round(fx0 + (t0 * fdx));
        var ny0 = (int)Math.Round(fy0 + (t0 * fdy));
        dash.Advance(Math.Max(Math.Abs(nx0 - fx0), Math.Abs(ny0 - fy0)) * stepLength);
        x1 = (int)Math.Round(fx0 + (t1 * fdx));
        y1 = (int)Math.Round(fy0 + (t1 * fdy));
        x0 = nx0;
        y0 = ny0;
        return true;
    }

    private static bool ClipEdge(double p, double q, ref double t0, ref double t1)
    {
        if (p == 0)
        {
            return q >= 0;
        }

        var r = q / p;
        if (p < 0)
        {
            if (r > t1)
            {
                return false;
            }

            t0 = Math.Max(t0, r);
        }
        else
        {
            if (r < t0)
            {
                return false;
            }

            t1 = Math.Min(t1, r);
        }

        return true;
    }
}

/// <summary>An on/off dash pattern in pixels with its running phase (a value type: keep one per path kind).</summary>
public struct DashPattern
{
    private readonly double _on;
    private readonly double _period;
    private double _phase;

    /// <summary>A pattern of <paramref name="on"/> pixels drawn, <paramref name="off"/> pixels skipped.</summary>
    public DashPattern(double on, double off)
    {
        _on = on;
        _period = on + off;
        _phase = 0;
    }

    /// <summary>Always on.</summary>
    public static DashPattern Solid => default;

    /// <summary>True while the pen is down at the current phase.</summary>
    public readonly bool IsOn => _period <= 0 || _phase < _on;

    /// <summary>Moves the phase on by <paramref name="pixels"/>.</summary>
    public void Advance(double pixels)
    {
        if (_period > 0)
        {
            _phase = (_phase + pixels) % _period;
        }
    }

    /// <summary>Starts the pattern over (a new run of rapids).</summary>
    public void Reset() => _phase = 0;
}
