using System.Text.Json;

namespace PmacStream.GCode;

/// <summary>
/// The machine profile's JSON format (see the GCode README): read by hand from a <see cref="JsonDocument"/> and written
/// with a <see cref="Utf8JsonWriter"/>, so that reading a profile at every CLI start costs no serializer warm-up.
/// </summary>
internal static class ProfileJson
{
    /// <summary>Reads profile JSON into its settings. Throws <see cref="InvalidDataException"/> naming the reason.</summary>
    public static Dto Read(string json, string source)
    {
        try
        {
            using var doc = JsonDocument.Parse(json, new JsonDocumentOptions { CommentHandling = JsonCommentHandling.Skip, AllowTrailingCommas = true });
            if (doc.RootElement.ValueKind != JsonValueKind.Object)
            {
                throw MachineProfile.Bad(source, "expected a JSON object");
            }

            return ReadDto(doc.RootElement, source);
        }
        catch (JsonException e)
        {
            throw MachineProfile.Bad(source, $"not valid JSON at line {(e.LineNumber ?? 0) + 1}: {e.Message}");
        }
    }

    /// <summary>The profile as JSON, in the shape <see cref="Read"/> takes.</summary>
    public static string Write(MachineProfile p)
    {
        using var ms = new MemoryStream();
        using (var w = new Utf8JsonWriter(ms, new JsonWriterOptions { Indented = true, Encoder = System.Text.Encodings.Web.JavaScriptEncoder.UnsafeRelaxedJsonEscaping }))
        {
            w.WriteStartObject();
            w.WriteString("name", p.Name);
            w.WriteString("description", p.Description);
            w.WriteNumber("toolCount", p.ToolCount);
            w.WriteNumber("rapidRate", p.RapidRate);
            if (p.AbsoluteEncoders)
            {
                // Written only when set: the built-in profiles' JSON, and so their library identity, stay as they were.
                w.WriteBoolean("absoluteEncoders", true);
            }

            WriteAxes(w, p);

            p.ArcTolerance.Write(w);
            w.WriteBoolean("dwellPInMilliseconds", p.DwellPInMilliseconds);
            w.WriteBoolean("slashInBlock", p.SlashInBlock);
            w.WriteBoolean("extendedWorkOffsets", p.ExtendedWorkOffsets);
            w.WriteBoolean("externalWorkOffset", p.ExternalWorkOffset);
            if (p.Macros != Expansion.MacroDialect.None)
            {
                w.WriteString("macros", p.Macros == Expansion.MacroDialect.Fanuc ? "fanuc" : "linuxcnc");
            }

            w.WriteString("programTail", p.ProgramTail);
            w.WriteString("startup", p.Startup);
            w.WriteString("letters", p.Letters);
            WritePoints(w, "workOffsets", p.WorkOffsets);
            WritePoints(w, "referencePositions", p.ReferencePositions);
            WriteTools(w, p);
            foreach (var (name, groups) in new[] { ("gGroups", p.GGroups), ("mGroups", p.MGroups) })
            {
                w.WriteStartArray(name);
                foreach (var g in groups)
                {
                    w.WriteStartObject();
                    w.WriteString("name", g.Name);
                    w.WriteString("description", g.Description);
                    w.WriteBoolean("modal", g.Modal);
                    w.WriteEndObject();
                }

                w.WriteEndArray();
            }

            foreach (var (name, list) in new[] { ("gCodes", p.GCodes), ("mCodes", p.MCodes) })
            {
                w.WriteStartArray(name);
                foreach (var c in list)
                {
                    WriteCode(w, c);
                }

                w.WriteEndArray();
            }

            w.WriteEndObject();
        }

        return System.Text.Encoding.UTF8.GetString(ms.ToArray());
    }

    /// <summary>The tool tables and the tool change position, each only when the profile sets it.</summary>
    private static void WriteTools(Utf8JsonWriter w, MachineProfile p)
    {
        if (p.ToolLengths.Count > 0)
        {
            w.WriteStartObject("toolLengths");
            foreach (var (key, v) in p.ToolLengths)
            {
                w.WriteNumber(key, v);
            }

            w.WriteEndObject();
        }

        if (p.ToolRadii.Count > 0)
        {
            w.WriteStartObject("toolRadii");
            foreach (var (key, v) in p.ToolRadii)
            {
                w.WriteNumber(key, v);
            }

            w.WriteEndObject();
        }

        if (p.ToolChangePosition is { } tc)
        {
            w.WriteStartArray("toolChangePosition");
            foreach (var x in tc)
            {
                w.WriteNumberValue(x);
            }

            w.WriteEndArray();
        }
    }

