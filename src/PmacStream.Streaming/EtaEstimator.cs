namespace PmacStream.Streaming;

/// <summary>
/// Remaining time of a job in real (wall) seconds. The interpreter's move times are program seconds at the programmed
/// feed; the machine runs them scaled by the live feed (P500 over the programmed F in paper mode, the % override in
/// override mode) and, beyond that, at whatever rate it really achieves (acceleration, a simulator clock running
/// faster than real time, a controller slower than the model). So:
/// <c>ETA = program seconds left / (feed factor x measured rate)</c>, where the measured rate is predicted wall time
/// over actual wall time for the program seconds executed so far, exponentially smoothed over about
/// <see cref="SmoothingSeconds"/> of predicted time so it follows changes but does not jump with each block.
/// </summary>
public sealed class EtaEstimator
{
    private double _lastWall = double.NaN;
    private double _lastDone;
    private double _lastFactor = 1;
    private double _predicted;
    private double _actual;

    /// <summary>Creates an estimator; <paramref name="smoothingSeconds"/> is the memory of the rate, in predicted seconds.</summary>
    public EtaEstimator(double smoothingSeconds = 30)
    {
        SmoothingSeconds = smoothingSeconds > 0 ? smoothingSeconds : throw new ArgumentOutOfRangeException(nameof(smoothingSeconds));
    }

    /// <summary>How much predicted time the measured rate remembers (its time constant).</summary>
    public double SmoothingSeconds { get; }

    /// <summary>Measured rate: predicted wall seconds per actual wall second (1 until something was measured).</summary>
    /// <remarks>
    /// The model's 1.0 until half a smoothing span of program time was measured: the first blocks' intervals (a tool
    /// change the stop watch has not seen yet, the tick's quantization) say little, and the move times are the
    /// controller's own (docs/turbo-pmac-timing.md), so an early rate only made the ETA worse (issue 28's table).
    /// </remarks>
    public double Rate => _actual > 1e-9 && _predicted >= SmoothingSeconds / 2 ? _predicted / _actual : 1.0;

    /// <summary>Predicted seconds measured so far (decayed): how much the rate rests on.</summary>
    public double Evidence => _predicted;

    /// <summary>
    /// Records progress: at wall time <paramref name="wallSeconds"/>, <paramref name="programSecondsDone"/> program
    /// seconds (at programmed feed) lie behind the executing block, with <paramref name="feedFactor"/> in force.
    /// Pass <paramref name="counting"/> false while held or stopped: that time is not the machine's rate.
    /// </summary>
    public void Observe(double wallSeconds, double programSecondsDone, double feedFactor, bool counting)
    {
        var factor = SaneFactor(feedFactor);
        if (double.IsNaN(_lastWall) || !counting || programSecondsDone < _lastDone)
        {
            Restart(wallSeconds, programSecondsDone, factor);
            return;
        }

        if (programSecondsDone == _lastDone)
        {
            // Within one block: wait for the next block boundary, so an interval always covers whole blocks.
            _lastFactor = factor;
            return;
        }

        var dt = wallSeconds - _lastWall;
        var predicted = (programSecondsDone - _lastDone) / _lastFactor;
        if (dt > 0)
        {
            var keep = Math.Exp(-predicted / SmoothingSeconds);
            _predicted = (_predicted * keep) + predicted;
            _actual = (_actual * keep) + dt;
        }

        Restart(wallSeconds, programSecondsDone, factor);
    }

    /// <summary>Wall seconds left for <paramref name="programSecondsLeft"/> program seconds at <paramref name="feedFactor"/>.</summary>
    public TimeSpan Estimate(double programSecondsLeft, double feedFactor) =>
        TimeSpan.FromSeconds(Math.Max(0, programSecondsLeft) / (SaneFactor(feedFactor) * Rate));

    private static double SaneFactor(double f) => double.IsFinite(f) && f > 0 ? Math.Clamp(f, 0.01, 100) : 1.0;

    private void Restart(double wall, double done, double factor)
    {
        _lastWall = wall;
        _lastDone = done;
        _lastFactor = factor;
    }
}
