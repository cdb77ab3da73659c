namespace PmacStream.Sim;

/// <summary>
/// What the simulated machine has around one motor that a Turbo PMAC cannot know from its I-variables: where its
/// home switch and its hardware overtravel limit switches are. Positions are in counts of the machine, measured from
/// where the motor stood at power-on (the encoder's zero). All *assumed*: a simulator setting.
/// </summary>
public sealed class MotorSettings
{
    /// <summary>Where the home switch triggers, in counts from the power-on position. Default 0: a homing search finds it at once.</summary>
    public double HomeSwitchPosition { get; set; }

    /// <summary>Where the positive end limit switch is (counts from the power-on position); null for none (default).</summary>
    public double? PlusLimitPosition { get; set; }

    /// <summary>Where the negative end limit switch is (counts from the power-on position); null for none (default).</summary>
    public double? MinusLimitPosition { get; set; }
}
