using PmacStream.GCode;

namespace PmacStream.Preview;

/// <summary>How a segment moves the tool.</summary>
public enum PathMotion
{
    /// <summary>G00 positioning: drawn dashed in the rapid colour.</summary>
    Rapid,

    /// <summary>G01 straight feed.</summary>
    Linear,

    /// <summary>G02 clockwise arc (or helix) about the plane's normal.</summary>
    ArcCw,

    /// <summary>G03 counter-clockwise arc (or helix) about the plane's normal.</summary>
    ArcCcw,
}

/// <summary>The arc plane, numbered as its G code.</summary>
public enum ArcPlane
{
    /// <summary>G17: the XY plane, normal +Z, helix along Z.</summary>
    XY = 17,

    /// <summary>G18: the ZX plane, normal +Y, helix along Y.</summary>
    ZX = 18,

    /// <summary>G19: the YZ plane, normal +X, helix along X.</summary>
    YZ = 19,
}

/// <summary>
/// One move of the toolpath as the preview draws it: what the renderer consumes, one at a time, so a program of any
/// size is drawn without keeping its points. Coordinates are absolute and in millimetres.
/// </summary>
/// <param name="Motion">Rapid, linear or arc direction.</param>
/// <param name="Start">Absolute start point.</param>
/// <param name="End">Absolute end point.</param>
/// <param name="Center">Arc centre (its coordinate along the plane's normal is ignored); unused for straight moves.</param>
/// <param name="Plane">Arc plane; unused for straight moves.</param>
/// <param name="SourceLine">1-based source line of the block, for matching with the executed-move log.</param>
public readonly record struct PathSegment(
    PathMotion Motion,
    Point3 Start,
    Point3 End,
    Point3 Center = default,
    ArcPlane Plane = ArcPlane.XY,
    long SourceLine = 0)
{
    /// <summary>True for G02/G03.</summary>
    public bool IsArc => Motion is PathMotion.ArcCw or PathMotion.ArcCcw;

    /// <summary>A straight move.</summary>
    public static PathSegment Line(Point3 start, Point3 end, bool rapid = false, long sourceLine = 0) =>
        new(rapid ? PathMotion.Rapid : PathMotion.Linear, start, end, default, ArcPlane.XY, sourceLine);

    /// <summary>An arc or helix in <paramref name="plane"/>.</summary>
    public static PathSegment Arc(Point3 start, Point3 end, Point3 center, ArcPlane plane, bool clockwise, long sourceLine = 0) =>
        new(clockwise ? PathMotion.ArcCw : PathMotion.ArcCcw, start, end, center, plane, sourceLine);
}
