using System.Globalization;
using Serilog;

using PmacStream.GCode;

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
    public Rgba Background { get; init; } = new(255, 255, 255);

    /// <summary>Feed moves (G01, G02, G03), solid.</summary>
    public Rgba Feed { get; init; } = new(31, 78, 158);

    /// <summary>Rapid moves (G00), dashed.</summary>
    public Rgba Rapid { get; init; } = new(230, 112, 0);

    /// <summary>Executed moves from the log (a wide band under the program), executed once.</summary>
    public Rgba Executed { get; init; } = new(120, 214, 120);

    /// <summary>Executed moves whose line ran more than once.</summary>
    public Rgba Repeated { get; init; } = new(230, 64, 230);

    /// <summary>Program moves the log never executed (only with a log).</summary>
    public Rgba Missing { get; init; } = new(214, 0, 0);

    /// <summary>Legend text and frame.</summary>
    public Rgba Text { get; init; } = new(40, 40, 40);

    /// <summary>The current-position marker.</summary>
    public Rgba Marker { get; init; } = new(214, 0, 0);
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
}

/// <summary>Extents and counts of a toolpath (pass 1).</summary>
/// <param name="Min">Lowest X, Y, Z reached, arcs included (mm).</param>
/// <param name="Max">Highest X, Y, Z reached (mm).</param>
/// <param name="Rapids">G00 moves.</param>
/// <param name="Lines">G01 moves.</param>
/// <param name="Arcs">G02/G03 moves.</param>
public readonly record struct PreviewExtents(Point3D Min, Point3D Max, long Rapids, long Lines, long Arcs)
{
    /// <summary>Moves of every kind.</summary>
    public long Moves => Rapids + Lines + Arcs;

    /// <summary>True when the program has no move to draw.</summary>
    public bool IsEmpty => Moves == 0;
}

/// <summary>
/// Maps machine coordinates to image pixels for one view: the toolpath's projected extents fitted into the plot
/// area with equal scale on both axes, image y pointing down.
/// </summary>
public sealed class ViewProjection
{
    private static readonly double Cos30 = Math.Sqrt(3) / 2;

    private readonly double _uMid;
    private readonly double _vMid;
    private readonly double _cx;
    private readonly double _cy;

    /// <summary>Fits the box <paramref name="min"/>..<paramref name="max"/> into the plot rectangle.</summary>
    public ViewProjection(PreviewView view, Point3D min, Point3D max, int left, int top, int width, int height)
    {
        View = view;
        double u0 = double.PositiveInfinity, u1 = double.NegativeInfinity, v0 = double.PositiveInfinity, v1 = double.NegativeInfinity;
        for (var corner = 0; corner < 8; corner++)
        {
            var p = new Point3D((corner & 1) == 0 ? min.X : max.X, (corner & 2) == 0 ? min.Y : max.Y, (corner & 4) == 0 ? min.Z : max.Z);
            var (u, v) = Project(view, p);
            u0 = Math.Min(u0, u);
            u1 = Math.Max(u1, u);
            v0 = Math.Min(v0, v);
            v1 = Math.Max(v1, v);
        }

        var du = u1 - u0;
        var dv = v1 - v0;
        var sx = du > 1e-12 ? (width - 1) / du : double.PositiveInfinity;
        var sy = dv > 1e-12 ? (height - 1) / dv : double.PositiveInfinity;
        Scale = Math.Min(sx, sy);
        if (double.IsInfinity(Scale))
        {
            Scale = 1; // a single point: any scale will do
        }

        _uMid = (u0 + u1) / 2;
        _vMid = (v0 + v1) / 2;
        _cx = left + ((width - 1) / 2.0);
        _cy = top + ((height - 1) / 2.0);
    }

    /// <summary>The view.</summary>
    public PreviewView View { get; }

    /// <summary>Pixels per millimetre.</summary>
    public double Scale { get; }

