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

    /// <summary>The library for a profile with other options (outputs, program stops, variable map), one line per entry.</summary>
    public static IReadOnlyList<string> Lines(MachineProfile profile, Prog1000Options options) =>
        Prog1000Library.Generate(profile, options with { Comments = false })
            .Split(["\r\n", "\n"], StringSplitOptions.RemoveEmptyEntries | StringSplitOptions.TrimEntries)
            .Where(l => l[0] != ';')
            .ToList();

    /// <summary>
    /// The machine's tables as the library keeps them, as online assignments the host downloads: work offsets G54-G59
    /// (and G59.1-G59.3), tool lengths and the tool change position of the profile (millimetres, machine coordinates).
    /// </summary>
    public static IReadOnlyList<string> TableLines(MachineProfile profile, LibraryMap? map = null)
    {
        map ??= new LibraryMap();
        var lines = new List<string>();
        string Num(double v) => HostConversion.Num(v);
        for (var index = 1; index <= 9; index++)
        {
            var code = index <= 6 ? 53 + index : 0;
            var o = code > 0 ? profile.WorkOffset(code) : default;
            var at = map.WorkOffsets + (3 * index);
            lines.Add($"P{at}={Num(o.X)} P{at + 1}={Num(o.Y)} P{at + 2}={Num(o.Z)}");
        }

        foreach (var (h, length) in profile.ToolLengths)
        {
            lines.Add($"P{map.ToolLengths + int.Parse(h, System.Globalization.CultureInfo.InvariantCulture)}={Num(length)}");
        }

        if (profile.ToolChangePosition is { } tc)
        {
            lines.Add($"P{map.ToolChangePosition}={Num(tc[0])} P{map.ToolChangePosition + 1}={Num(tc[1])} P{map.ToolChangePosition + 2}={Num(tc[2])}");
        }

        return lines;
    }

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