    private static void WriteCode(Utf8JsonWriter w, CodeDefinition c)
    {
        w.WriteStartObject();
        w.WriteString("code", c.Code);
        w.WriteString("group", c.Group);
        w.WriteString("description", c.Description);
        w.WriteString("controller", ControllerName(c.Controller));
        if (c.Words.Length > 0)
        {
            w.WriteString("words", c.Words);
        }

        if (c.Requires.Length > 0)
        {
            w.WriteString("requires", c.Requires);
        }

        if (c.Values.Count > 0)
        {
            w.WriteStartObject("values");
            foreach (var (letter, set) in c.Values)
            {
                w.WriteString(letter.ToString(), set.Text);
            }

            w.WriteEndObject();
        }

        if (c.Routine != null)
        {
            w.WriteString("routine", c.Routine);
        }

        if (c.Stop != ProgramStopKind.None)
        {
            w.WriteString("stop", c.Stop == ProgramStopKind.Optional ? "optional" : "program");
        }

        if (c.Note.Length > 0)
        {
            w.WriteString("note", c.Note);
        }

        w.WriteEndObject();
    }

    private static void WritePoints(Utf8JsonWriter w, string name, IReadOnlyDictionary<string, double[]> points)
    {
        w.WriteStartObject(name);
        foreach (var (key, v) in points)
        {
            w.WriteStartArray(key);
            foreach (var x in v)
            {
                w.WriteNumberValue(x);
            }

            w.WriteEndArray();
        }

        w.WriteEndObject();
    }

