using System.Diagnostics;
using System.Globalization;

namespace PmacStream.Testing;

/// <summary>
/// How long a fuzz target runs and from which seed: <c>PMACSTREAM_FUZZ_SECONDS</c> (default 4: CI runs each target
/// for seconds) and <c>PMACSTREAM_FUZZ_SEED</c> (default fixed, so a CI failure repeats; <c>bench/scripts/fuzz.sh</c>
/// runs longer with fresh seeds). A failure names the seed and the input.
/// </summary>
public sealed class FuzzBudget
{
    private readonly Stopwatch _clock = Stopwatch.StartNew();

    public FuzzBudget(int defaultSeed)
    {
        Seconds = Read("PMACSTREAM_FUZZ_SECONDS", 4);
        Seed = (int)Read("PMACSTREAM_FUZZ_SEED", defaultSeed);
    }

    public double Seconds { get; }

    public int Seed { get; }

    /// <summary>Most time one input may take before it counts as a hang.</summary>
    public static TimeSpan HangLimit => TimeSpan.FromSeconds(10);

    public bool Left => _clock.Elapsed.TotalSeconds < Seconds;

    public TimeSpan Elapsed => _clock.Elapsed;

    private static double Read(string name, double fallback) =>
        double.TryParse(Environment.GetEnvironmentVariable(name), NumberStyles.Float, CultureInfo.InvariantCulture, out var v) && v > 0 ? v : fallback;
}
