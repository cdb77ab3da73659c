using System.Runtime.InteropServices;
using SkiaSharp;

namespace PmacStream.Hmi;

/// <summary>
/// The toolpath pane's pixels: 32 bits a pixel, blue, green, red, alpha in memory order, alpha premultiplied (what
/// GDI+ calls <c>Format32bppPArgb</c>), in one pinned block that never moves, so a view can wrap it in a bitmap
/// once and repaint from it whenever the presenter says it changed. Drawn and read on the UI thread only.
/// </summary>
public sealed class ToolpathFrame : IDisposable
{
    private readonly byte[] _pixels;

    /// <summary>A frame of <paramref name="width"/> x <paramref name="height"/> pixels, cleared to <paramref name="background"/>.</summary>
    public ToolpathFrame(int width, int height, SKColor background)
    {
        ArgumentOutOfRangeException.ThrowIfLessThan(width, 1);
        ArgumentOutOfRangeException.ThrowIfLessThan(height, 1);
        Width = width;
        Height = height;
        Stride = width * 4;
        _pixels = GC.AllocateArray<byte>(Stride * height, pinned: true);
        Scan0 = Marshal.UnsafeAddrOfPinnedArrayElement(_pixels, 0);
        Bitmap = new SKBitmap();
        Bitmap.InstallPixels(new SKImageInfo(width, height, SKColorType.Bgra8888, SKAlphaType.Premul), Scan0, Stride);
        Bitmap.Erase(background);
    }

    /// <summary>Width in pixels.</summary>
    public int Width { get; }

    /// <summary>Height in pixels.</summary>
    public int Height { get; }

    /// <summary>Bytes from one row to the next.</summary>
    public int Stride { get; }

    /// <summary>Address of the first pixel (top left); valid as long as the frame is referenced.</summary>
    public IntPtr Scan0 { get; }

    /// <summary>The pixels (<see cref="Stride"/> x <see cref="Height"/> bytes).</summary>
    public ReadOnlySpan<byte> Pixels => _pixels;

    /// <summary>Counts the pixels of exactly <paramref name="colour"/> (opaque), e.g. the executed path's.</summary>
    public int CountPixels(SKColor colour)
    {
        var n = 0;
        for (var i = 0; i + 3 < _pixels.Length; i += 4)
        {
            if (_pixels[i] == colour.Blue && _pixels[i + 1] == colour.Green && _pixels[i + 2] == colour.Red && _pixels[i + 3] == 255)
            {
                n++;
            }
        }

        return n;
    }

    /// <summary>The Skia bitmap over the pixels (what the pane draws on).</summary>
    internal SKBitmap Bitmap { get; }

    /// <inheritdoc />
    /// <remarks>Frees the Skia wrapper only: the pixels stay valid for a view still showing them until the frame is collected.</remarks>
    public void Dispose() => Bitmap.Dispose();
}
