using System.Globalization;
using PmacStream.Pmac;
using PmacStream.Preparation;
using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// The reads a session makes of one coordinate system, as numbers and flags: the tracking variable (M0), lines ahead
/// (<c>PR</c>), the line probe, the live feed and the status word (<c>&amp;n??</c>). An unexpected reply to a number is
/// a link fault; a status word of another shape is tolerated once and then no longer asked for motion.
/// </summary>
internal sealed class ControllerQueries
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    private readonly ControllerChannel _channel;
    private readonly CoordinateSystemCommands _cs;
    private readonly SyncAssignment _sync;

    /// <summary>Reads the coordinate system of <paramref name="cs"/> over <paramref name="channel"/>, tracked by <paramref name="sync"/>.</summary>
    public ControllerQueries(ControllerChannel channel, CoordinateSystemCommands cs, SyncAssignment sync)
    {
        _channel = channel;
        _cs = cs;
        _sync = sync;
    }

    /// <summary>
    /// True once the controller answered the status query in another shape: motion is then taken as stopped and the
    /// drain waits for more stable readings instead.
    /// </summary>
    public bool StatusUnknown { get; private set; }

    /// <summary>Reads the tracking variable: the source line executing (its round trip is measured).</summary>
    public async ValueTask<int> TrackedLineAsync(CancellationToken cancellationToken)
    {
        var text = await _channel.QueryTimedAsync(_sync.ReadCommand, cancellationToken).ConfigureAwait(false);
        return ParseInt(text, _sync.ReadCommand);
    }

    /// <summary>Reads <c>PR</c>: program lines in the rotary buffer ahead of the calculation.</summary>
    public async ValueTask<int> LinesAheadAsync(CancellationToken cancellationToken) =>
        ParseInt(await _channel.OnlineAsync("PR", cancellationToken).ConfigureAwait(false), "PR");

    /// <summary>Reads the line-probe variable (the position value of the last line calculated).</summary>
    public async ValueTask<long> ProbeAsync(string probe, CancellationToken cancellationToken)
    {
        var text = FirstValue(await _channel.OnlineAsync(probe, cancellationToken).ConfigureAwait(false));
        return double.TryParse(text, NumberStyles.Float, CultureInfo.InvariantCulture, out var v) && v >= 0 && v < 1e15
            ? (long)Math.Round(v)
            : throw new PmacLinkException($"unexpected reply '{text}' to {probe}");
    }

    /// <summary>Reads the live feed (the feed variable, or <c>&amp;n %</c>); null when refused or not a number.</summary>
    public async ValueTask<double?> FeedAsync(CancellationToken cancellationToken)
    {
        try
        {
            var text = await _channel.OnlineAsync(_cs.ReadFeed, cancellationToken).ConfigureAwait(false);
            return double.TryParse(FirstValue(text), NumberStyles.Float, CultureInfo.InvariantCulture, out var v) ? v : null;
        }
        catch (PmacErrorException)
        {
            return null;
        }
    }

    /// <summary>
    /// True when no move is executing or queued (status second word: bit 17 in position, bit 21 segments queued). A
    /// reply of another shape sets <see cref="StatusUnknown"/> and counts as stopped; an ERR reply is a fault like any
    /// other (it must not be mistaken for "stopped").
    /// </summary>
    public async ValueTask<bool> MotionStoppedAsync(CancellationToken cancellationToken)
    {
        if (StatusUnknown)
        {
            return true;
        }

        var text = await StatusAsync(cancellationToken).ConfigureAwait(false);
        if (MotionStopped(text) is { } stopped)
        {
            return stopped;
        }

        Log.Warning("unexpected status reply '{Text}' to {Status}; the drain falls back to stable M0 readings", text, _cs.Status);
        StatusUnknown = true;
        return true;
    }

    /// <summary>The program-running bit of the status (first word, bit 0); null when the reply is not understood.</summary>
    public async ValueTask<bool?> ProgramRunningAsync(CancellationToken cancellationToken) =>
        ProgramRunning(await StatusAsync(cancellationToken).ConfigureAwait(false));

    /// <summary>
    /// Where the controller is with a job: <c>PR</c> first, then M0, the status and the line probe (null: none). Lines
    /// only leave the buffer meanwhile, so <c>PR</c> read first never counts fewer lines than M0 read after it leaves.
    /// </summary>
    public async ValueTask<ControllerReading> ReadAsync(string? probe, CancellationToken cancellationToken)
    {
        var linesAhead = await LinesAheadAsync(cancellationToken).ConfigureAwait(false);
        var tracked = await TrackedLineAsync(cancellationToken).ConfigureAwait(false);
        var running = await ProgramRunningAsync(cancellationToken).ConfigureAwait(false);
        long? value = probe is null ? null : await ProbeAsync(probe, cancellationToken).ConfigureAwait(false);
        return new ControllerReading(tracked, running, linesAhead, value);
    }

    /// <summary>The motion-stopped bits of a status reply (blanks removed); null when it is not two hex words.</summary>
    internal static bool? MotionStopped(string status) =>
        status.Length >= 12 && int.TryParse(status.AsSpan(6, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var w2)
            ? (w2 & (1 << 17)) != 0 && (w2 & (1 << 21)) == 0
            : null;

    /// <summary>The program-running bit of a status reply (blanks removed); null when it does not start with a hex word.</summary>
    internal static bool? ProgramRunning(string status) =>
        status.Length >= 6 && int.TryParse(status.AsSpan(0, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var w1)
            ? (w1 & 1) != 0
            : null;

    /// <summary>The first value of a reply (values are separated by line ends), trimmed.</summary>
    internal static string FirstValue(string text)
    {
        var t = text.Trim();
        var nl = t.IndexOf('\n');
        return nl >= 0 ? t[..nl].Trim() : t;
    }

    /// <summary>A reply's first value as a whole number (rounded); anything else is a link fault.</summary>
    internal static int ParseInt(string text, string what) =>
        double.TryParse(FirstValue(text), NumberStyles.Float, CultureInfo.InvariantCulture, out var v)
            ? (int)Math.Round(v)
            : throw new PmacLinkException($"unexpected reply '{text}' to {what}");

    private async ValueTask<string> StatusAsync(CancellationToken cancellationToken) =>
        FirstValue(await _channel.OnlineAsync(_cs.Status, cancellationToken).ConfigureAwait(false)).Replace(" ", string.Empty, StringComparison.Ordinal);
}
