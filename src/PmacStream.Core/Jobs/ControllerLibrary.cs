using System.Globalization;
using System.Text;
using PmacStream.GCode;
using PmacStream.Pmac;
using PmacStream.Preparation;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>What a job does about the controller's library before the first chunk.</summary>
public enum LibraryPolicy
{
    /// <summary>Read the library's identity (P7000, P7001) and refuse a controller with none or another one.</summary>
    Verify,

    /// <summary>Download the library and the machine's tables first, then verify (<c>--load-library</c>).</summary>
    Load,

    /// <summary>Read and log the identity, never refuse (<c>--force</c>).</summary>
    Force,
}

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
    /// The machine's tables as the library keeps them, as online assignments the host downloads: FANUC's external work
    /// offset (zero) where the profile has one, work offsets G54-G59 (and G59.1-G59.3), tool lengths and the tool change position of the profile (millimetres, machine coordinates).
    /// </summary>
    public static IReadOnlyList<string> TableLines(MachineProfile profile, LibraryMap? map = null)
    {
        map ??= new LibraryMap();
        var lines = new List<string>();
        string Num(double v) => HostConversion.Num(v);
        // Index 0 is FANUC's external work offset where the profile has one: zero, as the host's interpreter starts it.
        for (var index = profile.ExternalWorkOffset ? 0 : 1; index <= 9; index++)
        {
            var code = index is >= 1 and <= 6 ? 53 + index : 0;
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

    /// <summary>The machine's tables as a reader sees them (<c>pmacstream machine</c>), each value with the P-variable the library reads it from.</summary>
    public static string DescribeTables(MachineProfile machine, LibraryMap? map = null)
    {
        map ??= new LibraryMap();
        static string N(double v) => HostConversion.Num(v);
        var s = new StringBuilder();
        s.Append(CultureInfo.InvariantCulture, $"Machine tables of profile '{machine.Name}' (millimetres, machine coordinates).\n");
        s.Append("Set them in the profile file (workOffsets, toolLengths, referencePositions, toolChangePosition); `machine --lines` writes them for download, `stream --load-library` downloads them; a program's G10 changes them on the controller.\n");
        s.Append("work offsets:\n");
        for (var index = 1; index <= 6; index++)
        {
            var o = machine.WorkOffset(53 + index);
            var at = map.WorkOffsets + (3 * index);
            s.Append(CultureInfo.InvariantCulture, $"  G{53 + index}  X{N(o.X)} Y{N(o.Y)} Z{N(o.Z)}  (P{at}-P{at + 2})\n");
        }

        s.Append("tool lengths:");
        s.Append(machine.ToolLengths.Count == 0 ? " none (every H is 0)\n" : "\n");
        foreach (var (h, length) in machine.ToolLengths.OrderBy(t => int.Parse(t.Key, CultureInfo.InvariantCulture)))
        {
            s.Append(CultureInfo.InvariantCulture, $"  H{h}  {N(length)}  (P{map.ToolLengths + int.Parse(h, CultureInfo.InvariantCulture)})\n");
        }

        s.Append("reference positions (host side: G28/G30 are sent as G53 moves):\n");
        foreach (var code in new[] { 28, 30 })
        {
            var r = machine.ReferencePosition(code);
            s.Append(CultureInfo.InvariantCulture, $"  G{code}  X{N(r.X)} Y{N(r.Y)} Z{N(r.Z)}\n");
        }

        s.Append(machine.ToolChangePosition is { } tc
            ? string.Create(CultureInfo.InvariantCulture, $"tool change position: X{N(tc[0])} Y{N(tc[1])} Z{N(tc[2])}  (P{map.ToolChangePosition}-P{map.ToolChangePosition + 2})\n")
            : "tool change position: none (M06 stops the program where it is)\n");
        return s.ToString();
    }

    /// <summary>The identity (profile id, hash) of the library <see cref="Lines(MachineProfile?)"/> writes for a profile.</summary>
    public static (int ProfileId, int Hash) ExpectedIdentity(MachineProfile? profile = null) =>
        Prog1000Library.IdentityOf(profile ?? MachineProfile.Default, new Prog1000Options { Comments = false });

    /// <summary>Reads the identity the controller's library recorded (0, 0 when it has none).</summary>
    public static async Task<(int ProfileId, int Hash)> ReadIdentityAsync(IPmacConnection connection, LibraryMap? map = null, CancellationToken cancellationToken = default)
    {
        map ??= new LibraryMap();
        var reply = await connection.GetResponseAsync($"P{map.Identity} P{map.Identity + 1}", cancellationToken).ConfigureAwait(false);
        var values = reply.Split(['\r', '\n', ' '], StringSplitOptions.RemoveEmptyEntries)
            .Select(v => double.TryParse(v, System.Globalization.NumberStyles.Float, System.Globalization.CultureInfo.InvariantCulture, out var d) ? (int)Math.Round(d) : 0)
            .ToList();
        return values.Count >= 2 ? (values[0], values[1]) : (0, 0);
    }

    /// <summary>
    /// Before a job's first chunk: makes sure the controller runs the library the program was checked against
    /// (<paramref name="profile"/>). <see cref="LibraryPolicy.Load"/> downloads it and the machine's tables first;
    /// <see cref="LibraryPolicy.Verify"/> refuses a controller with no library or another one; <see cref="LibraryPolicy.Force"/>
    /// only warns.
    /// </summary>
    /// <exception cref="JobException">The controller has no library or another one (Verify, Load), or it is not idle (Load).</exception>
    public static Task EnsureAsync(IPmacConnection connection, MachineProfile? profile, LibraryPolicy policy, CancellationToken cancellationToken = default) =>
        EnsureAsync(connection, profile, policy, LibraryDownloadScope.Default, cancellationToken);

    /// <summary>
    /// <see cref="EnsureAsync(IPmacConnection, MachineProfile?, LibraryPolicy, CancellationToken)"/> on the coordinate
    /// system of <paramref name="scope"/>: <see cref="LibraryPolicy.Load"/> is refused unless it is idle (no program
    /// running, no move in progress; the waiting rotary program of the completed job of the scope counts as idle).
    /// </summary>
    /// <exception cref="JobException">The controller has no library or another one (Verify, Load), or it is not idle (Load).</exception>
    public static async Task EnsureAsync(IPmacConnection connection, MachineProfile? profile, LibraryPolicy policy, LibraryDownloadScope scope, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(scope);
        profile ??= MachineProfile.Default;

        // A host killed mid-download leaves a buffer open on this port (one per port, whatever the connection): the
        // identity query would be stored in it as a program line and read as "no library". CLOSE with none open does
        // nothing.
        await connection.GetResponseAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        if (policy == LibraryPolicy.Load)
        {
            await LibraryDownloadGuard.RefuseUnlessIdleAsync(connection, scope, cancellationToken).ConfigureAwait(false);
            await DownloadTolerantAsync(connection, Lines(profile), cancellationToken).ConfigureAwait(false);
            await DownloadTolerantAsync(connection, TableLines(profile), cancellationToken).ConfigureAwait(false);
        }

        var expected = ExpectedIdentity(profile);
        var found = await ReadIdentityAsync(connection, null, cancellationToken).ConfigureAwait(false);
        if (found == expected)
        {
            Log.Information("{Device:l} runs the library of profile '{Profile:l}' (P7000={Id}, P7001={Hash})", connection.Description, profile.Name, found.ProfileId, found.Hash);
            return;
        }

        var map = new LibraryMap();
        var what = found == (0, 0)
            ? $"the controller has no PmacStream library (P{map.Identity}=0)"
            : $"the controller's library is another one (P{map.Identity}={found.ProfileId}, P{map.Identity + 1}={found.Hash}; profile '{profile.Name}' gives {expected.ProfileId}, {expected.Hash})";
        var message = $"{what}: the program was checked against '{profile.Name}', and on this controller its G and M codes would not do what they say. " +
                      "Load the library with --load-library (or 'pmacstream prog1000' and the controller's own download), or --force to run anyway";
        if (policy == LibraryPolicy.Force)
        {
            Log.Warning("{Message:l} (forced)", what);
            return;
        }

        throw new JobException(message, JobErrorKind.Failed);
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
