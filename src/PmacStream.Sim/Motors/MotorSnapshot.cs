namespace PmacStream.Sim;

/// <summary>One motor as the simulator sees it at an instant (<see cref="PmacSimulator.Motor"/>); positions in counts.</summary>
/// <param name="Position">Actual position (<c>P</c>): commanded minus following error.</param>
/// <param name="Commanded">Commanded position.</param>
/// <param name="Machine">Commanded position in counts from where the motor stood at power-on (where switches are placed, <see cref="MotorSettings"/>).</param>
/// <param name="Velocity">Commanded velocity, counts per second.</param>
/// <param name="FollowingError">Following error (<c>F</c>).</param>
/// <param name="HomeComplete">The Home Complete status bit.</param>
/// <param name="Enabled">Amplifier enabled, loop closed (false: killed).</param>
/// <param name="Moving">Making a move of its own (jog, homing).</param>
/// <param name="InPosition">The In Position status bit.</param>
/// <param name="StoppedOnLimit">The Stopped on Position Limit status bit.</param>
/// <param name="PlusLimit">The positive end limit input.</param>
/// <param name="MinusLimit">The negative end limit input.</param>
/// <param name="AmpFault">Killed by an amplifier fault.</param>
/// <param name="FatalFollowingError">Killed by a fatal following error.</param>
public readonly record struct MotorSnapshot(
    double Position,
    double Commanded,
    double Machine,
    double Velocity,
    double FollowingError,
    bool HomeComplete,
    bool Enabled,
    bool Moving,
    bool InPosition,
    bool StoppedOnLimit,
    bool PlusLimit,
    bool MinusLimit,
    bool AmpFault,
    bool FatalFollowingError);
