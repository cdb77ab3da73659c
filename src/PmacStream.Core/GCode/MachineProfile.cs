using System.Globalization;
using System.Text.Json;

namespace PmacStream.GCode;

/// <summary>One G or M code a machine supports.</summary>
/// <param name="Code">The code as written, e.g. <c>G01</c>, <c>G64.1</c>, <c>M30</c>.</param>
/// <param name="Group">Modal group: <c>GA</c>..<c>GI</c> for G codes, <c>MA</c>..<c>MC</c> for M codes (seed 002).</param>
/// <param name="Description">What the code does, for people.</param>
public sealed record CodeDefinition(string Code, string Group, string Description);

/// <summary>
/// What a machine understands: its G and M codes and their modal groups, tool count, rapid rate and the tail the
/// splitter appends. Loaded from JSON; <see cref="Default"/> is the embedded FANUC-style milling set of seed 002
/// (24 G codes in GA-GI, 7 M codes in MA-MC). Immutable after loading, so one instance can be shared by threads.
/// </summary>
public sealed class MachineProfile
{
    /// <summary>Names of the nine G groups, in store column order.</summary>
    public static readonly IReadOnlyList<string> GGroupNames = ["GA", "GB", "GC", "GD", "GE", "GF", "GG", "GH", "GI"];

    /// <summary>Names of the three M groups, in store column order.</summary>
    public static readonly IReadOnlyList<string> MGroupNames = ["MA", "MB", "MC"];

    private static readonly Lazy<MachineProfile> DefaultProfile = new(() => LoadEmbedded("default-mill.json"));

    private readonly Dictionary<int, (CodeDefinition Def, int Group)> _g = new();
    private readonly Dictionary<int, (CodeDefinition Def, int Group)> _m = new();
    private readonly bool[] _letters = new bool[26];
    private readonly Dictionary<int, Point3> _offsets = new();

    private MachineProfile(Dto dto, string source)
    {
        Name = string.IsNullOrWhiteSpace(dto.Name) ? Path.GetFileNameWithoutExtension(source) : dto.Name;
        Description = dto.Description ?? string.Empty;
        ToolCount = dto.ToolCount ?? 24;
        RapidRate = dto.RapidRate ?? 15000;
        ArcTolerance = dto.ArcTolerance ?? 0.002;
        DwellPInMilliseconds = dto.DwellPInMilliseconds ?? true;
        ProgramTail = dto.ProgramTail ?? "M05";
        Startup = dto.Startup ?? "G00 G21 G90 G54 G17 G49 G40 M05 M09";
        Letters = (dto.Letters ?? "NOGMXYZIJKRFSTHDP").ToUpperInvariant();
        WorkOffsets = dto.WorkOffsets ?? new Dictionary<string, double[]>();

        if (ToolCount < 0)
        {
            throw Bad(source, "toolCount must be 0 or more");
        }

        if (RapidRate <= 0 || ArcTolerance <= 0)
        {
            throw Bad(source, "rapidRate and arcTolerance must be greater than 0");
        }

        foreach (var c in Letters)
        {
            if (c is < 'A' or > 'Z')
            {
                throw Bad(source, $"letters: '{c}' is not an address letter A-Z");
            }

            _letters[c - 'A'] = true;
        }

        foreach (var (key, value) in WorkOffsets)
        {
            if (value is not { Length: 3 })
            {
                throw Bad(source, $"workOffsets.{key}: expected [x, y, z]");
            }

            if (key.Length < 2 || char.ToUpperInvariant(key[0]) != 'G' || !int.TryParse(key.AsSpan(1), NumberStyles.None, CultureInfo.InvariantCulture, out var code))
            {
                throw Bad(source, $"workOffsets.{key}: expected a work offset code such as G54");
            }

            _offsets[code] = new Point3(value[0], value[1], value[2]);
        }

        AddCodes(dto.GCodes, 'G', GGroupNames, _g, source);
        AddCodes(dto.MCodes, 'M', MGroupNames, _m, source);
        GCodes = dto.GCodes ?? [];
        MCodes = dto.MCodes ?? [];
    }

    /// <summary>The embedded default profile (seed 002 FANUC-style milling set).</summary>
    public static MachineProfile Default => DefaultProfile.Value;

    /// <summary>Short name.</summary>
    public string Name { get; }

    /// <summary>What this profile describes.</summary>
    public string Description { get; }

    /// <summary>Tools in the magazine; a T word above this is an error.</summary>
    public int ToolCount { get; }

    /// <summary>Rapid traverse rate in millimetres per minute, for move-time estimates of G00.</summary>
    public double RapidRate { get; }

    /// <summary>Largest difference (program units) between an arc's start and end radius that is still accepted.</summary>
    public double ArcTolerance { get; }