    /// <summary>The view's horizontal and vertical coordinate of a point (mm, vertical up).</summary>
    public static (double U, double V) Project(PreviewView view, Point3D p) => view switch
    {
        PreviewView.XY => (p.X, p.Y),
        PreviewView.XZ => (p.X, p.Z),
        PreviewView.YZ => (p.Y, p.Z),
        _ => ((p.X - p.Y) * Cos30, ((p.X + p.Y) * 0.5) + p.Z),
    };

    /// <summary>The pixel position (sub-pixel) of a point.</summary>
    public (double X, double Y) ToPixel(Point3D p)
    {
        var (u, v) = Project(View, p);
        return (_cx + ((u - _uMid) * Scale), _cy - ((v - _vMid) * Scale));
    }

    /// <summary>The nearest pixel of a point, clamped far outside so integer maths cannot overflow.</summary>
    internal (int X, int Y) ToPixelInt(Point3D p)
    {
        var (x, y) = ToPixel(p);
        const double limit = 1e8;
        return ((int)Math.Round(Math.Clamp(x, -limit, limit)), (int)Math.Round(Math.Clamp(y, -limit, limit)));
    }
}

/// <summary>A set of line numbers, one bit each, growing as needed.</summary>
internal sealed class LineSet
{
    private ulong[] _bits = new ulong[64];

    public void Add(long line)
    {
        if (line < 0 || line > int.MaxValue)
        {
            return;
        }

        var word = (int)(line >> 6);
        if (word >= _bits.Length)
        {
            Array.Resize(ref _bits, Math.Max(word + 1, _bits.Length * 2));
        }

        _bits[word] |= 1UL << (int)(line & 63);
    }

    public bool Contains(long line)
    {
        var word = line >> 6;
        return line >= 0 && word < _bits.Length && (_bits[word] & (1UL << (int)(line & 63))) != 0;
    }
}

/// <summary>A rendered preview: the image, how it maps coordinates, and what was found.</summary>
public sealed class PreviewPicture
{
    internal PreviewPicture(RgbaImage image, ViewProjection projection, PreviewExtents extents, LengthUnits units, ExecutionReport? execution, PreviewPalette palette)
    {
        Image = image;
        Projection = projection;
        Extents = extents;
        Units = units;
        Execution = execution;
        Palette = palette;
    }

    /// <summary>The picture (draw on a <see cref="RgbaImage.Clone"/> to keep it).</summary>
    public RgbaImage Image { get; }

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

    /// <summary>A copy of the picture with a cross-hair marker at <paramref name="position"/> (e.g. the executing position).</summary>
    public RgbaImage WithMarker(Point3D position)
    {
        var copy = Image.Clone();
        DrawMarker(copy, position);
        return copy;
    }

    /// <summary>Draws the marker on <paramref name="target"/> (same size as <see cref="Image"/>).</summary>
    public void DrawMarker(RgbaImage target, Point3D position)
    {
        var (x, y) = Projection.ToPixelInt(position);
        var c = Palette.Marker;
        const int r = 9;
        target.DrawLine(x - r - 4, y, x - 3, y, c, 2);
        target.DrawLine(x + 3, y, x + r + 4, y, c, 2);
        target.DrawLine(x, y - r - 4, x, y - 3, c, 2);
        target.DrawLine(x, y + 3, x, y + r + 4, c, 2);
        const int steps = 48;
        for (var i = 0; i < steps; i++)
        {
            var a0 = 2 * Math.PI * i / steps;
            var a1 = 2 * Math.PI * (i + 1) / steps;
            target.DrawLine(x + (int)Math.Round(r * Math.Cos(a0)), y + (int)Math.Round(r * Math.Sin(a0)), x + (int)Math.Round(r * Math.Cos(a1)), y + (int)Math.Round(r * Math.Sin(a1)), c, 2);
        }
    }

    /// <summary>The picture as PNG bytes.</summary>
    public byte[] ToPng() => PngEncoder.Encode(Image);

    /// <summary>The picture with a marker at <paramref name="position"/>, as PNG bytes.</summary>
    public byte[] ToPng(Point3D position) => PngEncoder.Encode(WithMarker(position));
}

