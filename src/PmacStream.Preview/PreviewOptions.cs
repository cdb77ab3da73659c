using System.Globalization;
using PmacStream.GCode;
using SkiaSharp;

namespace PmacStream.Preview;

/// <summary>The direction the toolpath is looked at.</summary>
public enum PreviewView
{
    /// <summary>From above: X right, Y up.</summary>
    XY,

    /// <summary>From the front: X right, Z up.</summary>
    XZ,

    /// <summary>From the side: Y right, Z up.</summary>
    YZ,

    /// <summary>Isometric, Z up: +X toward the upper right and +Y toward the upper left, both 30 degrees from the horizontal.</summary>
    Iso,
}

/// <summary>The colours of a preview.</summary>
public sealed record PreviewPalette
{
    /// <summary>Background.</summary>
    public SKColor Background { get; init; } = new(255, 255, 255);

    /// <summary>Feed moves (G01, G02, G03), solid.</summary>
    public SKColor Feed { get; init; } = new(31, 78, 158);

    /// <summary>Rapid moves (G00), dashed.</summary>
    public SKColor Rapid { get; init; } = new(230, 112, 0);

    /// <summary>Executed moves from the log (a wide band under the program), executed once.</summary>
    public SKColor Executed { get; init; } = new(120, 214, 120);

    /// <summary>Executed moves whose line ran more than once.</summary>
    public SKColor Repeated { get; init; } = new(230, 64, 230);

    /// <summary>Program moves the log never executed (only with a log).</summary>
    public SKColor Missing { get; init; } = new(214, 0, 0);

    /// <summary>Legend text and frame.</summary>
    public SKColor Text { get; init; } = new(40, 40, 40);

    /// <summary>The current-position marker.</summary>
    public SKColor Marker { get; init; } = new(214, 0, 0);
}

/// <summary>How to draw a preview.</summary>
public sealed record PreviewOptions
{
    /// <summary>Image width in pixels.</summary>
    public int Width { get; init; } = 1200;

    /// <summary>Image height in pixels.</summary>
    public int Height { get; init; } = 900;

    /// <summary>The view.</summary>
    public PreviewView View { get; init; } = PreviewView.XY;

    /// <summary>Draw the legend strip (extents, units, counts, key) at the bottom.</summary>
    public bool Legend { get; init; } = true;

    /// <summary>
    /// The legend's language: a Chinese culture (zh, zh-CN) writes it in Simplified Chinese when a font with Chinese
    /// glyphs is installed; anything else writes English.
    /// </summary>
    public CultureInfo Culture { get; init; } = CultureInfo.InvariantCulture;

    /// <summary>Colours.</summary>
    public PreviewPalette Palette { get; init; } = new();

    /// <summary>Rapid dash: pixels drawn.</summary>
    public int DashOn { get; init; } = 6;

    /// <summary>Rapid dash: pixels skipped.</summary>
    public int DashOff { get; init; } = 4;

    /// <summary>Width of the executed band in pixels.</summary>
    public int ExecutedWidth { get; init; } = 5;

    /// <summary>Progress (fraction 0..1 of all passes, stage text); called at most every 4096 moves.</summary>
    public Action<double, string>? Progress { get; init; }

    /// <summary>
    /// Asked after the measuring pass, before the picture and the drawing library take their memory: false stops with
    /// <see cref="PreviewRefusedException"/> (a program with errors is not drawn unless forced). Null: always draw.
    /// </summary>
    public Func<bool>? DrawIf { get; init; }
}

/// <summary>The measuring pass is done and <see cref="PreviewOptions.DrawIf"/> said not to draw.</summary>
public sealed class PreviewRefusedException : Exception
{
    /// <summary>A refusal to draw.</summary>
    public PreviewRefusedException()
        : base("not drawn: the program has errors")
    {
    }
}

/// <summary>Extents and counts of a toolpath (pass 1).</summary>
/// <param name="Min">Lowest X, Y, Z reached, arcs included (mm).</param>
/// <param name="Max">Highest X, Y, Z reached (mm).</param>
/// <param name="Rapids">G00 moves.</param>
/// <param name="Lines">G01 moves.</param>
/// <param name="Arcs">G02/G03 moves.</param>
public readonly record struct PreviewExtents(Point3 Min, Point3 Max, long Rapids, long Lines, long Arcs)
{
    /// <summary>Moves of every kind.</summary>
    public long Moves => Rapids + Lines + Arcs;

    /// <summary>True when the program has no move to draw.</summary>
    public bool IsEmpty => Moves == 0;
}
