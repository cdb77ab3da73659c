using System.Globalization;
using PmacStream.GCode;
using Serilog;
using SkiaSharp;

namespace PmacStream.Preview;

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

/// <summary>
/// Draws a toolpath in bounded memory with Skia: pass 1 walks the program for its extents, pass 2 walks it again
/// drawing every move straight onto the canvas (nothing but the image and a few thousand points in flight are kept,
/// so a program of any length fits). Lines are antialiased; rapids are dashed in their own colour, feeds solid, arcs
/// are drawn as arcs (sampled by angle finely enough that the chord error stays under a quarter pixel) and helices as
/// arcs with the normal axis moving linearly. With an executed log, the executed path goes under the program as a
/// wide band (green once, magenta repeated): straight moves from the log's end points as the machine went, executed
/// arcs along the program's arc (the log has no centres); moves never executed are drawn red. Memory with a log adds
/// one byte (execution count) and one bit (is an arc) per line.
/// </summary>
public static class PreviewRenderer
{
    /// <summary>Largest picture drawn, in pixels (an 8192 x 8192 picture takes 256 MB).</summary>
    public const long MaxPixels = 64L * 1024 * 1024;

    private static readonly ILogger Logger = Log.ForContext(typeof(PreviewRenderer));

    /// <summary>Renders a G-code file (the HMI's preview panel): <c>RenderFile(path).WithMarker(position)</c>.</summary>
    public static PreviewPicture RenderFile(string path, PreviewOptions? options = null, string? executedLogPath = null, CancellationToken cancellationToken = default) =>
        Render(new GCodeToolpathSource(path), options, executedLogPath, cancellationToken);

    /// <summary>Renders <paramref name="source"/>; with <paramref name="executedLogPath"/>, overlays that log.</summary>
    public static PreviewPicture Render(IToolpathSource source, PreviewOptions? options = null, string? executedLogPath = null, CancellationToken cancellationToken = default)
    {
        options ??= new PreviewOptions();
        if (options.Width <= 0 || options.Height <= 0 || (long)options.Width * options.Height > MaxPixels)
        {
            throw new ArgumentOutOfRangeException(nameof(options), $"image size {options.Width}x{options.Height} is outside 1x1..64 megapixels");
        }

        var started = System.Diagnostics.Stopwatch.StartNew();
        var passes = executedLogPath is null ? 2.0 : 4.0;
        var pass = 0;
        void Report(double f, string stage) => options.Progress?.Invoke((pass + Math.Clamp(f, 0, 1)) / passes, stage);

        // The log holds only end points: an executed arc drawn from it would be a chord. Arc lines are noted here
        // (one bit a line) so their executed band is drawn along the program's arc instead.
        var arcLines = executedLogPath is null ? null : new LineSet();
        var multiMoveLines = executedLogPath is null ? null : new Dictionary<int, int>();
        var extents = Measure(source, arcLines, multiMoveLines, f => Report(f, "extents"), cancellationToken);
        pass++;
        ExecutionCounts? counts = null;
        var logBox = Box3.Empty;
        if (executedLogPath is not null)
        {
            (counts, logBox) = ReadExecuted(executedLogPath, multiMoveLines, cancellationToken);
            pass++;
        }

        if (options.DrawIf is { } drawIf && !drawIf())
        {
            throw new PreviewRefusedException();
        }

        var (min, max) = Bounds(extents, logBox);
        var palette = options.Palette;
        var layout = PreviewLayout.For(options);
        var projection = new ViewProjection(options.View, min, max, layout.PlotLeft, layout.PlotTop, layout.PlotWidth, layout.PlotHeight);
        // The platform's pixel order (BGRA on x64): Skia's fast blitters; other orders go through its slower general
        // pipeline (a third more CPU on a dense 1 GB program).
        var image = new SKBitmap(new SKImageInfo(options.Width, options.Height, SKImageInfo.PlatformColorType, SKAlphaType.Premul));
        var warnings = new List<string>();
        ExecutionReport? report = null;
        try
        {
            using var canvas = new SKCanvas(image);
            canvas.Clear(palette.Background);
            using (var pen = new PathPen(canvas, options.DashOn, options.DashOff))
            {
                if (executedLogPath is not null && counts is not null)
                {
                    report = new ExecutionReport { LogRows = counts.Rows };
                    DrawExecuted(pen, projection, executedLogPath, counts, arcLines!, options, cancellationToken);
                    pass++;
                }

                DrawProgram(pen, projection, source, options, counts, report, f => Report(f, "drawing"), cancellationToken);
                pen.Flush();
            }

            if (report is not null && counts is not null)
            {
                CountRepeats(report, counts);
            }

            if (options.Legend && layout.LegendHeight > 0)
            {
                DrawLegend(canvas, layout, projection, extents, source, options, report, warnings);
            }

            canvas.Flush();
        }
        catch
        {
            image.Dispose();
            throw;
        }

        Finished(source, options, extents, warnings, started);
        return new PreviewPicture(image, projection, extents, source.Units, report, palette, warnings);
    }