/// <summary>
/// Draws a toolpath in bounded memory: pass 1 walks the program for its extents, pass 2 walks it again drawing every
/// move straight into the pixel buffer (nothing but the image is kept, so a program of any length fits). Rapids are
/// dashed in their own colour, feeds solid, arcs are drawn as arcs (sampled by angle finely enough that the chord
/// error stays under a quarter pixel) and helices as arcs with the normal axis moving linearly. With an executed log,
/// the executed path goes under the program as a wide band (green once, magenta repeated): straight moves from the
/// log's end points as the machine went, executed arcs along the program's arc (the log has no centres); moves never
/// executed are drawn red. Memory with a log adds one byte (execution count) and one bit (is an arc) per line.
/// </summary>
public static class PreviewRenderer
{
    private static readonly ILogger Logger = Log.ForContext(typeof(PreviewRenderer));

    /// <summary>Renders a G-code file (the HMI's preview panel): <c>RenderFile(path).WithMarker(position)</c>.</summary>
    public static PreviewPicture RenderFile(string path, PreviewOptions? options = null, string? executedLogPath = null, CancellationToken cancellationToken = default) =>
        Render(new GCodeToolpathSource(path), options, executedLogPath, cancellationToken);

    /// <summary>Pass 1 alone: the toolpath's extents and move counts.</summary>
    public static PreviewExtents MeasureExtents(IToolpathSource source, CancellationToken cancellationToken = default) =>
        Measure(source, null, null, cancellationToken);

    /// <summary>Renders <paramref name="source"/>; with <paramref name="executedLogPath"/>, overlays that log.</summary>
    public static PreviewPicture Render(IToolpathSource source, PreviewOptions? options = null, string? executedLogPath = null, CancellationToken cancellationToken = default)
    {
        options ??= new PreviewOptions();
        var started = System.Diagnostics.Stopwatch.StartNew();
        var passes = executedLogPath is null ? 2.0 : 4.0;
        var pass = 0;
        void Report(double f, string stage) => options.Progress?.Invoke((pass + Math.Clamp(f, 0, 1)) / passes, stage);

        ExecutionCounts? counts = null;
        var logBox = Box3.Empty;
        if (executedLogPath is not null)
        {
            counts = new ExecutionCounts();
            foreach (var row in ExecutedLogReader.Read(executedLogPath, cancellationToken))
            {
                counts.Add(row.Line);
                logBox.Add(row.End);
            }

            pass++;
        }

        // The log holds only end points: an executed arc drawn from it would be a chord. Arc lines are noted here
        // (one bit a line) so their executed band is drawn along the program's arc instead.
        var arcLines = executedLogPath is null ? null : new LineSet();
        var extents = Measure(source, arcLines, f => Report(f, "extents"), cancellationToken);
        pass++;
        var min = extents.Min;
        var max = extents.Max;
        if (!logBox.IsEmpty)
        {
            // Executed moves off the program's path must be in the picture too.
            min = extents.IsEmpty ? new Point3D(logBox.MinX, logBox.MinY, logBox.MinZ)
                : new Point3D(Math.Min(min.X, logBox.MinX), Math.Min(min.Y, logBox.MinY), Math.Min(min.Z, logBox.MinZ));
            max = extents.IsEmpty ? new Point3D(logBox.MaxX, logBox.MaxY, logBox.MaxZ)
                : new Point3D(Math.Max(max.X, logBox.MaxX), Math.Max(max.Y, logBox.MaxY), Math.Max(max.Z, logBox.MaxZ));
        }

        var palette = options.Palette;
        var image = new RgbaImage(options.Width, options.Height, palette.Background);
        var layout = Layout.For(options);
        var projection = new ViewProjection(options.View, min, max, layout.PlotLeft, layout.PlotTop, layout.PlotWidth, layout.PlotHeight);

        ExecutionReport? report = null;
        if (executedLogPath is not null && counts is not null)
        {
            report = new ExecutionReport { LogRows = counts.Rows };
            DrawExecuted(image, projection, executedLogPath, counts, arcLines!, options, cancellationToken);
            pass++;
        }

        DrawProgram(image, projection, source, options, counts, report, f => Report(f, "drawing"), cancellationToken);
        if (report is not null && counts is not null)
        {
            for (var line = 1L; line <= counts.MaxLine; line++)
            {
                var times = counts[line];
                if (times > 1)
                {
                    report.RepeatedLines++;
                    ExecutionReport.AddRun(report.RepeatedList, line, times, line - 1);
                }
            }
        }

        if (options.Legend && layout.LegendHeight > 0)
        {
            DrawLegend(image, layout, projection, extents, source, options, report);
        }

        options.Progress?.Invoke(1, "done");
        Logger.Information(
            "Preview of {Name}: {Moves} moves ({Rapids} rapid, {Lines} linear, {Arcs} arc), view {View}, {Width}x{Height}, {Ms} ms",
            source.Name, extents.Moves, extents.Rapids, extents.Lines, extents.Arcs, options.View, options.Width, options.Height, started.ElapsedMilliseconds);
        return new PreviewPicture(image, projection, extents, source.Units, report, palette);
    }

