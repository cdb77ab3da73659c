using System.Globalization;
using PmacStream.Preparation;

namespace PmacStream.Machine;

/// <summary>The shifts between machine and work coordinates the library holds besides the tables.</summary>
/// <param name="Active">The active work offset (<c>G54</c>).</param>
/// <param name="G52">The local shift (G52) X Y Z.</param>
/// <param name="G92">The G92 shift X Y Z.</param>
/// <param name="External">FANUC's external work offset X Y Z (P7100..).</param>
/// <param name="ToolLength">The tool length applied on Z (G43), and its H.</param>
/// <param name="H">The active H number (0: none).</param>
public sealed record WorkShifts(string Active, double[] G52, double[] G92, double[] External, double ToolLength, int H);

/// <summary>Work offsets and the tool table at the machine: read from and written to the controller's P-variables, kept on the host too.</summary>
public sealed partial class MachineConsole
{
    /// <summary>The tables as the controller holds them (<c>P7100 + 3*index + axis</c>; tools <c>P7300+H</c> etc., see <see cref="LibraryMap"/>).</summary>
    public async Task<MachineTables> ReadTablesAsync(CancellationToken cancellationToken = default)
    {
        var m = Options.Map;
        var count = MachineTables.Names.Count;
        var offsets = await ReadVariablesAsync(Enumerable.Range(m.WorkOffsets + 3, 3 * count), cancellationToken).ConfigureAwait(false);
        var list = MachineTables.Names.Select((n, i) => new WorkOffsetEntry(n, i + 1, offsets[3 * i], offsets[(3 * i) + 1], offsets[(3 * i) + 2])).ToList();
        var n = Math.Clamp(Options.ToolCount, 0, MachineTables.MaxTool);
        var numbers = Enumerable.Range(1, n).ToList();
        var length = await ReadVariablesAsync(numbers.Select(t => m.ToolLengths + t), cancellationToken).ConfigureAwait(false);
        var radius = await ReadVariablesAsync(numbers.Select(t => m.ToolRadii + t), cancellationToken).ConfigureAwait(false);
        var lengthWear = await ReadVariablesAsync(numbers.Select(t => m.ToolLengthWear + t), cancellationToken).ConfigureAwait(false);
        var radiusWear = await ReadVariablesAsync(numbers.Select(t => m.ToolRadiusWear + t), cancellationToken).ConfigureAwait(false);
        var tables = MachineTables.Empty with { Offsets = list };
        for (var i = 0; i < n; i++)
        {
            // P7300+H holds what G43 applies (length plus wear); the geometry is that minus the wear.
            tables = tables.With(new ToolEntry(numbers[i], Round(length[i] - lengthWear[i]), radius[i], lengthWear[i], radiusWear[i]));
        }

        return tables;
    }

    /// <summary>The G52/G92/external shifts and the applied tool length (the library's modal state, Q20..Q28).</summary>
    public async Task<WorkShifts> ReadShiftsAsync(CancellationToken cancellationToken = default)
    {
        var m = Options.Map;
        var q = Numbers(await Connection.GetResponseAsync($"{Cs} {string.Join(' ', Enumerable.Range(0, 9).Select(m.Q))}", cancellationToken).ConfigureAwait(false));
        var ext = await ReadVariablesAsync(Enumerable.Range(m.WorkOffsets, 3), cancellationToken).ConfigureAwait(false);
        double Q(int i) => i < q.Count ? q[i] : 0;
        return new WorkShifts(MachineTables.NameOf(Q(0) >= 1 ? (int)Q(0) : 1), [Q(1), Q(2), Q(3)], [Q(4), Q(5), Q(6)], ext, Q(7), (int)Q(8));
    }