    /// <summary>FANUC reads <c>G04 P</c> in milliseconds; false means seconds (LinuxCNC).</summary>
    public bool DwellPInMilliseconds { get; }

    /// <summary>Code the splitter appends after the last chunk (seed 000's machine used <c>M03 M05</c>).</summary>
    public string ProgramTail { get; }

    /// <summary>The modal codes in force at power-on, e.g. <c>G00 G21 G90 G54 G17 G49 G40 M05 M09</c>.</summary>
    public string Startup { get; }

    /// <summary>Address letters the machine accepts (others are errors).</summary>
    public string Letters { get; }

    /// <summary>Work offsets by code (<c>G54</c>..<c>G59</c>) as [x, y, z]; missing ones are zero.</summary>
    public IReadOnlyDictionary<string, double[]> WorkOffsets { get; }

    /// <summary>The supported G codes.</summary>
    public IReadOnlyList<CodeDefinition> GCodes { get; }

    /// <summary>The supported M codes.</summary>
    public IReadOnlyList<CodeDefinition> MCodes { get; }

    /// <summary>Loads a profile from a JSON file. Throws <see cref="InvalidDataException"/> with the reason when it is not valid.</summary>
    public static MachineProfile Load(string path) => Parse(File.ReadAllText(path), path);

    /// <summary>Parses profile JSON. Throws <see cref="InvalidDataException"/> with the reason when it is not valid.</summary>
    public static MachineProfile Parse(string json, string source = "profile")
    {
        // JsonDocument and a hand mapping rather than the reflection serializer: the profile is read at every
        // start of the CLI, and warming up the serializer cost more than checking a 3,000-line program.
        Dto dto;
        try
        {
            using var doc = JsonDocument.Parse(json, new JsonDocumentOptions { CommentHandling = JsonCommentHandling.Skip, AllowTrailingCommas = true });
            if (doc.RootElement.ValueKind != JsonValueKind.Object)
            {
                throw Bad(source, "expected a JSON object");
            }

            dto = ReadDto(doc.RootElement, source);
        }
        catch (JsonException e)
        {
            throw Bad(source, $"not valid JSON at line {(e.LineNumber ?? 0) + 1}: {e.Message}");
        }

        return new MachineProfile(dto, source);
    }

    /// <summary>The profile as JSON (the same shape <see cref="Parse"/> reads).</summary>
    public string ToJson()
    {
        using var ms = new MemoryStream();
        using (var w = new Utf8JsonWriter(ms, new JsonWriterOptions { Indented = true, Encoder = System.Text.Encodings.Web.JavaScriptEncoder.UnsafeRelaxedJsonEscaping }))
        {
            w.WriteStartObject();
            w.WriteString("name", Name);
            w.WriteString("description", Description);
            w.WriteNumber("toolCount", ToolCount);
            w.WriteNumber("rapidRate", RapidRate);
            w.WriteNumber("arcTolerance", ArcTolerance);
            w.WriteBoolean("dwellPInMilliseconds", DwellPInMilliseconds);
            w.WriteString("programTail", ProgramTail);
            w.WriteString("startup", Startup);
            w.WriteString("letters", Letters);
            w.WriteStartObject("workOffsets");
            foreach (var (key, v) in WorkOffsets)
            {
                w.WriteStartArray(key);
                foreach (var x in v)
                {
                    w.WriteNumberValue(x);
                }

                w.WriteEndArray();
            }

            w.WriteEndObject();
            foreach (var (name, list) in new[] { ("gCodes", GCodes), ("mCodes", MCodes) })
            {
                w.WriteStartArray(name);
                foreach (var c in list)
                {
                    w.WriteStartObject();
                    w.WriteString("code", c.Code);
                    w.WriteString("group", c.Group);
                    w.WriteString("description", c.Description);
                    w.WriteEndObject();
                }

                w.WriteEndArray();
            }

            w.WriteEndObject();
        }

        return System.Text.Encoding.UTF8.GetString(ms.ToArray());
    }

    private static Dto ReadDto(JsonElement root, string source)
    {
        var dto = new Dto();
        foreach (var prop in root.EnumerateObject())
        {
            var v = prop.Value;
            try
            {
                switch (prop.Name.ToLowerInvariant())
                {
                    case "name": dto.Name = v.GetString(); break;
                    case "description": dto.Description = v.GetString(); break;
                    case "toolcount": dto.ToolCount = v.GetInt32(); break;
                    case "rapidrate": dto.RapidRate = v.GetDouble(); break;
                    case "arctolerance": dto.ArcTolerance = v.GetDouble(); break;
                    case "dwellpinmilliseconds": dto.DwellPInMilliseconds = v.GetBoolean(); break;
                    case "programtail": dto.ProgramTail = v.GetString(); break;
                    case "startup": dto.Startup = v.GetString(); break;
                    case "letters": dto.Letters = v.GetString(); break;
                    case "workoffsets":
                        dto.WorkOffsets = v.EnumerateObject().ToDictionary(o => o.Name, o => o.Value.EnumerateArray().Select(x => x.GetDouble()).ToArray());
                        break;
                    case "gcodes": dto.GCodes = ReadCodes(v); break;
                    case "mcodes": dto.MCodes = ReadCodes(v); break;
                    default: throw Bad(source, $"unknown setting '{prop.Name}'");
                }
            }
            catch (Exception e) when (e is InvalidOperationException or FormatException)
            {
                throw Bad(source, $"'{prop.Name}' has the wrong type: {e.Message}");
            }
        }

        return dto;
    }