    private static PreviewExtents Measure(IToolpathSource source, LineSet? arcLines, Action<double>? progress, CancellationToken cancellationToken)
    {
        var box = Box3.Empty;
        long rapids = 0, lines = 0, arcs = 0, n = 0;
        foreach (var s in source.ReadSegments(cancellationToken))
        {
            if (s.IsArc)
            {
                arcs++;
                ArcGeometry.Extend(s, ref box);
                arcLines?.Add(s.SourceLine);
            }
            else
            {
                if (s.Motion == PathMotion.Rapid)
                {
                    rapids++;
                }
                else
                {
                    lines++;
                }

                box.Add(s.Start);
                box.Add(s.End);
            }

            if ((++n & 0xFFF) == 0)
            {
                progress?.Invoke(source.PassFraction);
            }
        }

        return box.IsEmpty
            ? new PreviewExtents(default, default, 0, 0, 0)
            : new PreviewExtents(new Point3D(box.MinX, box.MinY, box.MinZ), new Point3D(box.MaxX, box.MaxY, box.MaxZ), rapids, lines, arcs);
    }

    private static void DrawExecuted(RgbaImage image, ViewProjection projection, string path, ExecutionCounts counts, LineSet arcLines, PreviewOptions options, CancellationToken cancellationToken)
    {
        var width = Math.Max(1, options.ExecutedWidth);
        var havePrevious = false;
        var previous = (X: 0, Y: 0);
        foreach (var row in ExecutedLogReader.Read(path, cancellationToken))
        {
            var p = projection.ToPixelInt(row.End);
            var colour = counts[row.Line] > 1 ? options.Palette.Repeated : options.Palette.Executed;
            var from = havePrevious ? previous : p;
            if (!arcLines.Contains(row.Line))
            {
                image.DrawLine(from.X, from.Y, p.X, p.Y, colour, width);
            }

            previous = p;
            havePrevious = true;
        }
    }

    private static void DrawProgram(
        RgbaImage image, ViewProjection projection, IToolpathSource source, PreviewOptions options, ExecutionCounts? counts,
        ExecutionReport? report, Action<double> progress, CancellationToken cancellationToken)
    {
        var palette = options.Palette;
        var rapidDash = new DashPattern(options.DashOn, options.DashOff);
        var solid = DashPattern.Solid;
        var previousMotionLine = -1L;
        long n = 0;
        foreach (var s in source.ReadSegments(cancellationToken))
        {
            var rapid = s.Motion == PathMotion.Rapid;
            var colour = rapid ? palette.Rapid : palette.Feed;
            if (counts is not null && report is not null && s.SourceLine > 0)
            {
                var times = counts[s.SourceLine];
                if (s.IsArc && times > 0)
                {
                    DrawSegment(image, projection, s, times > 1 ? palette.Repeated : palette.Executed, ref solid, Math.Max(1, options.ExecutedWidth));
                }

                if (times == 0)
                {
                    colour = palette.Missing;
                    report.MissingLines++;
                    ExecutionReport.AddRun(report.MissingList, s.SourceLine, 0, previousMotionLine);
                }

                previousMotionLine = s.SourceLine;
            }

            if (rapid)
            {
                DrawSegment(image, projection, s, colour, ref rapidDash);
            }
            else
            {
                DrawSegment(image, projection, s, colour, ref solid);
            }

            if ((++n & 0xFFF) == 0)
            {
                progress(source.PassFraction);
            }
        }
    }

