using System.Diagnostics;
using PmacStream.GCode;
using SkiaSharp;

namespace PmacStream.Preview;

/// <summary>
/// Draws the executed part of a toolpath over its planned picture as execution advances, in one pass over the
/// program that never goes back: each call draws only the moves between the last one drawn and the block now
/// executing, so a program of any length costs one open reader and the interpreter's modal state, never a list of
/// its moves. The tracking variable names the executing block (<c>M0==line</c> is set as its move starts), so the
/// moves of earlier lines are done and are drawn; the tool stands at the end of the last of them.
/// </summary>
internal sealed class ExecutedPathTracer : IDisposable
{
    private readonly IEnumerator<PathSegment> _moves;
    private readonly ViewProjection _projection;
    private readonly PathPen _pen;
    private readonly StrokeLook _feed;
    private readonly StrokeLook _rapid;
    private bool _havePending;
    private bool _ended;

    /// <summary>Traces <paramref name="source"/> onto <paramref name="canvas"/> with the planned picture's projection.</summary>
    public ExecutedPathTracer(IToolpathSource source, ViewProjection projection, SKCanvas canvas, SKColor colour, float width, CancellationToken cancellationToken)
    {
        _moves = source.ReadSegments(cancellationToken).GetEnumerator();
        _projection = projection;
        _pen = new PathPen(canvas, 6, 4);
        _feed = new StrokeLook(colour, width, false);
        _rapid = new StrokeLook(colour, 1, true);
    }

    /// <summary>Where the tool stands after the last move drawn (or passed over), null before the first.</summary>
    public Point3? Position { get; private set; }

    /// <summary>Moves drawn so far.</summary>
    public long Drawn { get; private set; }

    /// <summary>True once the program's last move was drawn.</summary>
    public bool AtEnd => _ended && !_havePending;

    /// <summary>
    /// Passes over the moves before <paramref name="line"/> without drawing them (a job started from that line did
    /// not run them). Costs the interpretation of the lines passed; call it off the UI thread for a late start.
    /// </summary>
    public void SkipBefore(long line)
    {
        while (Peek() is { } s && s.SourceLine < line)
        {
            Position = s.End;
            _havePending = false;
        }
    }

    /// <summary>
    /// Draws the moves of the lines before <paramref name="executingLine"/> not drawn yet, for at most
    /// <paramref name="budget"/> (the rest on the next call). Returns the moves drawn.
    /// </summary>
    public int DrawBefore(long executingLine, TimeSpan budget)
    {
        var clock = Stopwatch.StartNew();
        var n = 0;
        while (Peek() is { } s && s.SourceLine < executingLine)
        {
            PreviewRenderer.DrawSegment(_pen, _projection, s, s.Motion == PathMotion.Rapid ? _rapid : _feed);
            Position = s.End;
            _havePending = false;
            n++;
            if ((n & 0xFF) == 0 && clock.Elapsed > budget)
            {
                break;
            }
        }

        _pen.Flush();
        Drawn += n;
        return n;
    }

    /// <inheritdoc />
    public void Dispose()
    {
        _moves.Dispose();
        _pen.Dispose();
    }

    private PathSegment? Peek()
    {
        if (_havePending)
        {
            return _moves.Current;
        }

        if (_ended || !_moves.MoveNext())
        {
            _ended = true;
            return null;
        }

        _havePending = true;
        return _moves.Current;
    }
}