    /// <summary>
    /// Sets a work offset's axes (those given; the others stay) on the controller and in the host's copy. Refused
    /// while a program runs (its positions would move under it) and for a value out of range.
    /// </summary>
    public async Task<ConsoleResult> SetWorkOffsetAsync(string name, double? x, double? y, double? z, CancellationToken cancellationToken = default)
    {
        if (MachineTables.IndexOf(name) is not { } index)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, $"'{name}' is not a work offset: G54-G59, G59.1-G59.3 or G54.1P1-G54.1P48");
        }

        double?[] values = [x, y, z];
        if (values.FirstOrDefault(v => v is { } d && (!double.IsFinite(d) || Math.Abs(d) > MachineTables.MaxOffset)) is { } bad)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, string.Create(CultureInfo.InvariantCulture, $"offset value {bad} is out of range (at most {MachineTables.MaxOffset} mm)"));
        }

        if (await RefuseWhileRunningAsync(cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var at = Options.Map.WorkOffsets + (3 * index);
        var now = await ReadVariablesAsync(Enumerable.Range(at, 3), cancellationToken).ConfigureAwait(false);
        var entry = new WorkOffsetEntry(MachineTables.NameOf(index), index, x ?? now[0], y ?? now[1], z ?? now[2]);
        await Connection.GetResponseAsync($"P{at}={HostConversion.Num(entry.X)} P{at + 1}={HostConversion.Num(entry.Y)} P{at + 2}={HostConversion.Num(entry.Z)}", cancellationToken).ConfigureAwait(false);
        UpdateHost(t => t.With(entry));
        var text = string.Create(CultureInfo.InvariantCulture, $"{entry.Name} X{entry.X} Y{entry.Y} Z{entry.Z}");
        Log.Information("Work offset {Offset:l} set", text);
        return ConsoleResult.Ok(text);
    }

    /// <summary>
    /// Touch-off: sets <paramref name="axis"/> of work offset <paramref name="name"/> so the current position reads
    /// <paramref name="value"/> in it (the other shifts, G52, G92, the external offset and on Z the applied tool length, stay).
    /// </summary>
    public async Task<ConsoleResult> TouchOffAsync(string name, string axis, double value, CancellationToken cancellationToken = default)
    {
        if (Axis(axis) is not { TableAxis: >= 0 } a)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, $"touch-off needs X, Y or Z (got '{axis}')");
        }

        var machine = (await PositionsAsync(cancellationToken).ConfigureAwait(false))[Options.Axes.ToList().IndexOf(a)];
        var s = await ReadShiftsAsync(cancellationToken).ConfigureAwait(false);
        var i = a.TableAxis;
        var offset = Round(machine - value - s.External[i] - s.G52[i] - s.G92[i] - (i == 2 ? s.ToolLength : 0));
        return await SetWorkOffsetAsync(name, i == 0 ? offset : null, i == 1 ? offset : null, i == 2 ? offset : null, cancellationToken).ConfigureAwait(false);
    }

    /// <summary>Sets a tool's values (those given; the others stay) on the controller and in the host's copy.</summary>
    public async Task<ConsoleResult> SetToolAsync(int number, double? length, double? radius, double? lengthWear = null, double? radiusWear = null, CancellationToken cancellationToken = default)
    {
        if (ToolValueError(number, length, radius, lengthWear, radiusWear) is { } error)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, error);
        }

        if (await RefuseWhileRunningAsync(cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var m = Options.Map;
        var now = await ReadVariablesAsync([m.ToolLengths + number, m.ToolRadii + number, m.ToolLengthWear + number, m.ToolRadiusWear + number], cancellationToken).ConfigureAwait(false);
        var tool = new ToolEntry(number, length ?? Round(now[0] - now[2]), radius ?? now[1], lengthWear ?? now[2], radiusWear ?? now[3]);
        await Connection.GetResponseAsync(
            $"P{m.ToolLengths + number}={HostConversion.Num(tool.EffectiveLength)} P{m.ToolRadii + number}={HostConversion.Num(tool.Radius)} P{m.ToolLengthWear + number}={HostConversion.Num(tool.LengthWear)} P{m.ToolRadiusWear + number}={HostConversion.Num(tool.RadiusWear)}",
            cancellationToken).ConfigureAwait(false);
        UpdateHost(t => t.With(tool));
        var text = string.Create(CultureInfo.InvariantCulture, $"T{number} length {tool.Length} radius {tool.Radius} length wear {tool.LengthWear} radius wear {tool.RadiusWear}");
        Log.Information("Tool {Tool:l} set", text);
        return ConsoleResult.Ok(text);
    }

    /// <summary>
    /// Measures a tool's length from a Z touch: the tool's tip stands on a surface at work Z <paramref name="surfaceZ"/>
    /// (with no tool length applied); the length is what G43 must take off for the tip to read that (wear reset to 0).
    /// </summary>
    public async Task<ConsoleResult> MeasureToolLengthAsync(int number, double surfaceZ = 0, CancellationToken cancellationToken = default)
    {
        if (Options.Axes.FirstOrDefault(x => x.TableAxis == 2) is not { } z)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, "the machine has no Z axis");
        }

        var machine = (await PositionsAsync(cancellationToken).ConfigureAwait(false))[Options.Axes.ToList().IndexOf(z)];
        var s = await ReadShiftsAsync(cancellationToken).ConfigureAwait(false);
        var offset = await ReadVariablesAsync([Options.Map.WorkOffsets + (3 * MachineTables.IndexOf(s.Active)!.Value) + 2], cancellationToken).ConfigureAwait(false);
        var length = Round(machine - offset[0] - s.External[2] - s.G52[2] - s.G92[2] - surfaceZ);
        return await SetToolAsync(number, length, null, 0, null, cancellationToken).ConfigureAwait(false);
    }

    /// <summary>The differences between the controller's tables and the host's copy (after a controller power cycle: all of them).</summary>
    public async Task<IReadOnlyList<string>> CompareTablesAsync(CancellationToken cancellationToken = default) =>
        (await ReadTablesAsync(cancellationToken).ConfigureAwait(false)).Differences(HostTables());

    /// <summary>Writes the host's copy of the tables to the controller (restore after a power cycle); refused while a program runs.</summary>
    public async Task<ConsoleResult> RestoreTablesAsync(CancellationToken cancellationToken = default)
    {
        if (await RefuseWhileRunningAsync(cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var host = HostTables();
        var differences = await CompareTablesAsync(cancellationToken).ConfigureAwait(false);
        var m = Options.Map;
        foreach (var o in host.Offsets)
        {
            var at = m.WorkOffsets + (3 * o.Index);
            await Connection.GetResponseAsync($"P{at}={HostConversion.Num(o.X)} P{at + 1}={HostConversion.Num(o.Y)} P{at + 2}={HostConversion.Num(o.Z)}", cancellationToken).ConfigureAwait(false);
        }

        foreach (var n in Enumerable.Range(1, MachineTables.MaxTool).Where(n => n <= Options.ToolCount || host.Tools.Any(t => t.Number == n)))
        {
            var t = host.Tool(n);
            await Connection.GetResponseAsync(
                $"P{m.ToolLengths + n}={HostConversion.Num(t.EffectiveLength)} P{m.ToolRadii + n}={HostConversion.Num(t.Radius)} P{m.ToolLengthWear + n}={HostConversion.Num(t.LengthWear)} P{m.ToolRadiusWear + n}={HostConversion.Num(t.RadiusWear)}",
                cancellationToken).ConfigureAwait(false);
        }

        Log.Information("Tables restored from {Path:l}: {Count} differences written", Options.TablesPath, differences.Count);
        return ConsoleResult.Ok($"restored {differences.Count} difference{(differences.Count == 1 ? string.Empty : "s")} from {Options.TablesPath}");
    }

    /// <summary>The host's copy (empty tables when none is kept).</summary>
    public MachineTables HostTables() => Options.TablesPath is { } path ? MachineTables.Load(path) : MachineTables.Empty;

    private void UpdateHost(Func<MachineTables, MachineTables> change)
    {
        if (Options.TablesPath is { } path)
        {
            change(MachineTables.Load(path)).Save(path);
        }
    }

    private Task<ConsoleResult?> RefuseWhileRunningAsync(CancellationToken cancellationToken) => BusyAsync(cancellationToken);

    private static string? ToolValueError(int number, double? length, double? radius, double? lengthWear, double? radiusWear)
    {
        static bool Out(double? v, double min, double max) => v is { } d && (!double.IsFinite(d) || d < min || d > max);
        return number is < 1 or > MachineTables.MaxTool ? $"tool {number} is out of range (1-{MachineTables.MaxTool})"
            : Out(length, -MachineTables.MaxLength, MachineTables.MaxLength) ? $"--length {length} is out of range (at most {MachineTables.MaxLength} mm)"
            : Out(radius, 0, MachineTables.MaxRadius) ? $"--radius {radius} is out of range (0-{MachineTables.MaxRadius} mm)"
            : Out(lengthWear, -MachineTables.MaxWear, MachineTables.MaxWear) ? $"--length-wear {lengthWear} is out of range (at most {MachineTables.MaxWear} mm)"
            : Out(radiusWear, -MachineTables.MaxWear, MachineTables.MaxWear) ? $"--radius-wear {radiusWear} is out of range (at most {MachineTables.MaxWear} mm)"
            : null;
    }

    /// <summary>Reads P-variables, 24 to a command; a variable the reply leaves out reads 0.</summary>
    private async Task<double[]> ReadVariablesAsync(IEnumerable<int> numbers, CancellationToken cancellationToken)
    {
        var list = numbers.ToList();
        var values = new double[list.Count];
        for (var start = 0; start < list.Count; start += 24)
        {
            var batch = list.Skip(start).Take(24).ToList();
            var reply = Numbers(await Connection.GetResponseAsync(string.Join(' ', batch.Select(n => "P" + n.ToString(CultureInfo.InvariantCulture))), cancellationToken).ConfigureAwait(false));
            for (var i = 0; i < batch.Count && i < reply.Count; i++)
            {
                values[start + i] = reply[i];
            }
        }

        return values;
    }
}