    /// <summary>Draws one move; arcs as polylines fine enough to look round at this scale.</summary>
    internal static void DrawSegment(RgbaImage image, ViewProjection projection, in PathSegment s, Rgba colour, ref DashPattern dash, int width = 1)
    {
        var p0 = projection.ToPixelInt(s.Start);
        if (!s.IsArc)
        {
            var p1 = projection.ToPixelInt(s.End);
            image.DrawLine(p0.X, p0.Y, p1.X, p1.Y, colour, width, ref dash);
            return;
        }

        var (a0, sweep, rs, re) = ArcGeometry.Describe(s);
        var rpx = Math.Max(rs, re) * projection.Scale;
        // Chord error (sagitta) of a step of angle d at radius r: r(1 - cos(d/2)). Keep it under 0.25 px.
        var step = rpx > 0.5 ? 2 * Math.Acos(Math.Max(-1, 1 - (0.25 / rpx))) : Math.PI / 4;
        step = Math.Clamp(step, 1e-4, Math.PI / 18);
        var n = (int)Math.Min(200_000, Math.Ceiling(Math.Abs(sweep) / step));
        n = Math.Max(n, 1);
        var previous = p0;
        for (var i = 1; i <= n; i++)
        {
            // t = 1 lands on the programmed end (the radius is interpolated to the end radius).
            var p = ArcGeometry.PointAt(s, a0, sweep, rs, re, (double)i / n);
            var q = projection.ToPixelInt(p);
            if (q != previous || i == n)
            {
                image.DrawLine(previous.X, previous.Y, q.X, q.Y, colour, width, ref dash);
                previous = q;
            }
        }
    }

