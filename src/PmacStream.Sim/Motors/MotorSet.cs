using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// The 32 motors: their jog and homing moves on the virtual clock, following their coordinate system's program,
/// limits, following error and amplifier faults, kills and re-enables, and the faults injected for tests and demos.
/// A motor not moved on its own follows its axis (<c>#n-&gt;</c> definition): its commanded position is the axis
/// position times the scale. A jog, a homing move or a kill detaches it; the coordinate system matches its axes to the
/// motors again (PMATCH) when a program is next started with <c>R</c>/<c>S</c>. Guarded by the simulator's lock.
/// </summary>
internal sealed class MotorSet
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSimulator>();

    private readonly Motor[] _motors = new Motor[MotorMap.Count + 1];
    private readonly CoordinateSystem[] _cs;
    private readonly MotorMap _map;
    private readonly SimMemory _memory;
    private readonly SimOptions _options;
    private readonly Func<double> _now;
    private readonly List<FaultInjection> _pending = [];
    private readonly MotorSettings[] _settings = new MotorSettings[MotorMap.Count + 1];
    private readonly bool _anySwitch;
    private readonly double[] _scratch = new double[CoordinateSystem.AxisCount];
    private readonly double[] _velocityA = new double[CoordinateSystem.AxisCount];
    private readonly double[] _velocityB = new double[CoordinateSystem.AxisCount];
    private bool[] _homeArmed = new bool[MotorMap.Count + 1];

    // Axis positions of each coordinate system for one clock step, taken once for all its motors.
    private readonly double[][] _stepPositions = new double[SimMemory.CoordinateSystems + 1][];
    private readonly bool[] _stepValid = new bool[SimMemory.CoordinateSystems + 1];
    private bool _inStep;

    public MotorSet(CoordinateSystem[] coordinateSystems, MotorMap map, SimMemory memory, SimOptions options, Func<double> now)
    {
        _cs = coordinateSystems;
        _map = map;
        _memory = memory;
        _options = options;
        _now = now;
        _pending.AddRange(options.Faults);
        for (var m = 1; m < _settings.Length; m++)
        {
            // Read once: the machine's switches do not move while it runs.
            _settings[m] = options.MotorSettings.TryGetValue(m, out var s) ? s : new MotorSettings();
            _anySwitch |= _settings[m].PlusLimitPosition is not null || _settings[m].MinusLimitPosition is not null;
        }
    }

    /// <summary>Virtual time when a motion program first started running (the fault-injection clock's zero); null before.</summary>
    public double? ProgramEpoch { get; private set; }

    /// <summary>True while any motor makes a move of its own (jog, homing).</summary>
    public bool AnyMoving
    {
        get
        {
            for (var m = 1; m < _motors.Length; m++)
            {
                if (_motors[m].Moving)
                {
                    return true;
                }
            }

            return false;
        }
    }

    /// <summary>Power-on/reset: motors at rest, enabled, at their zero; homed only if <see cref="SimOptions.StartHomed"/>.</summary>
    public void PowerOn()
    {
        for (var m = 1; m < _motors.Length; m++)
        {
            var old = _motors[m];
            var motor = _motors[m] = new Motor(m) { HomeComplete = _options.StartHomed };

            // The machine does not move at a reset: a motor keeps its place, only its zero is back at the encoder's.
            if (old is not null)
            {
                motor.ZeroAt = 0;
                motor.Commanded = old.Machine;
                motor.Detached = true; // the axes are matched to it again at the next R (PMATCH)
            }

            // Turbo PMAC defaults (Software Reference, I-variables): the simulator's motors start with them.
            SetIDefault(m, 0, 1);      // Ixx00 motor activated
            SetIDefault(m, 8, 96);     // position scale factor: the move registers are in 1/(Ixx08*32) counts
            SetIDefault(m, 11, 32000); // fatal following error limit, 1/16 count
            SetIDefault(m, 12, 16000); // warning following error limit, 1/16 count
            SetIDefault(m, 19, 0.15625); // maximum jog/home acceleration, counts/msec^2
            SetIDefault(m, 21, 50);    // jog/home S-curve time, msec
            SetIDefault(m, 22, 32);    // jog speed, counts/msec
            SetIDefault(m, 23, 32);    // home speed and direction, counts/msec
            SetIDefault(m, 28, 160);   // in-position band, 1/16 count
        }

        _homeArmed = new bool[MotorMap.Count + 1];
        if (_options.SuggestedMVariables)
        {
            for (var m = 1; m < _motors.Length; m++)
            {
                foreach (var (suffix, offset) in new[] { (61, CommandedRegister), (62, ActualRegister), (63, TargetRegister) })
                {
                    var n = (m * 100) + suffix;
                    if (_memory.GetDefinition(n).IsSelf)
                    {
                        _memory.Define(n, new MDefinition('D', (m * RegisterStride) + offset, 0, 48, true));
                    }
                }
            }
        }
    }

    /// <summary>Motor xx's move registers start at D:$xx*$80 (motor 1's commanded position D:$000088).</summary>
    public const int RegisterStride = 0x80;

    /// <summary>Commanded position register (Mxx61, D:$000088 for motor 1).</summary>
    public const int CommandedRegister = 0x08;

    /// <summary>Actual position register (Mxx62, D:$00008B).</summary>
    public const int ActualRegister = 0x0B;

    /// <summary>Target (end) position register (Mxx63, D:$0000C7): where the move being executed ends.</summary>
    public const int TargetRegister = 0x47;

    /// <summary>
    /// A motor move register at a D: address, in 1/(Ixx08*32) counts, or null when the address is none of them.
    /// </summary>
    public double? Register(char space, int address)
    {
        if (space != 'D' || address < RegisterStride || address >= RegisterStride * _motors.Length)
        {
            return null;
        }

        var number = address / RegisterStride;
        var units = Math.Max(1, I(number, 8)) * 32;
        return (address % RegisterStride) switch
        {
            CommandedRegister => Get(number).Commanded * units,
            ActualRegister => ActualPosition(number) * units,
            TargetRegister => TargetPosition(number) * units,
            _ => null,
        };
    }

    /// <summary>
    /// Where the motor's present move ends, counts: a definite jog's end, the end of its coordinate system's executing
    /// move for a motor that follows its axis, else (at rest, an indefinite jog, homing) its commanded position.
    /// </summary>
    public double TargetPosition(int number)
    {
        var motor = Get(number);
        if (motor.Move == MotorMove.JogTo)
        {
            return motor.Target;
        }

        var (cs, axis, scale) = _map.Definition(number);
        if (!motor.Moving && axis >= 0 && !motor.Detached && motor.Enabled && _cs[cs].Current is { } seg)
        {
            return seg.End[axis] * scale;
        }

        return motor.Commanded;
    }

    /// <summary>Adds a fault to inject at its time on the program clock (at once if that time has passed).</summary>
    public void Schedule(FaultInjection fault) => _pending.Add(fault);

    /// <summary>The motor (refreshed from its coordinate system if it follows one).</summary>
    public Motor Get(int number)
    {
        var motor = _motors[number];
        Follow(motor);
        return motor;
    }

    /// <summary>Actual position in counts (<c>P</c>): commanded minus following error.</summary>
    public double ActualPosition(int number)
    {
        var motor = Get(number);
        return motor.Commanded - FollowingError(motor);
    }

    /// <summary>Actual velocity in counts per servo cycle (<c>V</c>), the servo cycle from I10.</summary>
    public double ReportedVelocity(int number)
    {
        var motor = Get(number);
        var cyclesPerMs = 8388608.0 / Math.Max(1, _memory.GetI(10));
        return motor.Enabled ? motor.Velocity / 1000.0 / cyclesPerMs : 0;
    }

    /// <summary>Following error in counts (<c>F</c>).</summary>
    public double FollowingError(int number) => FollowingError(Get(number));

    /// <summary>The motor is assigned to an axis of coordinate system <paramref name="cs"/>.</summary>
    public bool InCoordinateSystem(int number, int cs)
    {
        var (c, axis, _) = _map.Definition(number);
        return axis >= 0 && c == cs;
    }

    /// <summary>In position: loop closed, no move of its own or of its coordinate system, following error within Ixx28.</summary>
    public bool InPosition(int number)
    {
        var motor = Get(number);
        var (cs, axis, _) = _map.Definition(number);
        return motor.Enabled && !motor.Moving && !(axis >= 0 && !motor.Detached && _cs[cs].IsMoving)
            && Math.Abs(FollowingError(motor)) * 16 <= Math.Max(0, I(number, 28));
    }

    /// <summary>Ixx00: the motor is activated (servo calculations on).</summary>
    public bool Activated(int number) => I(number, 0) != 0;

    /// <summary>The warning following error limit (Ixx12) is exceeded, or the motor was killed on a fatal one.</summary>
    public bool WarningFollowingError(int number)
    {
        var motor = Get(number);
        var limit = I(number, 12);
        return motor.FatalFollowingError || (limit > 0 && Math.Abs(FollowingError(motor)) * 16 > limit);
    }

    /// <summary>The positive end limit input is on (an injected or configured switch the motor is at or beyond).</summary>
    public bool PlusLimitInput(int number) => PlusSwitch(Get(number)) is { } at && _motors[number].Machine >= at - 1e-9;

    /// <summary>The negative end limit input is on.</summary>
    public bool MinusLimitInput(int number) => MinusSwitch(Get(number)) is { } at && _motors[number].Machine <= at + 1e-9;

    // ---- commands -------------------------------------------------------------------------------------------

    /// <summary>
    /// A jog command: <c>J+</c> (<paramref name="kind"/> '+'), <c>J-</c>, <c>J/</c>, <c>J=</c> (no value: to the pre-jog
    /// position), <c>J=</c>value (to a position), <c>J:</c>distance (from the commanded position), <c>J^</c>distance
    /// (from the actual position). Returns 0 or an ERR number.
    /// </summary>
    public int Jog(int number, char kind, double? value)
    {
        var motor = Get(number);
        if (kind == '/')
        {
            if (!motor.Enabled)
            {
                Enable(motor); // J/ closes the loop of a killed motor where it is (Software Reference, $*).
            }
            else
            {
                motor.StopJog();
            }

            return 0;
        }

        if (RunningProgram(number))
        {
            return 1;
        }

        if (!motor.Enabled)
        {
            return 0; // *assumed*: a killed motor ignores jogs until J/, A or $ closes its loop
        }

        if (!motor.Detached)
        {
            motor.PreJog = motor.Commanded;
        }

        var speed = Math.Abs(I(number, 22)) * 1000;
        var accel = JogAcceleration(number, speed);
        motor.Detached = true;
        switch (kind)
        {
            case '+' or '-':
                {
                    var dir = kind == '+' ? 1 : -1;
                    if (!IntoLimit(motor, dir))
                    {
                        motor.StoppedOnLimit = false;
                        motor.StartJog(dir, speed, accel);
                    }

                    return 0;
                }

            default:
                {
                    var target = kind switch
                    {
                        '=' => value ?? motor.PreJog,
                        ':' => motor.Commanded + (value ?? 0),
                        _ => motor.Commanded - FollowingError(motor) + (value ?? 0),
                    };
                    var dir = Math.Sign(target - motor.Commanded);
                    if (dir != 0 && !IntoLimit(motor, dir))
                    {
                        motor.StoppedOnLimit = false;
                        motor.StartJogTo(target, speed, accel);
                    }

                    return 0;
                }
        }
    }

    /// <summary><c>HM</c>: a homing search at Ixx23 (its sign the direction) until the home switch, then to Ixx26 from it.</summary>
    public int Home(int number)
    {
        var motor = Get(number);
        if (RunningProgram(number))
        {
            return 1;
        }

        if (!motor.Enabled)
        {
            return 0; // *assumed*, as for jogs
        }

        var ixx23 = I(number, 23);
        var dir = ixx23 < 0 ? -1 : 1;
        var speed = Math.Abs(ixx23) * 1000;
        motor.HomeComplete = false;
        motor.Detached = true;
        motor.StoppedOnLimit = false;
        var sw = Settings(number).HomeSwitchPosition;
        _homeArmed[number] = (motor.Machine - sw) * dir <= 1e-9;
        motor.StartHomeSearch(dir, speed, JogAcceleration(number, speed));
        CheckHomeTrigger(motor);
        return 0;
    }

    /// <summary><c>HMZ</c>: declares the present commanded position the home (zero) position; no move.</summary>
    public int HomeHere(int number)
    {
        var motor = Get(number);
        if (RunningProgram(number))
        {
            return 1;
        }

        motor.Halt();
        motor.ZeroAt = motor.Machine;
        motor.Commanded = 0;
        motor.HomeComplete = true;
        motor.Detached = true;
        return 0;
    }

    /// <summary><c>K</c>: kills the motor (refused while its coordinate system runs a program).</summary>
    public int Kill(int number)
    {
        if (RunningProgram(number))
        {
            return 1;
        }

        Kill(Get(number));
        return 0;
    }

    /// <summary><c>$</c>: re-enables the motor (closes its loop where it is), clearing a fault kill.</summary>
    public void Reset(int number) => Enable(Get(number));

    /// <summary><c>&amp;n A</c>: stops the coordinate system's motors' own moves and closes the loop of those killed.</summary>
    public void Abort(int cs)
    {
        for (var m = 1; m < _motors.Length; m++)
        {
            if (InCoordinateSystem(m, cs))
            {
                var motor = Get(m);
                if (!motor.Enabled)
                {
                    Enable(motor);
                }
                else if (motor.Moving)
                {
                    motor.Halt();
                }
            }
        }
    }

    /// <summary>
    /// Before <c>R</c>/<c>S</c> on <paramref name="cs"/>: a killed motor refuses it (ERR012, open loop); resuming a
    /// held program needs every motor back where it stopped (ERR017); a new start matches the axes to motors moved on
    /// their own (PMATCH). Returns 0 or the ERR number.
    /// </summary>
    public int BeforeRun(CoordinateSystem cs)
    {
        var resuming = cs.Holding;
        if (cs.Running && !resuming)
        {
            return 0;
        }

        cs.ActualPosition(_scratch);
        var matched = new bool[CoordinateSystem.AxisCount];
        for (var m = 1; m < _motors.Length; m++)
        {
            var (c, axis, scale) = _map.Definition(m);
            if (axis < 0 || c != cs.Number)
            {
                continue;
            }

            var motor = _motors[m];
            if (!motor.Enabled)
            {
                return 12;
            }

            if (motor.Moving)
            {
                return 11; // previous move not completed
            }

            if (!motor.Detached)
            {
                continue;
            }

            if (resuming)
            {
                if (Math.Abs(motor.Commanded - (_scratch[axis] * scale)) > _options.ResumePositionToleranceCounts)
                {
                    return 17;
                }
            }
            else if (!matched[axis] && scale != 0)
            {
                // PMATCH: the lowest-numbered motor of an axis gives its position.
                matched[axis] = true;
                cs.MatchAxis(axis, motor.Commanded / scale);
                _scratch[axis] = motor.Commanded / scale;
            }
        }

        for (var m = 1; m < _motors.Length; m++)
        {
            if (InCoordinateSystem(m, cs.Number))
            {
                _motors[m].Detached = false;
                _motors[m].StoppedOnLimit = false;
            }
        }

        return 0;
    }

    /// <summary><c>PMATCH</c>: the axes of <paramref name="cs"/> start their next move from where their motors are.</summary>
    public void Match(CoordinateSystem cs)
    {
        if (cs.IsMoving)
        {
            return;
        }

        var matched = new bool[CoordinateSystem.AxisCount];
        for (var m = 1; m < _motors.Length; m++)
        {
            var (c, axis, scale) = _map.Definition(m);
            if (axis >= 0 && c == cs.Number && !matched[axis] && scale != 0)
            {
                var motor = Get(m);
                matched[axis] = true;
                cs.MatchAxis(axis, motor.Commanded / scale);
            }
        }

        for (var m = 1; m < _motors.Length; m++)
        {
            if (InCoordinateSystem(m, cs.Number) && !_motors[m].Moving && _motors[m].Enabled)
            {
                _motors[m].Detached = false;
            }
        }
    }

    /// <summary>A motion program started running: the fault-injection clock starts at the first one.</summary>
    public void ProgramStarted() => ProgramEpoch ??= _now();

    /// <summary>Injects <paramref name="kind"/> into <paramref name="number"/> now.</summary>
    public void Fire(FaultKind kind, int number)
    {
        var motor = Get(number);
        Log.Information("fault injected: {Kind} on motor {Motor} at {Time:0.000} s", FaultInjection.Name(kind), number, _now());
        switch (kind)
        {
            case FaultKind.PlusLimit:
                motor.InjectedPlusLimit = motor.Machine;
                TripLimit(motor);
                motor.InjectedPlusLimit = motor.Machine; // where the abort left it: a move found at its end stands there
                break;
            case FaultKind.MinusLimit:
                motor.InjectedMinusLimit = motor.Machine;
                TripLimit(motor);
                motor.InjectedMinusLimit = motor.Machine;
                break;
            case FaultKind.FatalFollowingError:
                motor.FatalFollowingError = true;
                motor.InjectedFollowingError = (Math.Max(0, I(number, 11)) / 16.0) + 1;
                FaultKill(motor);
                break;
            default:
                motor.AmpFault = true;
                FaultKill(motor);
                break;
        }
    }

    // ---- clock ------------------------------------------------------------------------------------------------

    /// <summary>The next time motors need a step: now plus a servo-sized step while any moves on its own or a program moves one near a limit.</summary>
    public double NextMotionTime(double now)
    {
        if (Quiet())
        {
            return double.PositiveInfinity;
        }

        var step = Math.Max(1e-5, _options.MotorStepMs / 1000.0);
        for (var m = 1; m < _motors.Length; m++)
        {
            var motor = _motors[m];
            if (motor.Moving)
            {
                return now + step;
            }

            var (cs, axis, _) = _map.Definition(m);
            if (axis >= 0 && !motor.Detached && _cs[cs].IsMoving && HasLimit(motor))
            {
                return now + step;
            }
        }

        return double.PositiveInfinity;
    }

    /// <summary>The time of the next injected fault, infinity when none is due (or no program has started yet).</summary>
    public double NextFaultTime()
    {
        if (ProgramEpoch is not { } epoch || _pending.Count == 0)
        {
            return double.PositiveInfinity;
        }

        var next = double.PositiveInfinity;
        foreach (var f in _pending)
        {
            next = Math.Min(next, epoch + f.Seconds);
        }

        return next;
    }

    /// <summary>Fires the injected faults due at <paramref name="now"/>.</summary>
    public void FireDue(double now)
    {
        if (ProgramEpoch is not { } epoch || _pending.Count == 0)
        {
            return;
        }

        for (var i = 0; i < _pending.Count; i++)
        {
            var f = _pending[i];
            if (epoch + f.Seconds <= now + 1e-12)
            {
                _pending.RemoveAt(i--);
                Fire(f.Kind, f.Motor);
            }
        }
    }

    /// <summary>Advances the motors over [t0, t1]: own moves in servo-sized steps, following motors to their axes, limit and following-error checks.</summary>
    public void Advance(double t0, double t1)
    {
        var dt = t1 - t0;
        if (dt <= 0)
        {
            return;
        }

        if (Quiet())
        {
            return; // nothing moves on its own and nothing can trip: motors are read from their axes when asked
        }

        var step = Math.Max(1e-5, _options.MotorStepMs / 1000.0);
        Array.Clear(_stepValid);
        _inStep = true;
        try
        {
            AdvanceMotors(t0, t1, dt, step);
        }
        finally
        {
            _inStep = false;
        }
    }

    private void AdvanceMotors(double t0, double t1, double dt, double step)
    {
        var lag = _options.ServoLagMs > 0;
        for (var m = 1; m < _motors.Length; m++)
        {
            var motor = _motors[m];
            if (!motor.Moving && (motor.Detached || _map.Definition(m).Axis < 0))
            {
                continue; // holds its position: nothing changes over the step
            }

            if (motor.Moving)
            {
                for (var t = t0; t < t1 - 1e-12 && motor.Moving;)
                {
                    var h = Math.Min(step, t1 - t);
                    motor.Step(h);
                    t += h;
                    CheckOwnMove(motor);
                }

                ReleaseInjectedLimits(motor);
            }
            else if (motor.Enabled && (lag || HasLimit(motor)))
            {
                // A following motor is read from its axis when asked (Get); it needs a step only to be checked.
                Follow(motor);
                CheckFollowing(motor);
                ReleaseInjectedLimits(motor);
            }
        }
    }

    /// <summary>
    /// No motor moves on its own and none following a program can trip (no lag, no switch, no software limit): the
    /// clock need not step them. The common case while a job streams, so it is checked first and cheaply.
    /// </summary>
    private bool Quiet()
    {
        if (_options.ServoLagMs > 0 || _anySwitch)
        {
            return false;
        }

        for (var m = 1; m < _motors.Length; m++)
        {
            var motor = _motors[m];
            if (motor.Moving || motor.InjectedPlusLimit is not null || motor.InjectedMinusLimit is not null
                || _memory.GetI((m * 100) + 13) != 0 || _memory.GetI((m * 100) + 14) != 0)
            {
                return false;
            }
        }

        return true;
    }

    // ---- internals ----------------------------------------------------------------------------------------------

    private MotorSettings Settings(int number) => _settings[number];

    private double I(int motor, int item) => _memory.GetI((motor * 100) + item);

    private void SetIDefault(int motor, int item, double value) => _memory.SetI((motor * 100) + item, value);

    /// <summary>
    /// Jog/home acceleration in counts/s^2: the speed change over the acceleration time, which is Ixx20, or 2 x Ixx21 when
    /// the S-curve time is more than half of it, capped at Ixx19. The S-curve shape itself is not simulated (constant
    /// acceleration over the same time).
    /// </summary>
    private double JogAcceleration(int number, double speedCountsPerSecond)
    {
        var ms = Math.Max(I(number, 20), 2 * I(number, 21));
        var limit = I(number, 19) > 0 ? I(number, 19) * 1e6 : double.PositiveInfinity;
        var accel = ms > 0 ? speedCountsPerSecond / (ms / 1000.0) : limit;
        accel = Math.Min(accel, limit);
        return double.IsPositiveInfinity(accel) || accel <= 0 ? 1e12 : accel;
    }

    private bool RunningProgram(int number)
    {
        var (cs, axis, _) = _map.Definition(number);
        if (axis < 0)
        {
            return false;
        }

        var c = _cs[cs];

        // A held program whose feed has slewed to 0 lets its motors be jogged (to be brought back before R).
        return c.Running && !(c.Holding && c.OverrideCurrent <= 1e-6);
    }

    private double FollowingError(Motor motor)
    {
        if (!motor.Enabled)
        {
            return motor.InjectedFollowingError;
        }

        return motor.Velocity * _options.ServoLagMs / 1000.0;
    }

    /// <summary>A motor that follows its axis takes the axis position and velocity (times its scale).</summary>
    private void Follow(Motor motor)
    {
        var (cs, axis, scale) = _map.Definition(motor.Number);
        if (axis < 0 || motor.Detached || motor.Moving || !motor.Enabled)
        {
            return;
        }

        var c = _cs[cs];
        double[] positions;
        if (_inStep)
        {
            positions = _stepPositions[cs] ??= new double[CoordinateSystem.AxisCount];
            if (!_stepValid[cs])
            {
                c.ActualPosition(positions);
                _stepValid[cs] = true;
            }
        }
        else
        {
            positions = _scratch;
            c.ActualPosition(positions);
        }

        var position = positions[axis] * scale;
        motor.Velocity = c.IsMoving ? AxisVelocity(c, axis) * scale : 0;
        motor.Commanded = position;
    }

    /// <summary>
    /// The axis's velocity now (units/s): the executing segment's slope at its present fraction (a central difference of
    /// its position, whatever its profile) at the present feed override.
    /// </summary>
    private double AxisVelocity(CoordinateSystem c, int axis)
    {
        if (c.Current is not { Duration: > 0 } seg)
        {
            return 0;
        }

        var f = 1 - Math.Clamp(seg.Remaining / seg.Duration, 0, 1);
        var f0 = Math.Max(0, f - 1e-4);
        var f1 = Math.Min(1, f + 1e-4);
        seg.PositionAt(f0, _velocityA);
        seg.PositionAt(f1, _velocityB);
        return (_velocityB[axis] - _velocityA[axis]) / (f1 - f0) / seg.Duration * (c.OverrideCurrent / 100.0);
    }

    private double? PlusSwitch(Motor motor) => Min(Settings(motor.Number).PlusLimitPosition, motor.InjectedPlusLimit);

    private double? MinusSwitch(Motor motor) => Max(Settings(motor.Number).MinusLimitPosition, motor.InjectedMinusLimit);

    private static double? Min(double? a, double? b) => a is null ? b : b is null ? a : Math.Min(a.Value, b.Value);

    private static double? Max(double? a, double? b) => a is null ? b : b is null ? a : Math.Max(a.Value, b.Value);

    private bool HasLimit(Motor motor) =>
        PlusSwitch(motor) is not null || MinusSwitch(motor) is not null || I(motor.Number, 13) != 0 || I(motor.Number, 14) != 0;

    /// <summary>Moving in <paramref name="dir"/> would go further into an active limit (hardware input on, or beyond a software limit).</summary>
    private bool IntoLimit(Motor motor, int dir)
    {
        if (dir > 0)
        {
            var soft = I(motor.Number, 13);
            return (PlusSwitch(motor) is { } at && motor.Machine >= at - 1e-9) || (soft != 0 && motor.Commanded >= soft && motor.Move != MotorMove.HomeSearch);
        }

        if (dir < 0)
        {
            var soft = I(motor.Number, 14);
            return (MinusSwitch(motor) is { } at && motor.Machine <= at + 1e-9) || (soft != 0 && motor.Commanded <= soft && motor.Move != MotorMove.HomeSearch);
        }

        return false;
    }

    /// <summary>After a step of the motor's own move: the home trigger, then limits (a software limit stops it exactly there).</summary>
    private void CheckOwnMove(Motor motor)
    {
        if (motor.Move == MotorMove.HomeSearch)
        {
            CheckHomeTrigger(motor);
        }

        if (CheckFatalFollowingError(motor))
        {
            return;
        }

        var dir = Math.Sign(motor.Velocity);
        if (dir == 0 || !IntoLimit(motor, dir))
        {
            return;
        }

        var soft = I(motor.Number, dir > 0 ? 13 : 14);
        if (soft != 0 && motor.Move != MotorMove.HomeSearch && (dir > 0 ? motor.Commanded > soft : motor.Commanded < soft))
        {
            motor.Commanded = soft;
        }

        motor.Halt();
        motor.StoppedOnLimit = true;
        Log.Information("motor {Motor} stopped on a position limit at {Position:0.###} counts", motor.Number, motor.Commanded);
    }

    private void CheckHomeTrigger(Motor motor)
    {
        if (motor.Move != MotorMove.HomeSearch || !_homeArmed[motor.Number])
        {
            return;
        }

        var sw = Settings(motor.Number).HomeSwitchPosition;
        if ((motor.Machine - sw) * motor.Direction < -1e-9)
        {
            return;
        }

        // The trigger position is captured exactly (hardware capture); the zero is Ixx26/16 counts from it, and the
        // post-trigger move takes the motor there (Software Reference, Ixx26).
        var machine = motor.Machine;
        motor.ZeroAt = sw + (I(motor.Number, 26) / 16.0);
        motor.Commanded = machine - motor.ZeroAt;
        motor.HomeComplete = true;
        motor.StartJogTo(0, motor.Speed, motor.Acceleration);
        Log.Information("motor {Motor} home trigger found; zero at {Zero:0.###} machine counts", motor.Number, motor.ZeroAt);
    }

    /// <summary>A motor that follows its program: a limit or a fatal following error stops the coordinate system.</summary>
    private void CheckFollowing(Motor motor)
    {
        var (cs, axis, _) = _map.Definition(motor.Number);
        if (axis < 0 || motor.Detached)
        {
            return;
        }

        var dir = Math.Sign(motor.Velocity);
        if (dir != 0 && IntoLimit(motor, dir))
        {
            TripLimit(motor);
            return;
        }

        CheckFatalFollowingError(motor);
        _ = cs;
    }

    /// <summary>Following error beyond Ixx11 (when not 0) kills the motor as a fault; true when it did.</summary>
    private bool CheckFatalFollowingError(Motor motor)
    {
        var fatal = I(motor.Number, 11);
        if (!motor.Enabled || fatal <= 0 || Math.Abs(FollowingError(motor)) * 16 <= fatal)
        {
            return false;
        }

        motor.InjectedFollowingError = FollowingError(motor);
        motor.FatalFollowingError = true;
        FaultKill(motor);
        return true;
    }

    /// <summary>A limit reached: the motor stops; a program running in its coordinate system is aborted (all its motors stop).</summary>
    private void TripLimit(Motor motor)
    {
        motor.StoppedOnLimit = true;
        if (motor.Moving)
        {
            motor.Halt();
        }

        var (cs, axis, _) = _map.Definition(motor.Number);
        if (axis >= 0 && !motor.Detached && (_cs[cs].Running || _cs[cs].IsMoving))
        {
            // The abort first: a move it finds at its end leaves the axes exactly there, which the motor then follows.
            _cs[cs].Abort();
            _stepValid[cs] = false;
            Follow(motor);
            Log.Warning("C.S.{Cs} aborted: motor {Motor} on a position limit", cs, motor.Number);
        }

        motor.Velocity = 0;
    }

    /// <summary>A fault kill: the motor, and with <see cref="SimOptions.FaultKillsCoordinateSystem"/> every motor of its coordinate system; the program aborts.</summary>
    private void FaultKill(Motor motor)
    {
        var (cs, axis, _) = _map.Definition(motor.Number);
        if (axis >= 0 && (_cs[cs].Running || _cs[cs].IsMoving))
        {
            _cs[cs].Abort();
            _stepValid[cs] = false;
            for (var m = 1; m < _motors.Length; m++)
            {
                Follow(_motors[m]);
            }

            Log.Warning("C.S.{Cs} aborted: motor {Motor} killed by a fault", cs, motor.Number);
        }

        Kill(motor);
        if (axis >= 0 && _options.FaultKillsCoordinateSystem)
        {
            for (var m = 1; m < _motors.Length; m++)
            {
                if (m != motor.Number && InCoordinateSystem(m, cs))
                {
                    Kill(_motors[m]);
                }
            }
        }
    }

    private void Kill(Motor motor)
    {
        Follow(motor);
        motor.Halt();
        motor.Enabled = false;
        motor.Detached = true;
    }

    private void Enable(Motor motor)
    {
        motor.Halt();
        motor.Enabled = true;
        motor.AmpFault = false;
        motor.FatalFollowingError = false;
        motor.InjectedFollowingError = 0;
        motor.Detached = true;
    }

    /// <summary>An injected limit switch is gone once the motor has moved off it.</summary>
    private static void ReleaseInjectedLimits(Motor motor)
    {
        if (motor.InjectedPlusLimit is { } plus && motor.Machine < plus - 1e-6)
        {
            motor.InjectedPlusLimit = null;
        }

        if (motor.InjectedMinusLimit is { } minus && motor.Machine > minus + 1e-6)
        {
            motor.InjectedMinusLimit = null;
        }
    }
}