    private static void DrawLegend(SKCanvas canvas, PreviewLayout layout, ViewProjection projection, PreviewExtents extents, IToolpathSource source, PreviewOptions options, ExecutionReport? report, List<string> warnings)
    {
        using var font = new LegendFont(layout.FontSize);
        var chinese = WantsChinese(options.Culture, font, warnings);
        PreviewLegend.Draw(canvas, layout, font, chinese, projection, extents, source, options, report);
        Logger.Debug("Preview legend font {Family}, fallbacks {Fallbacks}, language {Language}", font.Family, string.Join(", ", font.Fallbacks), chinese ? "zh-CN" : "en");
    }

    /// <summary>Logs the picture's warnings and what was drawn, and reports the render done.</summary>
    private static void Finished(IToolpathSource source, PreviewOptions options, PreviewExtents extents, List<string> warnings, System.Diagnostics.Stopwatch started)
    {
        foreach (var warning in warnings)
        {
            Logger.Warning("Preview of {Name}: {Warning}", source.Name, warning);
        }

        options.Progress?.Invoke(1, "done");
        Logger.Information(
            "Preview of {Name}: {Moves} moves ({Rapids} rapid, {Lines} linear, {Arcs} arc), view {View}, {Width}x{Height}, {Ms} ms",
            source.Name, extents.Moves, extents.Rapids, extents.Lines, extents.Arcs, options.View, options.Width, options.Height, started.ElapsedMilliseconds);
    }

    /// <summary>The executed log's counts per line and the box its end points span.</summary>
    private static (ExecutionCounts Counts, Box3 Box) ReadExecuted(string executedLogPath, Dictionary<int, int>? multiMoveLines, CancellationToken cancellationToken)
    {
        // A block the program draws as several moves (a canned cycle, a reference return) may carry a tracking
        // assignment on each controller line: its marks in a row count once. A one-move block counts every mark.
        var counts = new ExecutionCounts(multiMoveLines);
        var logBox = Box3.Empty;
        foreach (var row in ExecutedLogReader.Read(executedLogPath, cancellationToken))
        {
            counts.Add(row.Line, row.BlockStart);
            logBox.Add(row.End);
        }

        return (counts, logBox);
    }

    /// <summary>The program's extents, grown to hold the executed moves.</summary>
    private static (Point3 Min, Point3 Max) Bounds(PreviewExtents extents, Box3 logBox)
    {
        var min = extents.Min;
        var max = extents.Max;
        if (!logBox.IsEmpty)
        {
            // Executed moves off the program's path must be in the picture too.
            min = extents.IsEmpty ? new Point3(logBox.MinX, logBox.MinY, logBox.MinZ)
                : new Point3(Math.Min(min.X, logBox.MinX), Math.Min(min.Y, logBox.MinY), Math.Min(min.Z, logBox.MinZ));
            max = extents.IsEmpty ? new Point3(logBox.MaxX, logBox.MaxY, logBox.MaxZ)
                : new Point3(Math.Max(max.X, logBox.MaxX), Math.Max(max.Y, logBox.MaxY), Math.Max(max.Z, logBox.MaxZ));
        }

        return (min, max);
    }

    /// <summary>The lines executed more than once, into the report.</summary>
    private static void CountRepeats(ExecutionReport report, ExecutionCounts counts)
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

    /// <summary>
    /// True when the legend is to be written in Chinese and can be: without a font with Chinese glyphs the labels
    /// would be empty boxes, so the legend falls back to English and says why.
    /// </summary>
    private static bool WantsChinese(CultureInfo culture, LegendFont font, List<string> warnings)
    {
        if (!font.CanDraw("X 0.5 mm"))
        {
            warnings.Add("no font is installed (fontconfig found none): the legend has no readable text; install fontconfig and a font such as fonts-dejavu-core or fonts-noto-cjk");
        }

        if (!culture.Name.StartsWith("zh", StringComparison.OrdinalIgnoreCase))
        {
            return false;
        }

        if (font.CanDraw(LegendText.AllChinese()))
        {
            return true;
        }

        warnings.Add("no installed font has Chinese glyphs: the legend is in English; install a CJK font such as fonts-noto-cjk");
        return false;
    }