    /// <summary>The controller value as the JSON writes it.</summary>
    public static string ControllerName(ControllerSupport c) => c switch
    {
        ControllerSupport.Library => "library",
        ControllerSupport.Host => "host",
        _ => "not-yet",
    };

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
                    case "absoluteencoders": dto.AbsoluteEncoders = v.GetBoolean(); break;
                    case "coordinatesystem": dto.CoordinateSystem = v.GetInt32(); break;
                    case "axes": dto.Axes = ReadAxes(v, source); break;
                    case "arctolerance": dto.ArcTolerance = ArcTolerance.Read(v, source); break;
                    case "dwellpinmilliseconds": dto.DwellPInMilliseconds = v.GetBoolean(); break;
                    case "slashinblock": dto.SlashInBlock = v.GetBoolean(); break;
                    case "extendedworkoffsets": dto.ExtendedWorkOffsets = v.GetBoolean(); break;
                    case "externalworkoffset": dto.ExternalWorkOffset = v.GetBoolean(); break;
                    case "macros": dto.Macros = v.GetString(); break;
                    case "programtail": dto.ProgramTail = v.GetString(); break;
                    case "startup": dto.Startup = v.GetString(); break;
                    case "letters": dto.Letters = v.GetString(); break;
                    case "workoffsets": dto.WorkOffsets = ReadPoints(v); break;
                    case "referencepositions": dto.ReferencePositions = ReadPoints(v); break;
                    case "toollengths": dto.ToolLengths = v.EnumerateObject().ToDictionary(o => o.Name, o => o.Value.GetDouble()); break;
                    case "toolradii": dto.ToolRadii = v.EnumerateObject().ToDictionary(o => o.Name, o => o.Value.GetDouble()); break;
                    case "toolchangeposition": dto.ToolChangePosition = v.EnumerateArray().Select(x => x.GetDouble()).ToArray(); break;
                    case "ggroups": dto.GGroups = ReadGroups(v); break;
                    case "mgroups": dto.MGroups = ReadGroups(v); break;
                    case "gcodes": dto.GCodes = ReadCodes(v, source); break;
                    case "mcodes": dto.MCodes = ReadCodes(v, source); break;
                    default: throw MachineProfile.Bad(source, $"unknown setting '{prop.Name}'");
                }
            }
            catch (Exception e) when (e is InvalidOperationException or FormatException)
            {
                throw MachineProfile.Bad(source, $"'{prop.Name}' has the wrong type: {e.Message}");
            }
        }

        return dto;
    }

    private static Dictionary<string, double[]> ReadPoints(JsonElement v) =>
        v.EnumerateObject().ToDictionary(o => o.Name, o => o.Value.EnumerateArray().Select(x => x.GetDouble()).ToArray());

    private static List<ModalGroup> ReadGroups(JsonElement array) =>
        array.EnumerateArray().Select(e => new ModalGroup(
            Text(e, "name"),
            Text(e, "description"),
            !e.TryGetProperty("modal", out var m) || m.GetBoolean())).ToList();

    private static List<CodeDefinition> ReadCodes(JsonElement array, string source)
    {
        var list = new List<CodeDefinition>();
        foreach (var e in array.EnumerateArray())
        {
            var code = Text(e, "code");
            var controller = Text(e, "controller") switch
            {
                "library" => ControllerSupport.Library,
                "host" => ControllerSupport.Host,
                "not-yet" or "" => ControllerSupport.NotYet,
                var other => throw MachineProfile.Bad(source, $"code '{code}': controller '{other}' is not library, host or not-yet"),
            };

            var stop = Text(e, "stop") switch
            {
                "" => ProgramStopKind.None,
                "program" => ProgramStopKind.Program,
                "optional" => ProgramStopKind.Optional,
                var other => throw MachineProfile.Bad(source, $"code '{code}': stop '{other}' is not program or optional"),
            };

            var values = new Dictionary<char, ValueSet>();
            if (e.TryGetProperty("values", out var vs))
            {
                foreach (var p in vs.EnumerateObject())
                {
                    if (p.Name.Length != 1 || char.ToUpperInvariant(p.Name[0]) is < 'A' or > 'Z')
                    {
                        throw MachineProfile.Bad(source, $"code '{code}': values.{p.Name}: expected an address letter");
                    }

                    try
                    {
                        values[char.ToUpperInvariant(p.Name[0])] = ValueSet.Parse(p.Value.GetString() ?? string.Empty);
                    }
                    catch (FormatException ex)
                    {
                        throw MachineProfile.Bad(source, $"code '{code}': values.{p.Name}: {ex.Message}");
                    }
                }
            }

            list.Add(new CodeDefinition(code, Text(e, "group"), Text(e, "description"))
            {
                Controller = controller,
                Words = Text(e, "words").ToUpperInvariant(),
                Requires = Text(e, "requires").ToUpperInvariant(),
                Values = values,
                Routine = e.TryGetProperty("routine", out var r) ? r.GetString() : null,
                Stop = stop,
                Note = Text(e, "note"),
            });
        }

        return list;
    }

    /// <summary>
    /// The machine's axes and coordinate system, written only when the profile lists axes (as absoluteEncoders): the
    /// built-in profiles (X Y Z on motors 1-3) stay as they were.
    /// </summary>
    private static void WriteAxes(Utf8JsonWriter w, MachineProfile p)
    {
        if (p.Axes.Count == 0)
        {
            return;
        }

        w.WriteNumber("coordinateSystem", p.CoordinateSystem);
        w.WriteStartArray("axes");
        foreach (var a in p.Axes)
        {
            w.WriteStartObject();
            w.WriteString("name", a.Name);
            w.WriteNumber("motor", a.Motor);
            w.WriteNumber("countsPerUnit", a.CountsPerUnit);
            if (a.Rotary)
            {
                w.WriteBoolean("rotary", true);
            }

            w.WriteEndObject();
        }

        w.WriteEndArray();
    }

    /// <summary>The machine's axes: <c>[{"name": "A", "motor": 4, "countsPerUnit": 100, "rotary": true}, ...]</c>.</summary>
    private static List<ProfileAxis> ReadAxes(JsonElement v, string source)
    {
        var list = new List<ProfileAxis>();
        foreach (var e in v.EnumerateArray())
        {
            var name = Text(e, "name").Trim().ToUpperInvariant();
            if (name.Length != 1 || !"XYZABCUVW".Contains(name[0], StringComparison.Ordinal))
            {
                throw MachineProfile.Bad(source, $"axes: '{Text(e, "name")}' is not an axis letter (X Y Z A B C U V W)");
            }

            var motor = e.TryGetProperty("motor", out var m) ? m.GetInt32() : 0;
            var scale = e.TryGetProperty("countsPerUnit", out var c) ? c.GetDouble() : 1;
            if (motor is < 1 or > 32 || !double.IsFinite(scale) || scale <= 0)
            {
                throw MachineProfile.Bad(source, $"axes: {name} needs a motor 1-32 and countsPerUnit > 0");
            }

            if (list.Any(a => a.Name == name || a.Motor == motor))
            {
                throw MachineProfile.Bad(source, $"axes: {name} (motor {motor}) is listed twice");
            }

            list.Add(new ProfileAxis(name, motor, scale, e.TryGetProperty("rotary", out var r) && r.GetBoolean()));
        }

        return list;
    }

    private static string Text(JsonElement e, string name) =>
        e.TryGetProperty(name, out var v) && v.ValueKind == JsonValueKind.String ? v.GetString() ?? string.Empty : string.Empty;

    /// <summary>The settings as read, before validation.</summary>
    internal sealed class Dto
    {
        public string? Name { get; set; }

        public string? Description { get; set; }

        public int? ToolCount { get; set; }

        public double? RapidRate { get; set; }

        public bool? AbsoluteEncoders { get; set; }

        public int? CoordinateSystem { get; set; }

        public List<ProfileAxis>? Axes { get; set; }

        public ArcTolerance? ArcTolerance { get; set; }

        public bool? DwellPInMilliseconds { get; set; }

        public bool? SlashInBlock { get; set; }

        public bool? ExtendedWorkOffsets { get; set; }

        public bool? ExternalWorkOffset { get; set; }

        public string? Macros { get; set; }

        public string? ProgramTail { get; set; }

        public string? Startup { get; set; }

        public string? Letters { get; set; }

        public Dictionary<string, double[]>? WorkOffsets { get; set; }

        public Dictionary<string, double[]>? ReferencePositions { get; set; }

        public Dictionary<string, double>? ToolLengths { get; set; }

        public Dictionary<string, double>? ToolRadii { get; set; }

        public double[]? ToolChangePosition { get; set; }

        public List<ModalGroup>? GGroups { get; set; }

        public List<ModalGroup>? MGroups { get; set; }

        public List<CodeDefinition>? GCodes { get; set; }

        public List<CodeDefinition>? MCodes { get; set; }
    }
}
