using System.Diagnostics;

namespace PmacStream.Streaming;

/// <summary>What the job history keeps of a job beside what a resume needs (null in records of older versions).</summary>
/// <param name="ProgramId">The program revision it ran (the store's id), or null (a file streamed by an older version).</param>
/// <param name="Station">The station (PC) that ran it: <c>--station</c>, the settings, or the host name.</param>
/// <param name="Machine">The machine: <c>--machine</c>, else its connection (host:port, serial device, sim).</param>
/// <param name="User">The operating-system user who started it.</param>
/// <param name="Runner">The process running it now, as <c>host:pid:start</c> (to tell a running job from one whose process died).</param>
/// <param name="Ended">When it ended (completed, aborted, alarm, or the process stopped), else null.</param>
/// <param name="Outcome">As recorded: running, completed, aborted, interrupted, alarm.</param>
/// <param name="BlocksExecuted">Motion blocks executed at the last record.</param>
/// <param name="BlocksTotal">Motion blocks of the program.</param>
/// <param name="Stops">Program stops (M00/M01) it met.</param>
/// <param name="Alarms">Faults (link lost, controller errors) it met.</param>
/// <param name="Resumes">Times it was resumed.</param>
public sealed record JobHistory(long? ProgramId, string? Station, string? Machine, string? User, string? Runner, DateTimeOffset? Ended, string? Outcome,
    long? BlocksExecuted, long? BlocksTotal, int Stops, int Alarms, int Resumes)
{
    /// <summary>The outcomes the history names.</summary>
    public static readonly IReadOnlyList<string> Outcomes = ["running", "completed", "aborted", "interrupted", "alarm"];

    /// <summary>This process, as <see cref="Runner"/> records it.</summary>
    public static string ThisProcess
    {
        get
        {
            using var p = Process.GetCurrentProcess();
            return $"{Environment.MachineName}:{p.Id}:{p.StartTime.ToUniversalTime().Ticks}";
        }
    }

    /// <summary>
    /// True when <paramref name="runner"/> is a process on this host that no longer runs (its job was interrupted:
    /// killed, or the PC went down). A runner on another host is taken as alive (its lease says otherwise).
    /// </summary>
    public static bool RunnerGone(string? runner)
    {
        if (runner?.Split(':') is not [var host, var pidText, var ticksText] || !string.Equals(host, Environment.MachineName, StringComparison.OrdinalIgnoreCase))
        {
            return false;
        }

        if (!int.TryParse(pidText, out var pid) || !long.TryParse(ticksText, out var ticks))
        {
            return true;
        }

        try
        {
            using var p = Process.GetProcessById(pid);
            return Math.Abs((p.StartTime.ToUniversalTime() - new DateTime(ticks, DateTimeKind.Utc)).TotalSeconds) > 2;
        }
        catch (Exception e) when (e is ArgumentException or InvalidOperationException or System.ComponentModel.Win32Exception or NotSupportedException)
        {
            return true;
        }
    }
}
