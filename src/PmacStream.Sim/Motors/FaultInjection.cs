using System.Globalization;

namespace PmacStream.Sim;

/// <summary>The faults the simulator can inject into a motor (tests and demos).</summary>
public enum FaultKind
{
    /// <summary>The positive end (overtravel) limit input comes on where the motor is; it stays until the motor is moved off it.</summary>
    PlusLimit,

    /// <summary>The negative end (overtravel) limit input comes on where the motor is; it stays until the motor is moved off it.</summary>
    MinusLimit,

    /// <summary>The following error exceeds Ixx11: the motor (and the motors of its coordinate system) is killed until re-enabled.</summary>
    FatalFollowingError,

    /// <summary>The amplifier reports a fault: the motor (and the motors of its coordinate system) is killed until re-enabled.</summary>
    AmpFault,
}

/// <summary>
/// A fault to inject into <see cref="Motor"/> at <see cref="Seconds"/> on the simulator's clock counted from the moment
/// a motion program first starts running (homing and jogging before it do not count), so that a fault lands mid-job
/// whatever the clock speed. Written <c>KIND:MOTOR@SECONDS</c>, e.g. <c>limit+:1@2.5</c>.
/// </summary>
/// <param name="Kind">What happens.</param>
/// <param name="Motor">The motor number, 1..32.</param>
/// <param name="Seconds">Virtual seconds after the first program start.</param>
public sealed record FaultInjection(FaultKind Kind, int Motor, double Seconds)
{
    /// <summary>The names <see cref="Parse"/> accepts, as the command line writes them.</summary>
    public static IReadOnlyList<string> KindNames { get; } = ["limit+", "limit-", "fatal-following-error", "amp-fault"];

    /// <summary>Parses <c>KIND:MOTOR@SECONDS</c> (KIND one of <see cref="KindNames"/>); throws <see cref="FormatException"/> with the reason.</summary>
    public static FaultInjection Parse(string text)
    {
        var t = text.Trim();
        var colon = t.LastIndexOf(':');
        var at = t.IndexOf('@', StringComparison.Ordinal);
        if (colon <= 0 || at < colon)
        {
            throw new FormatException($"--inject '{text}': expected KIND:MOTOR@SECONDS, e.g. limit+:1@2.5");
        }

        var kind = t[..colon].ToLowerInvariant() switch
        {
            "limit+" => FaultKind.PlusLimit,
            "limit-" => FaultKind.MinusLimit,
            "fatal-following-error" => FaultKind.FatalFollowingError,
            "amp-fault" => FaultKind.AmpFault,
            _ => throw new FormatException($"--inject '{text}': KIND must be one of {string.Join(", ", KindNames)}"),
        };
        if (!int.TryParse(t[(colon + 1)..at], NumberStyles.None, CultureInfo.InvariantCulture, out var motor) || motor < 1 || motor > MotorMap.Count)
        {
            throw new FormatException($"--inject '{text}': MOTOR must be a motor number 1..{MotorMap.Count}");
        }

        if (!double.TryParse(t[(at + 1)..], NumberStyles.Float, CultureInfo.InvariantCulture, out var seconds) || !(seconds >= 0) || double.IsInfinity(seconds))
        {
            throw new FormatException($"--inject '{text}': SECONDS must be 0 or more");
        }

        return new FaultInjection(kind, motor, seconds);
    }

    /// <summary>The command-line name of <paramref name="kind"/>.</summary>
    public static string Name(FaultKind kind) => KindNames[(int)kind];

    /// <inheritdoc />
    public override string ToString() => string.Create(CultureInfo.InvariantCulture, $"{Name(Kind)}:{Motor}@{Seconds}");
}
