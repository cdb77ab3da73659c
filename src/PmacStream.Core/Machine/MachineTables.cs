using System.Globalization;
using System.Text;
using System.Text.Json;

namespace PmacStream.Machine;

/// <summary>One work offset table: X Y Z in millimetres, machine coordinates.</summary>
/// <param name="Name">G54..G59, G59.1..G59.3, G54.1P1..G54.1P48.</param>
/// <param name="Index">The library's table index: 1-6 G54-G59, 7-9 G59.1-G59.3, 10 + n-1 G54.1 Pn.</param>
/// <param name="X">X offset.</param>
/// <param name="Y">Y offset.</param>
/// <param name="Z">Z offset.</param>
public sealed record WorkOffsetEntry(string Name, int Index, double X, double Y, double Z)
{
    /// <summary>The value of axis 0 (X), 1 (Y) or 2 (Z).</summary>
    public double this[int axis] => axis switch { 0 => X, 1 => Y, _ => Z };

    /// <summary>This entry with axis <paramref name="axis"/> set.</summary>
    public WorkOffsetEntry With(int axis, double value) => axis switch { 0 => this with { X = value }, 1 => this with { Y = value }, _ => this with { Z = value } };
}

/// <summary>One tool of the tool table (millimetres): H n reads its length, D n its radius.</summary>
/// <param name="Number">Tool (offset) number, 1-199.</param>
/// <param name="Length">Tool length (geometry).</param>
/// <param name="Radius">Cutter radius (geometry).</param>
/// <param name="LengthWear">Length wear, added to the length.</param>
/// <param name="RadiusWear">Radius wear, added to the radius.</param>
public sealed record ToolEntry(int Number, double Length, double Radius, double LengthWear, double RadiusWear)
{
    /// <summary>The length G43 applies: length plus wear.</summary>
    public double EffectiveLength => Length + LengthWear;

    /// <summary>The radius G41/G42 use: radius plus wear.</summary>
    public double EffectiveRadius => Radius + RadiusWear;
}

/// <summary>The machine's tables: work offsets and tools, as on the controller or in the host's copy.</summary>
/// <param name="Offsets">Every work offset table, G54 first.</param>
/// <param name="Tools">Tools with any value set, by number.</param>
public sealed record MachineTables(IReadOnlyList<WorkOffsetEntry> Offsets, IReadOnlyList<ToolEntry> Tools)
{
    /// <summary>Highest tool (offset) number the library's map holds.</summary>
    public const int MaxTool = 199;

    /// <summary>Largest offset magnitude accepted, mm.</summary>
    public const double MaxOffset = 100_000;

    /// <summary>Largest tool length magnitude accepted, mm.</summary>
    public const double MaxLength = 2_000;

    /// <summary>Largest radius accepted, mm.</summary>
    public const double MaxRadius = 500;

    /// <summary>Largest wear magnitude accepted, mm.</summary>
    public const double MaxWear = 10;

    /// <summary>Every table name in the library's index order (index 1 first).</summary>
    public static IReadOnlyList<string> Names { get; } =
        Enumerable.Range(54, 6).Select(c => "G" + c.ToString(CultureInfo.InvariantCulture))
            .Concat(["G59.1", "G59.2", "G59.3"])
            .Concat(Enumerable.Range(1, 48).Select(n => "G54.1P" + n.ToString(CultureInfo.InvariantCulture)))
            .ToList();

    /// <summary>Empty tables (every offset 0, no tool).</summary>
    public static MachineTables Empty { get; } = new(Names.Select((n, i) => new WorkOffsetEntry(n, i + 1, 0, 0, 0)).ToList(), []);

    /// <summary>
    /// The library index of a table name (<c>G55</c> 2, <c>G59.2</c> 8, <c>G54.1P3</c> or <c>G54.1 P3</c> 12); null when
    /// it names none.
    /// </summary>
    public static int? IndexOf(string name)
    {
        var n = name.Replace(" ", string.Empty, StringComparison.Ordinal).ToUpperInvariant();
        var i = Names.ToList().IndexOf(n);
        return i >= 0 ? i + 1 : null;
    }

    /// <summary>The table name of an index (0 is the external offset, shown as <c>EXT</c>).</summary>
    public static string NameOf(int index) => index >= 1 && index <= Names.Count ? Names[index - 1] : "EXT";

    /// <summary>The offset table <paramref name="name"/>.</summary>
    public WorkOffsetEntry Offset(string name) => Offsets.First(o => o.Name == Names[IndexOf(name)!.Value - 1]);

    /// <summary>The tool <paramref name="number"/> (zeros when it has no entry).</summary>
    public ToolEntry Tool(int number) => Tools.FirstOrDefault(t => t.Number == number) ?? new ToolEntry(number, 0, 0, 0, 0);

    /// <summary>These tables with one offset replaced.</summary>
    public MachineTables With(WorkOffsetEntry offset) => this with { Offsets = Offsets.Select(o => o.Index == offset.Index ? offset : o).ToList() };

    /// <summary>These tables with one tool replaced (a tool of all zeros is dropped).</summary>
    public MachineTables With(ToolEntry tool) => this with
    {
        Tools = Tools.Where(t => t.Number != tool.Number).Concat(tool is { Length: 0, Radius: 0, LengthWear: 0, RadiusWear: 0 } ? [] : [tool]).OrderBy(t => t.Number).ToList(),
    };

