namespace PmacStream.Sim;

/// <summary>What moves a motor on its own (not its coordinate system's program).</summary>
internal enum MotorMove
{
    /// <summary>Nothing of its own: it holds its position or follows its coordinate system.</summary>
    None,

    /// <summary>An indefinite jog (<c>J+</c>, <c>J-</c>) or the deceleration of a stopped jog.</summary>
    Jog,

    /// <summary>A definite jog (<c>J=</c>, <c>J=pos</c>, <c>J:</c>, <c>J^</c>) or the post-trigger part of a homing move.</summary>
    JogTo,

    /// <summary>A homing search: moving at Ixx23 until the home switch triggers.</summary>
    HomeSearch,
}

/// <summary>
/// One simulated motor: its commanded position (counts, referenced to the power-on or homed zero), the velocity of the
/// move it makes on its own (jog, homing) and its servo state (closed loop, killed) and latched faults. The servo
/// loop is modelled as a pure lag: the actual position trails the commanded one by velocity x
/// <see cref="SimOptions.ServoLagMs"/>. Guarded by the simulator's lock.
/// </summary>
internal sealed class Motor(int number)
{
    private const double Epsilon = 1e-9;

    /// <summary>The motor number, 1..32.</summary>
    public int Number { get; } = number;

    /// <summary>Commanded position in counts, from the motor's zero (power-on, or the home position once homed).</summary>
    public double Commanded { get; set; }

    /// <summary>Commanded velocity in counts per second.</summary>
    public double Velocity { get; set; }

    /// <summary>Where the motor's zero is in machine counts (from the power-on position): moved by homing.</summary>
    public double ZeroAt { get; set; }

    /// <summary>The machine position in counts from where it stood at power-on (what switches are placed against).</summary>
    public double Machine => Commanded + ZeroAt;

    /// <summary>Amplifier enabled and loop closed; false after <c>K</c> or a fault kill.</summary>
    public bool Enabled { get; set; } = true;

    /// <summary>Home Complete: the last homing search found its trigger (or <c>HMZ</c>).</summary>
    public bool HomeComplete { get; set; }

    /// <summary>Stopped on Position Limit: latched when a limit stopped the motor, cleared when it moves again.</summary>
    public bool StoppedOnLimit { get; set; }

    /// <summary>Killed by an amplifier fault (latched until re-enabled).</summary>
    public bool AmpFault { get; set; }

    /// <summary>Killed by a fatal following error (latched until re-enabled).</summary>
    public bool FatalFollowingError { get; set; }

    /// <summary>Following error injected with a fatal fault: what <c>F</c> reports until re-enabled (counts).</summary>
    public double InjectedFollowingError { get; set; }

    /// <summary>An injected positive end limit switch (machine counts), until the motor moves off it.</summary>
    public double? InjectedPlusLimit { get; set; }

    /// <summary>An injected negative end limit switch (machine counts), until the motor moves off it.</summary>
    public double? InjectedMinusLimit { get; set; }

    /// <summary>Moved by a jog, a homing move or a kill since its coordinate system last matched to it (PMATCH).</summary>
    public bool Detached { get; set; }

    /// <summary>The position <c>J=</c> returns to: where the motor was before the first jog since program motion.</summary>
    public double PreJog { get; set; }

    /// <summary>What moves the motor on its own.</summary>
    public MotorMove Move { get; private set; }

    /// <summary>The definite move's end (<see cref="MotorMove.JogTo"/>).</summary>
    public double Target { get; private set; }

    /// <summary>Direction of an indefinite jog or homing search (+1/-1); 0 while a stopped jog decelerates.</summary>
    public int Direction { get; private set; }

    /// <summary>Speed of the move in counts per second.</summary>
    public double Speed { get; private set; }

    /// <summary>Acceleration of the move in counts per second squared.</summary>
    public double Acceleration { get; private set; }

    /// <summary>True while the motor makes a move of its own.</summary>
    public bool Moving => Move != MotorMove.None;

    // The planned profile of a definite move (from the velocity it has towards the target): accelerate, cruise at the
    // peak, decelerate; time since its start. Not planned (numeric approach) when it starts moving away or too fast.
    private bool _planned;
    private double _tau;
    private double _start;
    private double _u;
    private double _peak;
    private double _tAccel;
    private double _tCruise;
    private double _tDecel;

    /// <summary>A move to <paramref name="target"/>.</summary>
    public void StartJogTo(double target, double speed, double acceleration)
    {
        Move = MotorMove.JogTo;
        Target = target;
        Speed = speed;
        Acceleration = acceleration;
        Direction = Math.Sign(target - Commanded);
        Plan();
    }

