using System.Globalization;

namespace PmacStream.Machine;

/// <summary>What the DRO reads beyond positions: distance to go from the motors' target registers, the spindle.</summary>
public sealed partial class MachineConsole
{
    // Per axis: true when its Mxx61 and Mxx63 point at memory (Delta Tau's suggested definitions); read once.
    private bool[]? _targetReadable;
    private double[]? _registerUnits;

    /// <summary>
    /// Distance to go per axis, mm: the motor's target (end) position register (<c>Mxx63</c>) less its commanded position
    /// (<c>Mxx61</c>), both in 1/(Ixx08*32) counts, so a job's block shows what is left of it, and 0 once in position.
    /// An axis whose M-variables are not defined on the controller falls back to the console's own move (jog, home).
    /// </summary>
    private async Task<double[]> ToGoAsync(double[] machine, CancellationToken cancellationToken)
    {
        var axes = Options.Axes;
        var toGo = axes.Select((a, i) => _targets.TryGetValue(a.Name, out var t) ? t - machine[i] : 0).ToArray();
        if (Options.TargetVariable is not { } suffix)
        {
            return toGo;
        }

        if (_targetReadable is null)
        {
            _targetReadable = new bool[axes.Count];
            for (var i = 0; i < axes.Count; i++)
            {
                _targetReadable[i] = await DefinedAsync(Var(axes[i].Motor, suffix), cancellationToken).ConfigureAwait(false)
                    && await DefinedAsync(Var(axes[i].Motor, 61), cancellationToken).ConfigureAwait(false);
            }

            var scale = Numbers(await Connection.GetResponseAsync(string.Join(' ', axes.Select(a => $"I{a.Motor}08")), cancellationToken).ConfigureAwait(false));
            _registerUnits = axes.Select((_, i) => (i < scale.Count && scale[i] > 0 ? scale[i] : 96) * 32).ToArray();
        }

        var read = Enumerable.Range(0, axes.Count).Where(i => _targetReadable[i]).ToList();
        if (read.Count == 0)
        {
            return toGo;
        }

        var values = Numbers(await Connection.GetResponseAsync(string.Join(' ', read.Select(i => $"M{Var(axes[i].Motor, 61)} M{Var(axes[i].Motor, suffix)}")), cancellationToken).ConfigureAwait(false));
        for (var k = 0; k < read.Count && (2 * k) + 1 < values.Count; k++)
        {
            var i = read[k];
            toGo[i] = (values[(2 * k) + 1] - values[2 * k]) / _registerUnits![i] / axes[i].CountsPerMm;
        }

        return toGo;
    }

    /// <summary>Mxx{suffix} of a motor: M163 for motor 1's target position.</summary>
    private static int Var(int motor, int suffix) => (motor * 100) + suffix;

    /// <summary>True when the M-variable points at memory (its definition is not <c>*</c>, the self-referenced default).</summary>
    private async Task<bool> DefinedAsync(int m, CancellationToken cancellationToken)
    {
        var reply = (await Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"M{m}->"), cancellationToken).ConfigureAwait(false)).Trim().TrimEnd('\u0006').Trim();
        return reply.Contains(':', StringComparison.Ordinal);
    }

    /// <summary>
    /// The spindle: programmed speed from the coordinate system's Q127 (where <c>S{data}</c> puts it), the library's
    /// spindle-on and reverse outputs, and the actual speed from the spindle motor's velocity when there is one (rpm from
    /// counts per servo cycle), else the programmed speed while the spindle is on.
    /// </summary>
    private async Task<SpindleReadout> SpindleAsync(CancellationToken cancellationToken)
    {
        var o = Options;
        var v = Numbers(await Connection.GetResponseAsync($"{Cs} {o.SpindleSpeedVariable} {o.SpindleOnVariable} {o.SpindleReverseVariable}", cancellationToken).ConfigureAwait(false));
        double V(int i) => i < v.Count ? v[i] : 0;
        var programmed = V(0);
        var on = V(1) != 0;
        double actual;
        if (o.SpindleMotor is { } motor)
        {
            _servoCycleMs ??= await NumberAsync("I10", cancellationToken).ConfigureAwait(false) / 8_388_608.0;
            var counts = await NumberAsync($"#{motor}V", cancellationToken).ConfigureAwait(false);
            actual = _servoCycleMs > 0 && o.SpindleCountsPerRev > 0 ? Math.Abs(counts) / _servoCycleMs.Value * 60_000 / o.SpindleCountsPerRev : 0;
        }
        else
        {
            actual = on ? programmed : 0;
        }

        return new SpindleReadout(Round(programmed), Math.Round(actual, 1), on, V(2) != 0);
    }
}