    /// <summary>
    /// The program's extents; notes arc lines in <paramref name="arcLines"/> and, in <paramref name="multiMoveLines"/>,
    /// the lines drawn as more than one move in a row (value <see cref="int.MaxValue"/>: their marks fold).
    /// </summary>
    private static PreviewExtents Measure(IToolpathSource source, LineSet? arcLines, Dictionary<int, int>? multiMoveLines, Action<double>? progress, CancellationToken cancellationToken)
    {
        var box = Box3.Empty;
        long rapids = 0, lines = 0, arcs = 0, n = 0, previousLine = 0;
        foreach (var s in source.ReadSegments(cancellationToken))
        {
            if (multiMoveLines is not null && s.SourceLine == previousLine && s.SourceLine is > 0 and <= int.MaxValue)
            {
                multiMoveLines[(int)s.SourceLine] = int.MaxValue;
            }

            previousLine = s.SourceLine;
            if (s.IsArc)
            {
                arcs++;
                box.AddArc(s);
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
            : new PreviewExtents(new Point3(box.MinX, box.MinY, box.MinZ), new Point3(box.MaxX, box.MaxY, box.MaxZ), rapids, lines, arcs);
    }

    private static void DrawExecuted(PathPen pen, ViewProjection projection, string path, ExecutionCounts counts, LineSet arcLines, PreviewOptions options, CancellationToken cancellationToken)
    {
        var width = Math.Max(1, options.ExecutedWidth);
        var havePrevious = false;
        var previous = (X: 0.0, Y: 0.0);
        foreach (var row in ExecutedLogReader.Read(path, cancellationToken))
        {
            var p = projection.ToPixel(row.End);
            var colour = counts[row.Line] > 1 ? options.Palette.Repeated : options.Palette.Executed;
            var from = havePrevious ? previous : p;
            if (!arcLines.Contains(row.Line))
            {
                pen.Begin(from.X, from.Y, new StrokeLook(colour, width, false));
                pen.LineTo(p.X, p.Y);
            }

            previous = p;
            havePrevious = true;
        }
    }

    private static void DrawProgram(
        PathPen pen, ViewProjection projection, IToolpathSource source, PreviewOptions options, ExecutionCounts? counts,
        ExecutionReport? report, Action<double> progress, CancellationToken cancellationToken)
    {
        var palette = options.Palette;
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
                    DrawSegment(pen, projection, s, new StrokeLook(times > 1 ? palette.Repeated : palette.Executed, Math.Max(1, options.ExecutedWidth), false));
                }

                if (times == 0)
                {
                    colour = palette.Missing;
                    report.MissingLines++;
                    ExecutionReport.AddRun(report.MissingList, s.SourceLine, 0, previousMotionLine);
                }

                previousMotionLine = s.SourceLine;
            }

            DrawSegment(pen, projection, s, new StrokeLook(colour, 1, rapid));
            if ((++n & 0xFFF) == 0)
            {
                progress(source.PassFraction);
            }
        }
    }

    /// <summary>Draws one move; arcs as polylines fine enough to look round at this scale.</summary>
    internal static void DrawSegment(PathPen pen, ViewProjection projection, in PathSegment s, StrokeLook look)
    {
        var p0 = projection.ToPixel(s.Start);
        pen.Begin(p0.X, p0.Y, look);
        if (!s.IsArc)
        {
            var p1 = projection.ToPixel(s.End);
            pen.LineTo(p1.X, p1.Y);
            return;
        }

        var plane = (int)s.Plane;
        var (a0, sweep, rs, re) = ArcGeometry.Describe(s.Start, s.End, s.Center, plane, s.Motion == PathMotion.ArcCcw);
        var rpx = Math.Max(rs, re) * projection.Scale;
        // Chord error (sagitta) of a step of angle d at radius r: r(1 - cos(d/2)). Keep it under 0.25 px.
        var step = rpx > 0.5 ? 2 * Math.Acos(Math.Max(-1, 1 - (0.25 / rpx))) : Math.PI / 4;
        step = Math.Clamp(step, 1e-4, Math.PI / 18);
        var n = (int)Math.Min(200_000, Math.Ceiling(Math.Abs(sweep) / step));
        n = Math.Max(n, 1);
        for (var i = 1; i <= n; i++)
        {
            // t = 1 lands on the programmed end (the radius is interpolated to the end radius).
            var p = projection.ToPixel(ArcGeometry.PointAt(s.Start, s.End, s.Center, plane, a0, sweep, rs, re, (double)i / n));
            pen.LineTo(p.X, p.Y);
        }
    }
}
