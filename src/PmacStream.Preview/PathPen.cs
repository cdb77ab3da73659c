using SkiaSharp;

namespace PmacStream.Preview;

/// <summary>How a stroke looks: colour, width in pixels (1 or less is a one-pixel hairline) and whether it is dashed.</summary>
/// <param name="Colour">Stroke colour.</param>
/// <param name="Width">Width in pixels.</param>
/// <param name="Dashed">Dashed with the pen's dash pattern.</param>
internal readonly record struct StrokeLook(SKColor Colour, float Width, bool Dashed);

/// <summary>
/// Draws a toolpath's moves on a Skia canvas in program order, antialiased, without keeping them: consecutive moves
/// of one look that join end to start become one polyline, stroked once it holds <see cref="MaxPoints"/> points or
/// the look changes, so millions of moves cost a few thousand draw calls and a fixed buffer. Points closer than
/// <see cref="MinStep"/> pixels to the last one drawn are merged (a dense program's moves inside one pixel). A dashed
/// polyline is stroked on its own, with the dash phase carried over when it is split, so dashes stay even along a
/// run of many short moves.
/// </summary>
internal sealed class PathPen : IDisposable
{
    /// <summary>Points per stroked polyline at most.</summary>
    public const int MaxPoints = 4096;

    /// <summary>Pixels a point must be from the last one drawn to be a new vertex.</summary>
    public const float MinStep = 0.2f;

    // Far-off points are clamped so that float coordinates keep their sub-pixel precision near the picture.
    private const double Limit = 1e6;

    private readonly SKCanvas _canvas;
    private readonly float[] _dash;
    private readonly SKPaint _paint = new() { IsAntialias = true, Style = SKPaintStyle.Stroke, StrokeCap = SKStrokeCap.Round, StrokeJoin = SKStrokeJoin.Round };
    private readonly SKPathBuilder _builder = new();
    private readonly SKPoint[] _points = new SKPoint[MaxPoints];
    private int _count;
    private int _builderPoints;
    private bool _pending;
    private SKPoint _last;
    private StrokeLook _look;
    private double _contourLength;
    private double _chunkStart;
    private double _batchPhase;

    /// <summary>A pen drawing on <paramref name="canvas"/>; dashed looks use <paramref name="dashOn"/> px on, <paramref name="dashOff"/> px off.</summary>
    public PathPen(SKCanvas canvas, float dashOn, float dashOff)
    {
        _canvas = canvas;
        _dash = [Math.Max(0.5f, dashOn), Math.Max(0.5f, dashOff)];
    }

    /// <summary>The canvas position of a pixel-centre coordinate (Skia puts pixel centres at half pixels).</summary>
    public static SKPoint ToCanvas(double x, double y) =>
        new((float)(Math.Clamp(x, -Limit, Limit) + 0.5), (float)(Math.Clamp(y, -Limit, Limit) + 0.5));

    /// <summary>Starts a move at (<paramref name="x"/>, <paramref name="y"/>): continues the polyline when it ends there in the same look.</summary>
    public void Begin(double x, double y, StrokeLook look)
    {
        var p = ToCanvas(x, y);
        if (look != _look)
        {
            Flush();
            _look = look;
        }
        else if (_count > 0 && SKPoint.DistanceSquared(p, _last) <= 1e-4f)
        {
            return;
        }

        EndContour();
        _points[0] = p;
        _count = 1;
        _last = p;
        _contourLength = 0;
        _chunkStart = 0;
    }

    /// <summary>Continues the move to (<paramref name="x"/>, <paramref name="y"/>).</summary>
    public void LineTo(double x, double y)
    {
        var p = ToCanvas(x, y);
        if (SKPoint.DistanceSquared(p, _points[_count - 1]) < MinStep * MinStep)
        {
            _last = p;
            _pending = true;
            return;
        }

        Append(p);
    }

    /// <summary>Strokes everything begun so far.</summary>
    public void Flush()
    {
        EndContour();
        if (_builderPoints == 0)
        {
            return;
        }

        using var path = _builder.Detach();
        _builderPoints = 0;
        _paint.Color = _look.Colour;
        _paint.StrokeWidth = _look.Width <= 1 ? 0 : _look.Width;
        // Round ends join a run of moves smoothly; dashes keep square ends so that they are as long as the pattern says.
        _paint.StrokeCap = _look.Dashed ? SKStrokeCap.Butt : SKStrokeCap.Round;
        using var dash = _look.Dashed ? SKPathEffect.CreateDash(_dash, (float)(_batchPhase % (_dash[0] + _dash[1]))) : null;
        _paint.PathEffect = dash;
        _canvas.DrawPath(path, _paint);
        _paint.PathEffect = null;
    }

    /// <inheritdoc />
    public void Dispose()
    {
        _paint.Dispose();
        _builder.Dispose();
    }

    private void Append(SKPoint p)
    {
        _pending = false;
        if (_count == MaxPoints)
        {
            // Full: stroke what there is and go on from its last point, with the dash phase it reached.
            var end = _points[_count - 1];
            Flush();
            _points[0] = end;
            _count = 1;
            _chunkStart = _contourLength;
        }

        _contourLength += SKPoint.Distance(_points[_count - 1], p);
        _points[_count++] = p;
        _last = p;
    }

    /// <summary>Moves the current polyline into the path; a dashed one is stroked at once so that each keeps its phase.</summary>
    private void EndContour()
    {
        if (_pending)
        {
            Append(_last);
        }

        if (_count == 0)
        {
            return;
        }

        if (_count == 1)
        {
            // A move shorter than a step still leaves a dot where it ran.
            _points[1] = _points[0];
            _count = 2;
        }

        if (_builderPoints == 0)
        {
            _batchPhase = _chunkStart;
        }

        _builder.AddPoly(_points.AsSpan(0, _count), false);
        _builderPoints += _count;
        _count = 0;
        if (_look.Dashed || _builderPoints >= MaxPoints)
        {
            Flush();
        }
    }
}
