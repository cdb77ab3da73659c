using System.Diagnostics;
using PmacStream.Pmac;
using Serilog;
using Serilog.Events;

namespace PmacStream.Streaming;

/// <summary>
/// A session's line to the controller: every command and reply logged at Debug, the measured round trip, and the
/// open-buffer rule. While this port has a buffer open, whatever it sends is stored in the buffer, not run: so an
/// online command (a read of M0, a feed change, <c>&amp;n R</c>) is refused then, except <c>CLOSE</c>.
/// Value tasks: over an in-process link every layer completes at once, and a tick allocates nothing for them.
/// </summary>
internal sealed class ControllerChannel
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    private readonly IPmacConnection _conn;

    /// <summary>Sends over <paramref name="connection"/>.</summary>
    public ControllerChannel(IPmacConnection connection) => _conn = connection;

    /// <summary>
    /// True while a buffer may be open on this port: set before program lines go out (and when it is unknown, after a
    /// crash or a broken link), cleared by <c>CLOSE</c>.
    /// </summary>
    public bool BufferOpen { get; set; }

    /// <summary>Measured round trip of a query or batch, seconds (smoothed; 0 until measured).</summary>
    public double RoundTripSeconds { get; private set; }

    /// <summary>
    /// The longest single query or batch so far, seconds: over a lossy link a request whose packet was lost waits for
    /// TCP's retransmission timeout (200 ms or more on Linux), so this is the stall the lead must ride out.
    /// </summary>
    public double WorstRoundTripSeconds { get; private set; }

    /// <summary>Sends a line as it is (program lines, <c>OPEN ROT</c>, <c>CLEAR</c>); returns the reply.</summary>
    public async ValueTask<string> SendAsync(string command, CancellationToken cancellationToken)
    {
        var t0 = Stopwatch.GetTimestamp();
        var reply = await _conn.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
        if (Log.IsEnabled(LogEventLevel.Debug))
        {
            // Checked first: four values would be boxed into an array on every command of every tick otherwise.
            Log.Debug("{Device} {Command} -> {Reply} ({Ms:0.000} ms)", _conn.Description, command, reply, Stopwatch.GetElapsedTime(t0).TotalMilliseconds);
        }

        return reply;
    }

    /// <summary>An online command: refused while a buffer is open (it would be stored, not run), except <c>CLOSE</c>, which closes it.</summary>
    public async ValueTask<string> OnlineAsync(string command, CancellationToken cancellationToken)
    {
        var close = command.Equals("CLOSE", StringComparison.OrdinalIgnoreCase);
        if (BufferOpen && !close)
        {
            throw new InvalidOperationException($"'{command}' must not be sent while a buffer is open on this port (it would be stored in the buffer)");
        }

        var reply = await SendAsync(command, cancellationToken).ConfigureAwait(false);
        if (close)
        {
            BufferOpen = false;
        }

        return reply;
    }

    /// <summary>An online command whose refusal (<c>ERRnnn</c>) does not matter (deleting what may not exist).</summary>
    public async ValueTask OnlineIgnoringErrorAsync(string command, CancellationToken cancellationToken)
    {
        try
        {
            await OnlineAsync(command, cancellationToken).ConfigureAwait(false);
        }
        catch (PmacErrorException e)
        {
            Log.Debug("{Command} refused (ERR{Number:000}), ignored", command, e.Number);
        }
    }

    /// <summary>An online query whose round trip is measured.</summary>
    public async ValueTask<string> QueryTimedAsync(string command, CancellationToken cancellationToken)
    {
        var t0 = Stopwatch.GetTimestamp();
        var reply = await OnlineAsync(command, cancellationToken).ConfigureAwait(false);
        MeasureRoundTrip(Stopwatch.GetElapsedTime(t0).TotalSeconds);
        return reply;
    }

    /// <summary>
    /// Sends a batch of lines in one write (<c>OPEN ROT</c>, program lines, <c>CLOSE</c>), measuring the round trip;
    /// a refused line throws <see cref="PmacErrorException"/> with its index in the batch. With several packets in flight
    /// the measured time is the batch's, not one request's.
    /// </summary>
    public async Task DownloadAsync(IReadOnlyList<string> batch, int programLines, int packetsInFlight, CancellationToken cancellationToken)
    {
        var sw = Stopwatch.StartNew();
        await _conn.DownloadAsync(batch, packetsInFlight, cancellationToken).ConfigureAwait(false);
        MeasureRoundTrip(sw.Elapsed.TotalSeconds);
        Log.Debug("{Device} sent {Count} program lines ({Ms:0.0} ms)", _conn.Description, programLines, sw.Elapsed.TotalMilliseconds);
    }

    /// <summary>Closes the buffer after a refused line; a link that is gone leaves it to recovery, which closes first.</summary>
    public async ValueTask TryCloseAsync(CancellationToken cancellationToken)
    {
        try
        {
            await SendAsync("CLOSE", cancellationToken).ConfigureAwait(false);
            BufferOpen = false;
        }
        catch (PmacErrorException)
        {
            BufferOpen = false; // CLOSE refused: nothing was open
        }
        catch (PmacLinkException)
        {
            // Left for recovery, which sends CLOSE first.
        }
    }

    private void MeasureRoundTrip(double seconds)
    {
        RoundTripSeconds = RoundTripSeconds <= 0 ? seconds : (0.8 * RoundTripSeconds) + (0.2 * seconds);
        WorstRoundTripSeconds = Math.Max(WorstRoundTripSeconds, seconds);
    }
}
