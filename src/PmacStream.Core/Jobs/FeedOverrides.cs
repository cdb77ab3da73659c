using System.Globalization;

namespace PmacStream.Jobs;

/// <summary>
/// The operator's feed control on every face: the coordinate system's feed override (<c>&amp;n %v</c>), a Turbo
/// PMAC feature that slews to the new value, applies at once and is never written by the program. Programmed feeds
/// (carried in P500 by paper-mode chunks) stay the program's; what the machine runs is programmed x override.
/// </summary>
public static class FeedOverrides
{
    /// <summary>The override a job starts with unless told otherwise: the programmed feeds as written.</summary>
    public const double Default = 100;

    /// <summary>Lowest override the faces offer (motion stands still).</summary>
    public const double Minimum = 0;

    /// <summary>Highest override the faces offer.</summary>
    public const double Maximum = 200;

    /// <summary>Checks that <paramref name="percent"/> lies in <see cref="Minimum"/>..<see cref="Maximum"/>.</summary>
    /// <exception cref="JobException">It does not (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public static double Validate(double percent) =>
        percent is >= Minimum and <= Maximum
            ? percent
            : throw new JobException(string.Create(CultureInfo.InvariantCulture, $"feed override {percent} % is outside {Minimum}-{Maximum} %"), JobErrorKind.BadRequest);

    /// <summary>The feed that results from a programmed feed and an override (percent).</summary>
    public static double Resulting(double programmedFeed, double percent) => programmedFeed * percent / 100.0;
}