    private static List<CodeDefinition> ReadCodes(JsonElement array) =>
        array.EnumerateArray().Select(e => new CodeDefinition(
            e.TryGetProperty("code", out var c) ? c.GetString() ?? string.Empty : string.Empty,
            e.TryGetProperty("group", out var g) ? g.GetString() ?? string.Empty : string.Empty,
            e.TryGetProperty("description", out var d) ? d.GetString() ?? string.Empty : string.Empty)).ToList();

    /// <summary>Looks up a G code by its number (1, 64.1). Returns the group index 0..8 (GA..GI) or -1 when unknown.</summary>
    public int GGroupOf(double number) => _g.TryGetValue(Key(number), out var e) ? e.Group : -1;

    /// <summary>Looks up an M code by its number. Returns the group index 0..2 (MA..MC) or -1 when unknown.</summary>
    public int MGroupOf(double number) => _m.TryGetValue(Key(number), out var e) ? e.Group : -1;

    /// <summary>True when the profile knows some G (or M) code with this integer part and a decimal (G64.1).</summary>
    public bool HasDecimalVariant(char letter, double number)
    {
        var whole = (int)Math.Floor(number) * 10;
        var table = letter == 'M' ? _m : _g;
        foreach (var k in table.Keys)
        {
            if (k / 10 * 10 == whole && k % 10 != 0)
            {
                return true;
            }
        }

        return false;
    }

    /// <summary>True when the address letter is accepted by this machine.</summary>
    public bool AcceptsLetter(char letter) => letter is >= 'A' and <= 'Z' && _letters[letter - 'A'];

    /// <summary>The work offset of G54..G59 (zero when the profile does not set it).</summary>
    public Point3 WorkOffset(int code) => _offsets.TryGetValue(code, out var v) ? v : default;

    internal static int Key(double number) => (int)Math.Round(number * 10.0);

    private static void AddCodes(List<CodeDefinition>? codes, char letter, IReadOnlyList<string> groups,
        Dictionary<int, (CodeDefinition, int)> table, string source)
    {
        foreach (var def in codes ?? [])
        {
            var text = def.Code?.Trim() ?? string.Empty;
            if (text.Length < 2 || char.ToUpperInvariant(text[0]) != letter ||
                !double.TryParse(text.AsSpan(1), NumberStyles.AllowDecimalPoint, CultureInfo.InvariantCulture, out var number))
            {
                throw Bad(source, $"code '{def.Code}': expected {letter} followed by a number, e.g. {letter}01");
            }

            var group = -1;
            for (var i = 0; i < groups.Count; i++)
            {
                if (string.Equals(groups[i], def.Group, StringComparison.OrdinalIgnoreCase))
                {
                    group = i;
                }
            }

            if (group < 0)
            {
                throw Bad(source, $"code '{def.Code}': group '{def.Group}' is not one of {string.Join(", ", groups)}");
            }

            if (!table.TryAdd(Key(number), (def, group)))
            {
                throw Bad(source, $"code '{def.Code}' is listed twice");
            }
        }
    }

    private static MachineProfile LoadEmbedded(string name)
    {
        var asm = typeof(MachineProfile).Assembly;
        using var s = asm.GetManifestResourceStream("PmacStream.GCode.Profiles." + name)
            ?? throw new InvalidOperationException($"embedded profile {name} is missing from {asm.GetName().Name}");
        using var r = new StreamReader(s);
        return Parse(r.ReadToEnd(), name);
    }

    private static InvalidDataException Bad(string source, string why) => new($"{source}: invalid machine profile: {why}");

    private sealed class Dto
    {
        public string? Name { get; set; }

        public string? Description { get; set; }

        public int? ToolCount { get; set; }

        public double? RapidRate { get; set; }

        public double? ArcTolerance { get; set; }

        public bool? DwellPInMilliseconds { get; set; }

        public string? ProgramTail { get; set; }

        public string? Startup { get; set; }

        public string? Letters { get; set; }

        public Dictionary<string, double[]>? WorkOffsets { get; set; }

        public List<CodeDefinition>? GCodes { get; set; }

        public List<CodeDefinition>? MCodes { get; set; }
    }
}