    /// <summary>What differs between these tables (the controller's) and <paramref name="other"/> (the host's copy), one line each.</summary>
    public IReadOnlyList<string> Differences(MachineTables other)
    {
        var lines = new List<string>();
        foreach (var o in Offsets)
        {
            var h = other.Offsets.First(x => x.Index == o.Index);
            if (o != h)
            {
                lines.Add(string.Create(CultureInfo.InvariantCulture, $"{o.Name}: controller X{o.X} Y{o.Y} Z{o.Z}, host X{h.X} Y{h.Y} Z{h.Z}"));
            }
        }

        foreach (var n in Tools.Select(t => t.Number).Union(other.Tools.Select(t => t.Number)).Order())
        {
            var (c, h) = (Tool(n), other.Tool(n));
            if (c != h)
            {
                lines.Add(string.Create(CultureInfo.InvariantCulture,
                    $"T{n}: controller length {c.Length} radius {c.Radius} wear {c.LengthWear}/{c.RadiusWear}, host length {h.Length} radius {h.Radius} wear {h.LengthWear}/{h.RadiusWear}"));
            }
        }

        return lines;
    }

    /// <summary>The host's copy as JSON (<c>tables.json</c>).</summary>
    public string ToJson()
    {
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Indented = true }))
        {
            w.WriteStartObject();
            w.WriteStartObject("workOffsets");
            foreach (var o in Offsets.Where(o => o.Index <= 9 || o is not { X: 0, Y: 0, Z: 0 }))
            {
                w.WriteStartArray(o.Name);
                w.WriteNumberValue(o.X);
                w.WriteNumberValue(o.Y);
                w.WriteNumberValue(o.Z);
                w.WriteEndArray();
            }

            w.WriteEndObject();
            w.WriteStartObject("tools");
            foreach (var t in Tools)
            {
                w.WriteStartObject(t.Number.ToString(CultureInfo.InvariantCulture));
                w.WriteNumber("length", t.Length);
                w.WriteNumber("radius", t.Radius);
                w.WriteNumber("lengthWear", t.LengthWear);
                w.WriteNumber("radiusWear", t.RadiusWear);
                w.WriteEndObject();
            }

            w.WriteEndObject();
            w.WriteEndObject();
        }

        return Encoding.UTF8.GetString(buffer.ToArray()) + "\n";
    }

    /// <summary>Reads the host's copy; <see cref="Empty"/> when the file does not exist.</summary>
    /// <exception cref="InvalidDataException">The file is not valid.</exception>
    public static MachineTables Load(string path)
    {
        if (!File.Exists(path))
        {
            return Empty;
        }

        try
        {
            using var doc = JsonDocument.Parse(File.ReadAllBytes(path));
            var tables = Empty;
            if (doc.RootElement.TryGetProperty("workOffsets", out var offsets))
            {
                foreach (var p in offsets.EnumerateObject())
                {
                    var index = IndexOf(p.Name) ?? throw new InvalidDataException($"{path}: workOffsets.{p.Name} is not a work offset (G54-G59, G59.1-G59.3, G54.1P1-P48)");
                    var v = p.Value.EnumerateArray().Select(e => e.GetDouble()).ToArray();
                    tables = v.Length == 3 ? tables.With(new WorkOffsetEntry(Names[index - 1], index, v[0], v[1], v[2])) : throw new InvalidDataException($"{path}: workOffsets.{p.Name}: expected [x, y, z]");
                }
            }

            if (doc.RootElement.TryGetProperty("tools", out var tools))
            {
                foreach (var p in tools.EnumerateObject())
                {
                    double D(string n) => p.Value.TryGetProperty(n, out var e) ? e.GetDouble() : 0;
                    var number = int.TryParse(p.Name, NumberStyles.None, CultureInfo.InvariantCulture, out var t) && t is >= 1 and <= MaxTool
                        ? t : throw new InvalidDataException($"{path}: tools.{p.Name} is not a tool number 1-{MaxTool}");
                    tables = tables.With(new ToolEntry(number, D("length"), D("radius"), D("lengthWear"), D("radiusWear")));
                }
            }

            return tables;
        }
        catch (Exception e) when (e is JsonException or InvalidOperationException or FormatException)
        {
            throw new InvalidDataException($"{path}: not a valid tables file ({e.Message})", e);
        }
    }

    /// <summary>Writes the host's copy (to a temporary file first, so a crash leaves the old one whole).</summary>
    public void Save(string path)
    {
        Directory.CreateDirectory(Path.GetDirectoryName(Path.GetFullPath(path))!);
        var temp = path + ".tmp";
        File.WriteAllText(temp, ToJson(), new UTF8Encoding(false));
        File.Move(temp, path, overwrite: true);
    }

    /// <summary>
    /// The tables file beside the run settings: <c>$PMACSTREAM_TABLES</c>, else <c>tables.json</c> in the settings
    /// file's folder (<c>~/.pmacstream/</c>).
    /// </summary>
    public static string DefaultPath(string? settingsPath = null) =>
        Environment.GetEnvironmentVariable("PMACSTREAM_TABLES") is { Length: > 0 } env
            ? env
            : Path.Combine(Path.GetDirectoryName(Path.GetFullPath(settingsPath ?? Jobs.RunSettingsFile.DefaultPath))!, "tables.json");
}
