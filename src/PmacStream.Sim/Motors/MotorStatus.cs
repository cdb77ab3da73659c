using System.Globalization;

namespace PmacStream.Sim;

/// <summary>
/// The status words as a Turbo PMAC reports them (Turbo PMAC/PMAC2 Software Reference, On-line Command Specification,
/// <c>?</c> pp. 281-284, <c>??</c> pp. 284-287; the tables are in docs/turbo-pmac-motors.md). Only the bits the
/// simulator has a state for are set; the others read 0.
/// </summary>
internal static class MotorStatus
{
    // Motor status, first word.
    public const int Activated = 1 << 23;
    public const int NegativeEndLimit = 1 << 22;
    public const int PositiveEndLimit = 1 << 21;
    public const int AmplifierEnabled = 1 << 19;
    public const int OpenLoop = 1 << 18;
    public const int MoveTimerActive = 1 << 17;
    public const int DesiredVelocityZero = 1 << 13;
    public const int HomeSearchInProgress = 1 << 10;

    // Motor status, second word.
    public const int AssignedToCs = 1 << 15;
    public const int AmplifierEnabledWord2 = 1 << 14;
    public const int StoppedOnPositionLimit = 1 << 11;
    public const int HomeComplete = 1 << 10;
    public const int AmplifierFault = 1 << 3;
    public const int FatalFollowingError = 1 << 2;
    public const int WarningFollowingError = 1 << 1;
    public const int InPosition = 1 << 0;

    // Coordinate-system status, second word.
    public const int CsAmplifierFault = 1 << 20;
    public const int CsFatalFollowingError = 1 << 19;
    public const int CsWarningFollowingError = 1 << 18;

    /// <summary>
    /// The coordinate definition code of bits 16-19 of the second word: 1 A, 2 B, 3 C, 4 U/V/W, 7 X/Y/Z, 0 none
    /// (the manual's example: "bits 16-19 form 1: assigned to A-axis").
    /// </summary>
    public static int AxisCode(int axis) => axis switch
    {
        < 0 => 0,
        <= 2 => 7,
        3 => 1,
        4 => 2,
        5 => 3,
        _ => 4,
    };

    /// <summary>The 12 hex digits of <c>#n?</c>.</summary>
    public static string Motor(MotorSet motors, MotorMap map, CoordinateSystem[] coordinateSystems, int number)
    {
        var motor = motors.Get(number);
        var (cs, axis, _) = map.Definition(number);
        var followsMoving = axis >= 0 && !motor.Detached && motor.Enabled && coordinateSystems[cs].IsMoving;
        var w1 = FirstWord(motors, motor, number, followsMoving);
        var w2 = SecondWord(motors, motor, number, cs, axis);
        return string.Create(CultureInfo.InvariantCulture, $"{w1:X6}{w2:X6}");
    }

    /// <summary>The first word of <c>#n?</c>: activation, limits, amplifier or open loop, move timer, home search.</summary>
    private static int FirstWord(MotorSet motors, Motor motor, int number, bool followsMoving)
    {
        var w1 = 0;
        if (motors.Activated(number))
        {
            w1 |= Activated;
        }

        if (motors.MinusLimitInput(number))
        {
            w1 |= NegativeEndLimit;
        }

        if (motors.PlusLimitInput(number))
        {
            w1 |= PositiveEndLimit;
        }

        if (motor.Enabled)
        {
            w1 |= AmplifierEnabled;
            if (!motor.Moving && !followsMoving)
            {
                w1 |= DesiredVelocityZero;
            }
        }
        else
        {
            w1 |= OpenLoop;
        }

        if (followsMoving || motor.Move == MotorMove.JogTo)
        {
            w1 |= MoveTimerActive;
        }

        if (motor.Move == MotorMove.HomeSearch)
        {
            w1 |= HomeSearchInProgress;
        }
        return w1;
    }

    /// <summary>The second word of <c>#n?</c>: the coordinate system and axis, amplifier, limit stop, home, faults, in position.</summary>
    private static int SecondWord(MotorSet motors, Motor motor, int number, int cs, int axis)
    {
        var w2 = axis >= 0 ? ((cs - 1) << 20) | (AxisCode(axis) << 16) | AssignedToCs : 0;
        if (motor.Enabled)
        {
            w2 |= AmplifierEnabledWord2;
        }

        if (motor.StoppedOnLimit)
        {
            w2 |= StoppedOnPositionLimit;
        }

        if (motor.HomeComplete)
        {
            w2 |= HomeComplete;
        }

        if (motor.AmpFault)
        {
            w2 |= AmplifierFault;
        }

        if (motor.FatalFollowingError)
        {
            w2 |= FatalFollowingError;
        }

        if (motors.WarningFollowingError(number))
        {
            w2 |= WarningFollowingError;
        }

        if (motors.InPosition(number))
        {
            w2 |= InPosition;
        }
        return w2;
    }

    /// <summary>
    /// The bits of the coordinate system's second word that come from its motors: amplifier fault (20), fatal (19) and
    /// warning (18) following error; and whether every motor of it is in position (for bit 17).
    /// </summary>
    public static (int Bits, bool AllInPosition) CoordinateSystem(MotorSet motors, int cs)
    {
        var bits = 0;
        var inPosition = true;
        for (var m = 1; m <= MotorMap.Count; m++)
        {
            if (!motors.InCoordinateSystem(m, cs))
            {
                continue;
            }

            var motor = motors.Get(m);
            if (motor.AmpFault)
            {
                bits |= CsAmplifierFault;
            }

            if (motor.FatalFollowingError)
            {
                bits |= CsFatalFollowingError;
            }

            if (motors.WarningFollowingError(m))
            {
                bits |= CsWarningFollowingError;
            }

            inPosition &= motor.Enabled && !motor.Moving;
        }

        return (bits, inPosition);
    }
}
