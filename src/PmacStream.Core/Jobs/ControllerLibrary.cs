using PmacStream.GCode;
using PmacStream.Pmac;
using PmacStream.Program;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>The PROG 1000/1001 G and M code library a controller needs before a job (the built-in simulator starts empty).</summary>
public static class ControllerLibrary
{
    private static readonly ILogger Log = Serilog.Log.ForContext(typeof(ControllerLibrary));

    /// <summary>The library for a machine profile, one downloadable line per entry (no comments).</summary>
    public static IReadOnlyList<string> Lines(MachineProfile? profile = null) =>
        Prog1000Library.Generate(profile ?? MachineProfile.Default, new Prog1000Options { Comments = false })
            .Split(["\r\n", "\n"], StringSplitOptions.RemoveEmptyEntries | StringSplitOptions.TrimEntries)
            .Where(l => l[0] != ';')
            .ToList();

    /// <summary>
    /// Downloads program lines one by one and goes on past a line the controller refuses (logged as a warning with
    /// its ERR number), so one routine a controller does not support (the simulator has no cutter compensation) does
    /// not leave the whole library missing. Returns the refused lines.
    /// </summary>
    public static async Task<IReadOnlyList<string>> DownloadTolerantAsync(IPmacConnection connection, IEnumerable<string> lines, CancellationToken cancellationToken = default)
    {
        var refused = new List<string>();
        foreach (var line in lines)
        {
            try
            {
                await connection.GetResponseAsync(line, cancellationToken).ConfigureAwait(false);
            }
            catch (PmacErrorException e)
            {
                refused.Add(line);
                Log.Warning("{Device:l} refused library line '{Line:l}' (ERR{Number:000}); the code it defines does nothing", connection.Description, line, e.Number);
            }
        }

        return refused;
    }
}
