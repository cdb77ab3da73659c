namespace PmacStream.GCode;

/// <summary>
/// The programmable transformations of FANUC milling, applied to programmed positions before the work offset, in
/// FANUC's order: mirror image (G51.1) first, then scaling (G51), then coordinate system rotation (G68) in the plane
/// selected when it was commanded (FANUC B-63944EN-2/02, 6.x "Scaling and coordinate system rotation": "the scaling
/// is applied first and then the coordinates are rotated"). Positions are program coordinates in millimetres.
/// </summary>
internal sealed class ProgramTransform
{
    private Point3 _mirrorCentre;
    private bool _mx, _my, _mz;
    private Point3 _scaleCentre;
    private double _sx = 1, _sy = 1, _sz = 1;
    private Point3 _rotCentre;
    private double _cos = 1, _sin;

    /// <summary>Whether any of mirror, scaling or rotation is in force.</summary>
    public bool Active => Mirroring || Scaling || Rotating;

    /// <summary>G51.1 in force.</summary>
    public bool Mirroring { get; private set; }

    /// <summary>G51 in force.</summary>
    public bool Scaling { get; private set; }

    /// <summary>G68 in force.</summary>
    public bool Rotating { get; private set; }

    /// <summary>The plane of the rotation (17, 18, 19).</summary>
    public int RotationPlane { get; private set; } = 17;

    /// <summary>The rotation angle in degrees.</summary>
    public double Angle { get; private set; }

    /// <summary>G51.1: mirror the named axes about the given coordinates.</summary>
    public void Mirror(double? x, double? y, double? z)
    {
        (_mx, _my, _mz) = (x.HasValue, y.HasValue, z.HasValue);
        _mirrorCentre = new Point3(x ?? 0, y ?? 0, z ?? 0);
        Mirroring = _mx || _my || _mz;
    }

    /// <summary>G50.1.</summary>
    public void CancelMirror() => (Mirroring, _mx, _my, _mz) = (false, false, false, false);

    /// <summary>G51: scale by the factors about the centre.</summary>
    public void Scale(Point3 centre, double fx, double fy, double fz)
    {
        (_scaleCentre, _sx, _sy, _sz) = (centre, fx, fy, fz);
        Scaling = true;
    }

    /// <summary>G50.</summary>
    public void CancelScale() => (Scaling, _sx, _sy, _sz) = (false, 1, 1, 1);

    /// <summary>
    /// G68: rotate by <paramref name="degrees"/> (counter-clockwise seen from the plane's positive normal) about
    /// <paramref name="centre"/>, given in program coordinates: mirror and scaling in force apply to it too.
    /// </summary>
    public void Rotate(int plane, Point3 centre, double degrees)
    {
        var radians = degrees * Math.PI / 180.0;
        (RotationPlane, Angle, _cos, _sin) = (plane, degrees, Math.Cos(radians), Math.Sin(radians));
        _rotCentre = ScaleMirror(centre);
        Rotating = true;
    }

    /// <summary>G69.</summary>
    public void CancelRotation() => (Rotating, Angle, _cos, _sin) = (false, 0, 1, 0);

    /// <summary>A programmed point where the transformations put it.</summary>
    public Point3 Apply(Point3 p) => RotateAbout(ScaleMirror(p), _rotCentre, _sin);

    /// <summary>A programmed vector (an incremental move, an arc's centre from its start) as the transformations turn it.</summary>
    public Point3 ApplyVector(Point3 d) => RotateAbout(new Point3(d.X * FactorX, d.Y * FactorY, d.Z * FactorZ), default, _sin);

    /// <summary>The programmed point that <see cref="Apply"/> puts at <paramref name="q"/>.</summary>
    public Point3 Inverse(Point3 q)
    {
        var s = RotateAbout(q, _rotCentre, -_sin);
        var m = new Point3(_scaleCentre.X + ((s.X - _scaleCentre.X) / _sx), _scaleCentre.Y + ((s.Y - _scaleCentre.Y) / _sy), _scaleCentre.Z + ((s.Z - _scaleCentre.Z) / _sz));
        return new Point3(_mx ? (2 * _mirrorCentre.X) - m.X : m.X, _my ? (2 * _mirrorCentre.Y) - m.Y : m.Y, _mz ? (2 * _mirrorCentre.Z) - m.Z : m.Z);
    }

    /// <summary>The signed factor along X (scaling times -1 when mirrored).</summary>
    public double FactorX => _mx ? -_sx : _sx;

    /// <summary>The signed factor along Y.</summary>
    public double FactorY => _my ? -_sy : _sy;

    /// <summary>The signed factor along Z.</summary>
    public double FactorZ => _mz ? -_sz : _sz;

    /// <summary>A single axis's value when the rotation does not turn that axis (a cycle's Z levels under a G17 rotation).</summary>
    public double ApplyZ(double z) => _scaleCentre.Z + ((( _mz ? (2 * _mirrorCentre.Z) - z : z) - _scaleCentre.Z) * _sz);

    /// <summary>The signed factors of a plane's two axes (17: X Y, 18: Z X, 19: Y Z).</summary>
    public (double First, double Second) PlaneFactors(int plane) => plane switch
    {
        18 => (FactorZ, FactorX),
        19 => (FactorY, FactorZ),
        _ => (FactorX, FactorY),
    };

    /// <summary>Whether the rotation turns the given plane out of itself (a rotation in another plane by an angle that is not a multiple of 180 degrees).</summary>
    public bool TiltsPlane(int plane) => Rotating && plane != RotationPlane && Math.Abs(_sin) > 1e-12;

    private Point3 ScaleMirror(Point3 p)
    {
        var m = new Point3(_mx ? (2 * _mirrorCentre.X) - p.X : p.X, _my ? (2 * _mirrorCentre.Y) - p.Y : p.Y, _mz ? (2 * _mirrorCentre.Z) - p.Z : p.Z);
        return new Point3(_scaleCentre.X + ((m.X - _scaleCentre.X) * _sx), _scaleCentre.Y + ((m.Y - _scaleCentre.Y) * _sy), _scaleCentre.Z + ((m.Z - _scaleCentre.Z) * _sz));
    }

    private Point3 RotateAbout(Point3 p, Point3 c, double sin)
    {
        if (!Rotating)
        {
            return p;
        }

        // In the plane's (first, second) axes: G17 X Y, G18 Z X, G19 Y Z, so a positive angle is counter-clockwise
        // seen from the plane's positive normal in each.
        switch (RotationPlane)
        {
            case 18:
                var (dz, dx) = (p.Z - c.Z, p.X - c.X);
                return new Point3(c.X + (dz * sin) + (dx * _cos), p.Y, c.Z + (dz * _cos) - (dx * sin));
            case 19:
                var (dy, dz2) = (p.Y - c.Y, p.Z - c.Z);
                return new Point3(p.X, c.Y + (dy * _cos) - (dz2 * sin), c.Z + (dy * sin) + (dz2 * _cos));
            default:
                var (dx2, dy2) = (p.X - c.X, p.Y - c.Y);
                return new Point3(c.X + (dx2 * _cos) - (dy2 * sin), c.Y + (dx2 * sin) + (dy2 * _cos), p.Z);
        }
    }
}
