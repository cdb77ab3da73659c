using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>
/// Maps machine coordinates to image pixels for one view: the toolpath's projected extents fitted into the plot
/// area with equal scale on both axes, image y pointing down. Whole numbers are pixel centres.
/// </summary>
public sealed class ViewProjection
{
    private static readonly double Cos30 = Math.Sqrt(3) / 2;

    private readonly double _uMid;
    private readonly double _vMid;
    private readonly double _cx;
    private readonly double _cy;

    /// <summary>Fits the box <paramref name="min"/>..<paramref name="max"/> into the plot rectangle.</summary>
    public ViewProjection(PreviewView view, Point3 min, Point3 max, int left, int top, int width, int height)
    {
        View = view;
        double u0 = double.PositiveInfinity, u1 = double.NegativeInfinity, v0 = double.PositiveInfinity, v1 = double.NegativeInfinity;
        for (var corner = 0; corner < 8; corner++)
        {
            var p = new Point3((corner & 1) == 0 ? min.X : max.X, (corner & 2) == 0 ? min.Y : max.Y, (corner & 4) == 0 ? min.Z : max.Z);
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
    public static (double U, double V) Project(PreviewView view, Point3 p) => view switch
    {
        PreviewView.XY => (p.X, p.Y),
        PreviewView.XZ => (p.X, p.Z),
        PreviewView.YZ => (p.Y, p.Z),
        _ => ((p.X - p.Y) * Cos30, ((p.X + p.Y) * 0.5) + p.Z),
    };

    /// <summary>The pixel position (sub-pixel; whole numbers are pixel centres) of a point.</summary>
    public (double X, double Y) ToPixel(Point3 p)
    {
        var (u, v) = Project(View, p);
        return (_cx + ((u - _uMid) * Scale), _cy - ((v - _vMid) * Scale));
    }
}
