using System.Globalization;
using PmacStream.GCode;
using SkiaSharp;

namespace PmacStream.Preview;

/// <summary>Where the plot and the legend go in a picture of a given size.</summary>
/// <param name="PlotLeft">Plot rectangle left, pixels.</param>
/// <param name="PlotTop">Plot rectangle top.</param>
/// <param name="PlotWidth">Plot rectangle width.</param>
/// <param name="PlotHeight">Plot rectangle height.</param>
/// <param name="LegendTop">Top of the legend's first text line.</param>
/// <param name="LegendHeight">Height of the legend strip (0: no legend).</param>
/// <param name="Scale">Size of the legend relative to a 500x400 picture (at least 1).</param>
/// <param name="LineHeight">Legend line pitch, pixels.</param>
internal readonly record struct PreviewLayout(int PlotLeft, int PlotTop, int PlotWidth, int PlotHeight, int LegendTop, int LegendHeight, float Scale, int LineHeight)
{
    /// <summary>Legend font size in pixels.</summary>
    public float FontSize => 8.5f * Scale;

    /// <summary>The layout for <paramref name="o"/>'s size.</summary>
    public static PreviewLayout For(PreviewOptions o)
    {
        var scale = Math.Max(1f, Math.Min(o.Width / 500f, o.Height / 400f));
        var margin = Math.Max(4, Math.Min(o.Width, o.Height) / 40);
        var lineHeight = (int)Math.Round(11 * scale);
        var legend = o.Legend ? (4 * lineHeight) + (int)Math.Round(6 * scale) : 0;
        if (legend > o.Height / 3)
        {
            legend = 0; // too small a picture for words
        }

        var plotHeight = Math.Max(1, o.Height - legend - (2 * margin));
        var plotWidth = Math.Max(1, o.Width - (2 * margin));
        return new PreviewLayout(margin, margin, plotWidth, plotHeight, o.Height - legend + (int)Math.Round(2 * scale), legend, scale, lineHeight);
    }
}

/// <summary>
/// The legend strip under the plot: file, view and units; extents; move counts (and the executed log's findings)
/// with a scale bar; and the key of colours. English, or Simplified Chinese when asked for and the fonts have it.
/// </summary>
internal static class PreviewLegend
{
    /// <summary>Draws the legend on <paramref name="canvas"/>.</summary>
    public static void Draw(
        SKCanvas canvas, PreviewLayout layout, LegendFont font, bool chinese, ViewProjection projection, PreviewExtents extents,
        IToolpathSource source, PreviewOptions options, ExecutionReport? report)
    {
        var p = options.Palette;
        var s = layout.Scale;
        var lh = layout.LineHeight;
        float x = layout.PlotLeft;
        float y = layout.LegendTop;
        string T(LegendTextId id) => LegendText.Get(id, chinese);
        using var text = new SKPaint { Color = p.Text, IsAntialias = true, Style = SKPaintStyle.Fill };
        using var rule = new SKPaint { Color = new SKColor(200, 200, 200), Style = SKPaintStyle.Fill };
        canvas.DrawRect(0, y - (4 * s), options.Width, 1, rule);

        var inch = source.Units == LengthUnits.Inches;
        var unit = inch ? "in" : "mm";
        var f = inch ? 1 / 25.4 : 1.0;
        var fmt = inch ? "0.0000" : "0.000";
        var ci = CultureInfo.InvariantCulture;
        string R(double v) => (v * f).ToString(fmt, ci);
        var viewText = T(options.View switch
        {
            PreviewView.XY => LegendTextId.ViewXY,
            PreviewView.XZ => LegendTextId.ViewXZ,
            PreviewView.YZ => LegendTextId.ViewYZ,
            _ => LegendTextId.ViewIso,
        });
        var unitsText = T(inch ? LegendTextId.UnitsInch : LegendTextId.UnitsMm) + (source.MixedUnits ? T(LegendTextId.UnitsMixed) : string.Empty);
        // Rotary axes are left out of the picture: the legend says which, so a 4-axis part is not read as 3-axis.
        var rotary = source.RotaryAxes.Length > 0 ? "   " + string.Format(ci, T(LegendTextId.Rotary), string.Join(' ', source.RotaryAxes.ToCharArray())) : string.Empty;
        font.Draw(canvas, $"{source.Name}   {viewText}   {unitsText}{rotary}", x, y, text);
        y += lh;
        font.Draw(canvas, extents.IsEmpty ? T(LegendTextId.NoMoves) : $"X {R(extents.Min.X)} .. {R(extents.Max.X)}   Y {R(extents.Min.Y)} .. {R(extents.Max.Y)}   Z {R(extents.Min.Z)} .. {R(extents.Max.Z)} {unit}", x, y, text);

        y += lh;
        var counts = string.Format(ci, T(LegendTextId.Moves), N(extents.Moves), N(extents.Lines), N(extents.Arcs), N(extents.Rapids));
        if (report is not null)
        {
            counts += "   " + string.Format(ci, T(LegendTextId.Executed), N(report.LogRows), N(report.MissingLines), N(report.RepeatedLines));
        }

        var used = font.Draw(canvas, counts, x, y, text);
        DrawScaleBar(canvas, font, text, x + used + (18 * s), y, s, projection.Scale, f, unit, options.Width);

        y += lh;
        var kx = x;
        kx = Key(canvas, font, text, kx, y, s, new StrokeLook(p.Feed, 1, false), options, T(LegendTextId.KeyFeed));
        kx = Key(canvas, font, text, kx, y, s, new StrokeLook(p.Rapid, 1, true), options, T(LegendTextId.KeyRapid));
        if (report is not null)
        {
            kx = Key(canvas, font, text, kx, y, s, new StrokeLook(p.Executed, 3 * s, false), options, T(LegendTextId.KeyExecuted));
            kx = Key(canvas, font, text, kx, y, s, new StrokeLook(p.Repeated, 3 * s, false), options, T(LegendTextId.KeyRepeated));
            Key(canvas, font, text, kx, y, s, new StrokeLook(p.Missing, 1, false), options, T(LegendTextId.KeyMissing));
        }
    }

