using System.Globalization;

namespace PmacStream.Sim;

/// <summary>
/// The motor definitions (<c>#n-&gt;X</c>): the coordinate-system axis each motor follows, with its scale. Motor
/// positions are the commanded path of that axis; the motor status word says whether it moves. Guarded by the
/// simulator's lock.
/// </summary>
internal sealed class MotorMap(CoordinateSystem[] coordinateSystems)
{
    /// <summary>Motors #1..#32.</summary>
    public const int Count = 32;

    private const string Axes = "XYZABCUVW";

    private readonly (int Cs, int Axis, double Scale)[] _motors = new (int, int, double)[Count + 1];
    private readonly double[] _scratch = new double[CoordinateSystem.AxisCount];

    /// <summary>Power-on definitions: motors 1..9 follow X Y Z A B C U V W of C.S. 1 at scale 1, the others nothing.</summary>
    public void PowerOn()
    {
        for (var m = 1; m < _motors.Length; m++)
        {
            _motors[m] = (1, m <= CoordinateSystem.AxisCount ? m - 1 : -1, 1.0);
        }
    }

    /// <summary>The answer to <c>#n-&gt;</c>: <c>1X</c>, <c>0.5Y</c>, or <c>0</c> when undefined.</summary>
    public string Describe(int motor)
    {
        var (_, axis, scale) = _motors[motor];
        return axis < 0 ? "0" : ReplyFrame.Number(scale) + Axes[axis];
    }

    /// <summary>Defines <c>#n-&gt;[scale]axis</c>; false when <paramref name="axisLetter"/> is no axis.</summary>
    public bool Define(int motor, char axisLetter, double scale)
    {
        var index = Axes.IndexOf(axisLetter);
        if (index < 0)
        {
            return false;
        }

        _motors[motor] = (1, index, scale);
        return true;
    }

    /// <summary>The motor's position now (its axis, interpolated within the executing move, times its scale).</summary>
    public double Position(int motor)
    {
        var (cs, axis, scale) = _motors[motor];
        if (axis < 0)
        {
            return 0;
        }

        coordinateSystems[cs].ActualPosition(_scratch);
        return Math.Round(_scratch[axis] * scale, 6);
    }

    /// <summary>The motor status (<c>?</c>, Ctrl-B): two hex words; in position unless its coordinate system moves.</summary>
    public string Status(int motor)
    {
        var (cs, axis, _) = _motors[motor];
        var moving = axis >= 0 && coordinateSystems[cs].IsMoving;
        var w1 = 0x800000 | (moving ? 0 : 0x002000);
        var w2 = ((cs - 1) << 20) | (axis >= 0 ? 0x008000 | ((Math.Min(axis, 8) + 1) << 16) : 0) | 0x004000 | 0x000400 | (moving ? 0 : 1);
        return string.Create(CultureInfo.InvariantCulture, $"{w1:X6}{w2:X6}");
    }
}
