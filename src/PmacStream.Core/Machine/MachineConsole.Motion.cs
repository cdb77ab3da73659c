using System.Diagnostics;
using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Streaming;

namespace PmacStream.Machine;

/// <summary>Home, jog and clear alarms: each refused while a program runs, each returning once the motion ends in position.</summary>
public sealed partial class MachineConsole
{
    /// <summary>Jog speeds accepted, mm/min.</summary>
    public const double MaxJogFeed = 60_000;

    /// <summary>
    /// Homes the axes named (<c>XY</c>, <c>Z</c>; null or empty: all), Z first when it is among them (the tool leaves
    /// the work before the table moves), with each motor's <c>HM</c> (homing speed and direction Ixx23, offset Ixx26).
    /// Returns when every one has Home Complete and is in position.
    /// </summary>
    public async Task<ConsoleResult> HomeAsync(string? axes = null, CancellationToken cancellationToken = default)
    {
        if (Pick(axes) is not { } picked)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, $"no such axis in '{axes}': the machine has {string.Join(string.Empty, Options.Axes.Select(a => a.Name))}");
        }

        if (await RefuseMotionAsync(null, 0, cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        foreach (var group in picked.GroupBy(a => a.Name == "Z" ? 0 : 1).OrderBy(g => g.Key))
        {
            foreach (var a in group)
            {
                Log.Information("Homing {Axis:l} (motor {Motor})", a.Name, a.Motor);
                _targets[a.Name] = 0;
                await Connection.GetResponseAsync($"#{a.Motor}HM", cancellationToken).ConfigureAwait(false);
            }

            var failed = await WaitAsync(group.ToList(), w => w.HomeComplete, cancellationToken).ConfigureAwait(false);
            if (failed is not null)
            {
                return failed;
            }
        }

        return ConsoleResult.Ok($"homed {string.Concat(picked.Select(a => a.Name))}");
    }

    /// <summary>
    /// Incremental jog: <paramref name="distance"/> mm from the commanded position (<c>J:</c>), at
    /// <paramref name="feed"/> mm/min (the motor's Ixx22 for the move, then restored) or the motor's jog speed.
    /// Returns once the axis is in position.
    /// </summary>
    public async Task<ConsoleResult> JogAsync(string axis, double distance, double? feed = null, CancellationToken cancellationToken = default)
    {
        if (!double.IsFinite(distance) || Math.Abs(distance) > MachineTables.MaxOffset)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, string.Create(CultureInfo.InvariantCulture, $"jog distance {distance} is out of range (at most {MachineTables.MaxOffset} mm)"));
        }

        return await JogCoreAsync(axis, Math.Sign(distance), feed, async a =>
        {
            var counts = distance * a.CountsPerMm;
            var reply = await NumbersAsync($"#{a.Motor}P", cancellationToken).ConfigureAwait(false);
            _targets[a.Name] = ((reply.Count > 0 ? reply[0] : 0) / a.CountsPerMm) + distance;
            await Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"#{a.Motor}J:{counts:0.####}"), cancellationToken).ConfigureAwait(false);
            return await WaitAsync([a], _ => true, cancellationToken).ConfigureAwait(false);
        }, cancellationToken).ConfigureAwait(false);
    }

    /// <summary>
    /// Continuous jog for a time: <c>J+</c> or <c>J-</c>, then <c>J/</c> after <paramref name="duration"/> (the host's
    /// clock; the built-in simulator's virtual clock is stepped by as much). Returns once the axis stopped in position.
    /// </summary>
    public async Task<ConsoleResult> JogForAsync(string axis, int direction, TimeSpan duration, double? feed = null, CancellationToken cancellationToken = default)
    {
        if (direction == 0 || duration <= TimeSpan.Zero || duration > Options.MotionTimeout)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, $"a continuous jog needs + or - and a time between 0 and {Options.MotionTimeout.TotalSeconds:0} s");
        }

        return await JogCoreAsync(axis, direction, feed, async a =>
        {
            await StartJogAsync(a, direction, cancellationToken).ConfigureAwait(false);
            await PauseAsync(duration, cancellationToken).ConfigureAwait(false);
            await Connection.GetResponseAsync($"#{a.Motor}J/", cancellationToken).ConfigureAwait(false);
            return await WaitAsync([a], _ => true, cancellationToken).ConfigureAwait(false);
        }, cancellationToken).ConfigureAwait(false);
    }

    /// <summary>
    /// Starts a continuous jog (a jog button pressed) at <paramref name="feed"/> mm/min (the motor's Ixx22 until
    /// <see cref="StopJogAsync"/> ends it and restores it; null: the motor's own jog speed). Refused as <see cref="JogAsync"/> is.
    /// </summary>
    public async Task<ConsoleResult> StartJogAsync(string axis, int direction, double? feed = null, CancellationToken cancellationToken = default)
    {
        if (Axis(axis) is not { } a)
        {
            return NoAxis(axis);
        }

        if (feed is { } f && (!double.IsFinite(f) || f <= 0 || f > MaxJogFeed))
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, string.Create(CultureInfo.InvariantCulture, $"jog speed {f} is out of range (0 < speed <= {MaxJogFeed} mm/min)"));
        }

        if (await RefuseMotionAsync(a, Math.Sign(direction), cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        if (feed is { } speed)
        {
            var variable = $"I{a.Motor}22";
            if (!_heldJogSpeeds.ContainsKey(a.Motor) && (await NumbersAsync(variable, cancellationToken).ConfigureAwait(false)) is [var old, ..])
            {
                _heldJogSpeeds[a.Motor] = old;
            }

            await Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"{variable}={speed * a.CountsPerMm / 60_000:0.######}"), cancellationToken).ConfigureAwait(false);
        }

        await StartJogAsync(a, direction, cancellationToken).ConfigureAwait(false);
        return ConsoleResult.Ok($"jogging {a.Name}{(direction > 0 ? '+' : '-')}");
    }

    /// <summary>Stops a continuous jog (<c>J/</c>), waits until the axis is in position and gives the motor its own jog speed back.</summary>
    public async Task<ConsoleResult> StopJogAsync(string axis, CancellationToken cancellationToken = default)
    {
        if (Axis(axis) is not { } a)
        {
            return NoAxis(axis);
        }

        try
        {
            await Connection.GetResponseAsync($"#{a.Motor}J/", cancellationToken).ConfigureAwait(false);
            return await WaitAsync([a], _ => true, cancellationToken).ConfigureAwait(false) ?? ConsoleResult.Ok($"{a.Name} stopped");
        }
        finally
        {
            if (_heldJogSpeeds.Remove(a.Motor, out var old))
            {
                await Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"I{a.Motor}22={old:0.######}"), CancellationToken.None).ConfigureAwait(false);
            }
        }
    }

    /// <summary>
    /// Clears the alarms that a clear can end: a killed motor (fatal following error, amplifier fault, or killed with
    /// them) closes its loop where it stands (<c>J/</c>), which clears its fault bits (SRM p. 286), and, when no program
    /// runs, <c>&amp;n A</c> closes the loop of the coordinate system's other killed motors. A hardware limit stays until
    /// the axis is jogged off it: the result says so.
    /// </summary>
    public async Task<ConsoleResult> ClearAlarmsAsync(CancellationToken cancellationToken = default)
    {
        var words = await MotorWordsAsync(Connection, Options.Axes, cancellationToken).ConfigureAwait(false);
        var cleared = new List<string>();
        for (var i = 0; i < Options.Axes.Count; i++)
        {
            if (words[i].OpenLoop || words[i].AmplifierFault || words[i].FatalFollowingError)
            {
                await Connection.GetResponseAsync($"#{Options.Axes[i].Motor}J/", cancellationToken).ConfigureAwait(false);
                cleared.Add(Options.Axes[i].Name);
            }
        }

        if (cleared.Count > 0 && CsWord.Parse(await Connection.GetResponseAsync(Cs + "??", cancellationToken).ConfigureAwait(false)) is not { ProgramRunning: true })
        {
            // A fault kill may have killed every motor of the coordinate system (Ixx24), some of them not the console's
            // axes: the abort, with the program already stopped, closes the loop of all of them (SRM p. 275), so the
            // next run command is not refused with ERR012.
            await Connection.GetResponseAsync(Cs + "A", cancellationToken).ConfigureAwait(false);
        }

        var state = await ReadStateAsync(cancellationToken).ConfigureAwait(false);
        var left = state.Stopping.ToList();
        Log.Information("Alarms cleared on {Axes:l}; {Left} left", string.Concat(cleared), left.Count);
        var what = cleared.Count == 0 ? "no fault to clear" : $"cleared the faults of {string.Concat(cleared)} (loop closed)";
        return ConsoleResult.Ok(left.Count == 0 ? what : $"{what}; still active: {string.Join("; ", left.Select(l => l.Text))}");
    }

    private async Task<ConsoleResult> JogCoreAsync(string axis, int direction, double? feed, Func<MachineAxis, Task<ConsoleResult?>> move, CancellationToken cancellationToken)
    {
        if (Axis(axis) is not { } a)
        {
            return NoAxis(axis);
        }

        feed ??= Options.DefaultJogFeed;
        if (feed is { } f && (!double.IsFinite(f) || f <= 0 || f > MaxJogFeed))
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, string.Create(CultureInfo.InvariantCulture, $"--feed {f} is out of range (0 < feed <= {MaxJogFeed} mm/min)"));
        }

        if (await RefuseMotionAsync(a, direction, cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var speedVariable = $"I{a.Motor}22";
        var saved = feed is null ? (double?)null : (await NumbersAsync(speedVariable, cancellationToken).ConfigureAwait(false)) is [var s, ..] ? s : null;
        try
        {
            if (feed is { } speed)
            {
                await Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"{speedVariable}={speed * a.CountsPerMm / 60_000:0.######}"), cancellationToken).ConfigureAwait(false);
            }

            Log.Information("Jog {Axis:l} {Direction:l}{Feed:l}", a.Name, direction > 0 ? "+" : "-", feed is { } x ? string.Create(CultureInfo.InvariantCulture, $" at {x} mm/min") : string.Empty);
            return await move(a).ConfigureAwait(false) ?? ConsoleResult.Ok($"jogged {a.Name}");
        }
        finally
        {
            if (saved is { } old)
            {
                await Connection.GetResponseAsync(string.Create(CultureInfo.InvariantCulture, $"{speedVariable}={old:0.######}"), CancellationToken.None).ConfigureAwait(false);
            }
        }
    }

    private Task StartJogAsync(MachineAxis a, int direction, CancellationToken cancellationToken)
    {
        _targets.Remove(a.Name);
        return Connection.GetResponseAsync($"#{a.Motor}J{(direction > 0 ? '+' : '-')}", cancellationToken);
    }

    /// <summary>
    /// Why motion is refused now, or null: a program runs (or is held) on the coordinate system; a motor is killed or
    /// faulted; the axis is on a hardware limit and the move goes further into it (moving off is always allowed).
    /// <paramref name="axis"/> null: every axis moves (homing).
    /// </summary>
    private async Task<ConsoleResult?> RefuseMotionAsync(MachineAxis? axis, int direction, CancellationToken cancellationToken)
    {
        var words = await MotorWordsAsync(Connection, Options.Axes, cancellationToken).ConfigureAwait(false);
        var alarms = Options.Axes.SelectMany((a, i) => AlarmText.Decode(words[i], a.Motor, a.Name, Options.Language)).Where(a => a.Severity == AlarmSeverity.Alarm).ToList();
        var kills = alarms.Where(a => a.Code is AlarmText.FatalFollowingError or AlarmText.AmplifierFault or AlarmText.MotorKilled).ToList();
        if (kills.Count > 0)
        {
            return ConsoleResult.Refused(ConsoleRefusal.AlarmActive, $"an alarm is active: {kills[0].Text} (pmacstream alarms clear)");
        }

        if (await BusyAsync(cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var into = alarms.FirstOrDefault(l => (axis is null || l.Axis == axis.Name) &&
            ((l.Code == AlarmText.PlusLimit && direction >= 0) || (l.Code == AlarmText.MinusLimit && direction <= 0)));
        return into is null ? null : ConsoleResult.Refused(ConsoleRefusal.AlarmActive, $"an alarm is active: {into.Text}");
    }

    /// <summary>
    /// Refused while a program runs (or is held) or a move is in progress on the coordinate system; the rotary program
    /// of the completed job on this controller, which only waits for lines after its end, is ended (<c>&amp;n A</c>) and
    /// counts as idle, as a job start does.
    /// </summary>
    private async Task<ConsoleResult?> BusyAsync(CancellationToken cancellationToken)
    {
        var completed = LatestJob()?.Checkpoint is { State: SessionState.Completed } done ? done.LastExecutedLine : (int?)null;
        var scope = new LibraryDownloadScope(Options.CoordinateSystem, Options.Settings.TrackVariable, completed);
        return await LibraryDownloadGuard.BusyAsync(Connection, scope, cancellationToken).ConfigureAwait(false) is { } busy
            ? ConsoleResult.Refused(ConsoleRefusal.ProgramRuns, $"{busy}: motion commands and table changes wait until it has ended (or hold and abort it)")
            : null;
    }

    /// <summary>
    /// Waits until each axis is settled (in position, no jog, no homing move) and <paramref name="done"/>; null when it
    /// is, else the failure (a limit or a fault stopped it, or the timeout).
    /// </summary>
    private async Task<ConsoleResult?> WaitAsync(IReadOnlyList<MachineAxis> axes, Func<MotorWord, bool> done, CancellationToken cancellationToken)
    {
        var clock = Stopwatch.StartNew();
        while (true)
        {
            await PauseAsync(Options.Poll, cancellationToken).ConfigureAwait(false);
            var words = await MotorWordsAsync(Connection, axes, cancellationToken).ConfigureAwait(false);
            if (words.All(w => w.Settled && done(w)))
            {
                foreach (var a in axes)
                {
                    _targets.Remove(a.Name);
                }

                // A limit that stopped the move (the bit clears when the motor moves again).
                var limited = axes.Where((_, i) => words[i].StoppedOnLimit).Select(a => a.Name).ToList();
                return limited.Count == 0 ? null : ConsoleResult.Refused(ConsoleRefusal.AlarmActive, $"{string.Concat(limited)} stopped on a limit before the end of the move");
            }

            var stopped = axes.SelectMany((a, i) => AlarmText.Decode(words[i], a.Motor, a.Name, Options.Language)).FirstOrDefault(x => x.Severity == AlarmSeverity.Alarm);
            if (stopped is not null && words.All(w => w.VelocityZero || w.OpenLoop))
            {
                return ConsoleResult.Refused(ConsoleRefusal.AlarmActive, $"the motion stopped on an alarm: {stopped.Text}");
            }

            if (clock.Elapsed > Options.MotionTimeout)
            {
                return ConsoleResult.Refused(ConsoleRefusal.Failed, $"{string.Concat(axes.Select(a => a.Name))} not in position after {Options.MotionTimeout.TotalSeconds:0} s");
            }
        }
    }

    /// <summary>Lets time pass: the built-in simulator's virtual clock is stepped by it, a real controller's runs by itself.</summary>
    private async Task PauseAsync(TimeSpan time, CancellationToken cancellationToken)
    {
        if (Controller.Simulator?.Step is { } step)
        {
            for (var left = time; left > TimeSpan.Zero; left -= Options.Poll)
            {
                step(left < Options.Poll ? left : Options.Poll);
                await Task.Yield();
            }

            return;
        }

        await Task.Delay(time, cancellationToken).ConfigureAwait(false);
    }

    private async Task<List<double>> NumbersAsync(string query, CancellationToken cancellationToken) =>
        Numbers(await Connection.GetResponseAsync(query, cancellationToken).ConfigureAwait(false));

    private MachineAxis? Axis(string name) => Options.Axes.FirstOrDefault(a => string.Equals(a.Name, name.Trim(), StringComparison.OrdinalIgnoreCase));

    private ConsoleResult NoAxis(string name) =>
        ConsoleResult.Refused(ConsoleRefusal.BadValue, $"no axis '{name}': the machine has {string.Join(", ", Options.Axes.Select(a => a.Name))}");

    /// <summary>The axes named by letters (<c>XY</c>, <c>all</c> or empty for every one), or null when a letter names none.</summary>
    private List<MachineAxis>? Pick(string? letters)
    {
        if (string.IsNullOrWhiteSpace(letters) || letters.Trim().Equals("all", StringComparison.OrdinalIgnoreCase))
        {
            return [.. Options.Axes];
        }

        var picked = new List<MachineAxis>();
        foreach (var c in letters.Trim())
        {
            if (Axis(c.ToString()) is not { } a)
            {
                return null;
            }

            if (!picked.Contains(a))
            {
                picked.Add(a);
            }
        }

        return picked;
    }
}