    private void Plan()
    {
        var d = Math.Abs(Target - Commanded);
        var u = Velocity * Direction;
        var a = Acceleration;
        _planned = Direction != 0 && u >= 0 && u <= Speed && (u * u / (2 * a)) <= d;
        if (!_planned)
        {
            return;
        }

        _tau = 0;
        _start = Commanded;
        _u = u;
        var accelDistance = ((Speed * Speed) - (u * u)) / (2 * a);
        var decelDistance = Speed * Speed / (2 * a);
        if (d >= accelDistance + decelDistance)
        {
            _peak = Speed;
            _tCruise = (d - accelDistance - decelDistance) / Speed;
        }
        else
        {
            _peak = Math.Sqrt(((2 * a * d) + (u * u)) / 2);
            _tCruise = 0;
        }

        _tAccel = (_peak - u) / a;
        _tDecel = _peak / a;
    }

    /// <summary>Distance along and velocity of the planned profile at <paramref name="tau"/> seconds.</summary>
    private (double Distance, double Velocity) Profile(double tau)
    {
        var a = Acceleration;
        if (tau < _tAccel)
        {
            return ((_u * tau) + (a * tau * tau / 2), _u + (a * tau));
        }

        var accelDistance = ((_peak * _peak) - (_u * _u)) / (2 * a);
        if (tau < _tAccel + _tCruise)
        {
            return (accelDistance + (_peak * (tau - _tAccel)), _peak);
        }

        var t = Math.Min(tau - _tAccel - _tCruise, _tDecel);
        return (accelDistance + (_peak * _tCruise) + (_peak * t) - (a * t * t / 2), _peak - (a * t));
    }

    /// <summary>An indefinite jog in <paramref name="direction"/> (0 = decelerate to a stop).</summary>
    public void StartJog(int direction, double speed, double acceleration)
    {
        Move = MotorMove.Jog;
        Direction = direction;
        Speed = speed;
        Acceleration = acceleration;
    }

    /// <summary>A homing search in <paramref name="direction"/>.</summary>
    public void StartHomeSearch(int direction, double speed, double acceleration)
    {
        Move = MotorMove.HomeSearch;
        Direction = direction;
        Speed = speed;
        Acceleration = acceleration;
    }

    /// <summary><c>J/</c> while jogging: decelerate to a stop at the move's acceleration.</summary>
    public void StopJog()
    {
        if (Moving)
        {
            Move = MotorMove.Jog;
            Direction = 0;
        }
    }

    /// <summary>Stops at once where it is (a kill, a limit, an abort).</summary>
    public void Halt()
    {
        _planned = false;
        Move = MotorMove.None;
        Velocity = 0;
        Direction = 0;
    }

    /// <summary>
    /// Advances the motor's own move by <paramref name="dt"/> seconds (at most one servo-sized step; the caller splits
    /// longer spans): the velocity slews at <see cref="Acceleration"/> towards the jog speed, and for a definite move
    /// towards the speed from which it can still stop at the target, so it ends exactly there.
    /// </summary>
    public void Step(double dt)
    {
        if (!Moving || dt <= 0)
        {
            return;
        }

        if (Move == MotorMove.JogTo && _planned)
        {
            _tau += dt;
            if (_tau >= _tAccel + _tCruise + _tDecel)
            {
                Commanded = Target;
                Halt();
                return;
            }

            var (distance, velocity) = Profile(_tau);
            Commanded = _start + (Direction * distance);
            Velocity = Direction * velocity;
            return;
        }

        double desired;
        var remaining = 0.0;
        if (Move == MotorMove.JogTo)
        {
            remaining = Target - Commanded;
            if (Math.Abs(remaining) < Epsilon && Math.Abs(Velocity) < Acceleration * dt + Epsilon)
            {
                Commanded = Target;
                Halt();
                return;
            }

            desired = Math.Sign(remaining) * Math.Min(Speed, Math.Sqrt(2 * Acceleration * Math.Abs(remaining)));
        }
        else
        {
            desired = Direction * Speed;
        }

        var dv = Acceleration * dt;
        var v0 = Velocity;
        var v1 = desired > v0 ? Math.Min(desired, v0 + dv) : Math.Max(desired, v0 - dv);
        Commanded += (v0 + v1) / 2 * dt;
        Velocity = v1;
        if (Move == MotorMove.JogTo)
        {
            var after = Target - Commanded;
            if (Math.Sign(after) != Math.Sign(remaining) || Math.Abs(after) < Epsilon)
            {
                Commanded = Target; // arrived (the last step would pass it)
                Halt();
            }
        }
        else if (Move == MotorMove.Jog && Direction == 0 && Math.Abs(v1) < Epsilon)
        {
            Halt();
        }
    }
}
