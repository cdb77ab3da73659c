using System.Globalization;
using PmacStream.Pmac;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>
/// Where a library download lands: the coordinate system whose programs call PROG 1000/1001, the tracking variable
/// that names the line it executes, and the last line of the job that completed there (its rotary program still waits
/// for lines after its end, which the next start ends).
/// </summary>
/// <param name="CoordinateSystem">The coordinate system (<c>&amp;1</c>).</param>
/// <param name="TrackingVariable">The tracking variable (<c>M0</c>).</param>
/// <param name="CompletedJobLine">The last line of the job that completed on this controller; null: none known.</param>
public sealed record LibraryDownloadScope(int CoordinateSystem = 1, string TrackingVariable = "M0", int? CompletedJobLine = null)
{
    /// <summary>Coordinate system 1, tracked by M0, no completed job known.</summary>
    public static LibraryDownloadScope Default { get; } = new();
}

/// <summary>
/// Refuses a library download unless the coordinate system is idle: PROG 1000/1001 and the machine's tables replaced
/// under a running program would change what its G and M codes, work offsets and tool lengths do in mid-cut. Idle is
/// no program running and no move in progress; the rotary program of a completed job that only waits for lines after
/// its end (nothing ahead, no move, the tracking variable at that job's last line) is ended first and then counts as idle.
/// </summary>
internal static class LibraryDownloadGuard
{
    private static readonly ILogger Log = Serilog.Log.ForContext(typeof(LibraryDownloadGuard));

    /// <summary>Reads the coordinate system's status, its lines ahead and its tracking variable; throws when it is not idle.</summary>
    /// <exception cref="JobException">A program runs or a move is in progress, or the status reply is not understood.</exception>
    public static async Task RefuseUnlessIdleAsync(IPmacConnection connection, LibraryDownloadScope scope, CancellationToken cancellationToken)
    {
        if (await BusyAsync(connection, scope, cancellationToken).ConfigureAwait(false) is { } busy)
        {
            var message = $"{busy}: the PROG 1000/1001 library and the machine's tables are not loaded under it (they would change what its G and M codes, " +
                          $"work offsets and tool lengths do in mid-cut). Let the program finish, or hold and abort it (&{scope.CoordinateSystem} H, &{scope.CoordinateSystem} A), then load the library again; " +
                          "or run without --load-library on the library the controller has";
            Log.Warning("Library load refused: {Message:l}", message);
            throw new JobException(message, JobErrorKind.Failed);
        }
    }

    /// <summary>
    /// What keeps the coordinate system from being idle (what runs, at which tracking line), or null when it is idle;
    /// the rotary program of the completed job of <paramref name="scope"/>, waiting for lines, is ended (<c>&amp;nA</c>) here.
    /// </summary>
    public static async Task<string?> BusyAsync(IPmacConnection connection, LibraryDownloadScope scope, CancellationToken cancellationToken)
    {
        var cs = "&" + scope.CoordinateSystem.ToString(CultureInfo.InvariantCulture);
        var status = ControllerQueries.FirstValue(await connection.GetResponseAsync($"{cs}??", cancellationToken).ConfigureAwait(false))
            .Replace(" ", string.Empty, StringComparison.Ordinal);
        var running = ControllerQueries.ProgramRunning(status);
        var stopped = ControllerQueries.MotionStopped(status);
        if (running == false && stopped == true)
        {
            return null;
        }

        var line = ControllerQueries.ParseInt(await connection.GetResponseAsync(scope.TrackingVariable, cancellationToken).ConfigureAwait(false), scope.TrackingVariable);
        var ahead = ControllerQueries.ParseInt(await connection.GetResponseAsync("PR", cancellationToken).ConfigureAwait(false), "PR");
        if (running == true && stopped == true && ahead == 0 && scope.CompletedJobLine == line)
        {
            // A controller refuses to open a program buffer while a motion program runs (ERR001): the completed job's
            // rotary program only waits for lines after its end, so it is ended, as the next start would end it.
            Log.Information("{Cs:l}: the completed job's rotary program waits for lines after its last line {Line}, with nothing ahead and no move: ended ({Cs:l}A) before the load", cs, line);
            await connection.GetResponseAsync(cs + "A", cancellationToken).ConfigureAwait(false);
            var after = ControllerQueries.FirstValue(await connection.GetResponseAsync($"{cs}??", cancellationToken).ConfigureAwait(false)).Replace(" ", string.Empty, StringComparison.Ordinal);
            return ControllerQueries.ProgramRunning(after) == false
                ? null
                : $"{cs} still runs the completed job's rotary program after {cs}A ({scope.TrackingVariable}={line}, status '{after}')";
        }

        return running switch
        {
            true => $"{cs} is running a program at {scope.TrackingVariable}={line} ({ahead} line(s) ahead{(stopped == false ? ", a move in progress" : string.Empty)})",
            false => $"{cs} has a move in progress at {scope.TrackingVariable}={line} (no program running)",
            null => $"{cs} answered its status query with '{status}', so whether it runs a program is not known ({scope.TrackingVariable}={line})",
        };
    }
}