    private static string N(long n) => n.ToString("N0", CultureInfo.InvariantCulture);

    /// <summary>A round length (1, 2 or 5 x 10^k) about 80 pixels long, with its value, if it fits the picture.</summary>
    private static void DrawScaleBar(SKCanvas canvas, LegendFont font, SKPaint text, float bx, float y, float s, double pixelsPerMm, double f, string unit, int width)
    {
        var target = 80.0 * s / 2 / pixelsPerMm * f;
        var pow = Math.Pow(10, Math.Floor(Math.Log10(target)));
        var nice = target / pow < 2 ? pow : target / pow < 5 ? 2 * pow : 5 * pow;
        var barPx = (float)(nice / f * pixelsPerMm);
        var label = $"{nice.ToString("0.####", CultureInfo.InvariantCulture)} {unit}";
        if (!double.IsFinite(nice) || barPx <= 2 || bx + barPx + (4 * s) + font.Measure(label) >= width)
        {
            return;
        }

        var by = y + (font.LineHeight / 2);
        var t = Math.Max(1, (float)Math.Round(s));
        canvas.DrawRect(bx, by, barPx, t, text);
        canvas.DrawRect(bx, by - (2 * s), t, 5 * s, text);
        canvas.DrawRect(bx + barPx - t, by - (2 * s), t, 5 * s, text);
        font.Draw(canvas, label, bx + barPx + (4 * s), y, text);
    }

    /// <summary>One key entry: a short stroke in the look, then its label; returns where the next entry starts.</summary>
    private static float Key(SKCanvas canvas, LegendFont font, SKPaint text, float x, float y, float s, StrokeLook look, PreviewOptions options, string label)
    {
        var len = 24 * s;
        var yy = y + (font.LineHeight / 2);
        using (var pen = new PathPen(canvas, options.DashOn, options.DashOff))
        {
            // Whole pixel rows, so a one-pixel key line is as crisp as the toolpath's horizontal moves.
            var row = Math.Round(yy - 0.5);
            pen.Begin(x, row, look);
            pen.LineTo(x + len, row);
            pen.Flush();
        }

        var w = font.Draw(canvas, label, x + len + (4 * s), y, text);
        return x + len + (4 * s) + w + (12 * s);
    }
}