    private static void DrawLegend(RgbaImage image, Layout layout, ViewProjection projection, PreviewExtents extents, IToolpathSource source, PreviewOptions options, ExecutionReport? report)
    {
        var p = options.Palette;
        var s = layout.TextScale;
        var lh = layout.LineHeight;
        var x = layout.PlotLeft;
        var y = layout.LegendTop;
        image.FillRect(0, y - (s * 4), image.Width, 1, new Rgba(200, 200, 200));
        var inch = source.Units == LengthUnits.Inches;
        var unit = inch ? "in" : "mm";
        var f = inch ? 1 / 25.4 : 1.0;
        var fmt = inch ? "0.0000" : "0.000";
        string R(double v) => (v * f).ToString(fmt, CultureInfo.InvariantCulture);
        var viewText = options.View switch
        {
            PreviewView.XY => "view XY (X right, Y up)",
            PreviewView.XZ => "view XZ (X right, Z up)",
            PreviewView.YZ => "view YZ (Y right, Z up)",
            _ => "view ISO (X up-right, Y up-left, Z up)",
        };
        var unitsText = (inch ? "units inch (G20)" : "units mm (G21)") + (source.MixedUnits ? ", G20/G21 mixed" : string.Empty);
        image.DrawText(x, y, $"{source.Name}   {viewText}   {unitsText}", p.Text, s);
        y += lh;
        if (extents.IsEmpty)
        {
            image.DrawText(x, y, "no moves to draw", p.Text, s);
        }
        else
        {
            image.DrawText(x, y, $"X {R(extents.Min.X)} .. {R(extents.Max.X)}   Y {R(extents.Min.Y)} .. {R(extents.Max.Y)}   Z {R(extents.Min.Z)} .. {R(extents.Max.Z)} {unit}", p.Text, s);
        }

        y += lh;
        var ci = CultureInfo.InvariantCulture;
        var counts = $"moves {extents.Moves.ToString("N0", ci)}: {extents.Lines.ToString("N0", ci)} linear, {extents.Arcs.ToString("N0", ci)} arc, {extents.Rapids.ToString("N0", ci)} rapid";
        if (report is not null)
        {
            counts += $"   executed rows {report.LogRows.ToString("N0", ci)}, never run {report.MissingLines.ToString("N0", ci)}, repeated {report.RepeatedLines.ToString("N0", ci)}";
        }

        var used = image.DrawText(x, y, counts, p.Text, s);

        // Scale bar: a round length (1, 2 or 5 x 10^k) about 80 pixels long.
        var target = 80.0 * s / 2 / projection.Scale * f;
        var pow = Math.Pow(10, Math.Floor(Math.Log10(target)));
        var nice = target / pow < 2 ? pow : target / pow < 5 ? 2 * pow : 5 * pow;
        var barPx = (int)Math.Round(nice / f * projection.Scale);
        var bx = x + used + (6 * 3 * s);
        if (double.IsFinite(nice) && barPx > 2 && bx + barPx + (12 * 6 * s) < image.Width)
        {
            var by = y + (3 * s);
            image.FillRect(bx, by, barPx, Math.Max(1, s), p.Text);
            image.FillRect(bx, by - (2 * s), Math.Max(1, s), 5 * s, p.Text);
            image.FillRect(bx + barPx - Math.Max(1, s), by - (2 * s), Math.Max(1, s), 5 * s, p.Text);
            image.DrawText(bx + barPx + (4 * s), y, $"{nice.ToString("0.####", ci)} {unit}", p.Text, s);
        }

        y += lh;
        var kx = x;
        kx = Key(image, kx, y, s, p.Feed, false, 1, "feed", p.Text);
        kx = Key(image, kx, y, s, p.Rapid, true, 1, "rapid", p.Text);
        if (report is not null)
        {
            kx = Key(image, kx, y, s, p.Executed, false, 3, "executed", p.Text);
            kx = Key(image, kx, y, s, p.Repeated, false, 3, "executed twice+", p.Text);
            Key(image, kx, y, s, p.Missing, false, 1, "never executed", p.Text);
        }
    }

    private static int Key(RgbaImage image, int x, int y, int s, Rgba colour, bool dashed, int width, string label, Rgba text)
    {
        var len = 24 * s;
        var yy = y + (3 * s);
        var dash = dashed ? new DashPattern(6, 4) : DashPattern.Solid;
        image.DrawLine(x, yy, x + len, yy, colour, width * s, ref dash);
        var w = image.DrawText(x + len + (4 * s), y, label, text, s);
        return x + len + (4 * s) + w + (12 * s);
    }

    /// <summary>Where the plot and the legend go.</summary>
    private readonly record struct Layout(int PlotLeft, int PlotTop, int PlotWidth, int PlotHeight, int LegendTop, int LegendHeight, int TextScale, int LineHeight)
    {
        public static Layout For(PreviewOptions o)
        {
            var scale = Math.Max(1, Math.Min(o.Width / 500, o.Height / 400));
            var margin = Math.Max(4, Math.Min(o.Width, o.Height) / 40);
            var lineHeight = 11 * scale;
            var legend = o.Legend ? (4 * lineHeight) + (6 * scale) : 0;
            if (legend > o.Height / 3)
            {
                legend = 0; // too small a picture for words
            }

            var plotHeight = Math.Max(1, o.Height - legend - (2 * margin));
            var plotWidth = Math.Max(1, o.Width - (2 * margin));
            return new Layout(margin, margin, plotWidth, plotHeight, o.Height - legend + (2 * scale), legend, scale, lineHeight);
        }
    }
}
