namespace PmacStream.Sim;

/// <summary>
/// The motor definitions (<c>#n-&gt;X</c>): the coordinate-system axis each motor follows, with its scale. Motor
/// positions and status are <see cref="MotorSet"/>'s. Guarded by the simulator's lock.
/// </summary>
internal sealed class MotorMap
{
    /// <summary>Motors #1..#32.</summary>
    public const int Count = 32;

    private const string Axes = "XYZABCUVW";

    private readonly (int Cs, int Axis, double Scale)[] _motors = new (int, int, double)[Count + 1];

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

    /// <summary>The motor's definition: its coordinate system, axis index (-1 for none) and scale (counts per axis unit).</summary>
    public (int Cs, int Axis, double Scale) Definition(int motor) => _motors[motor];
}
