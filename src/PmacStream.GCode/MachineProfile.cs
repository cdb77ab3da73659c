using System.Globalization;

namespace PmacStream.GCode;

/// <summary>
/// What a machine understands: its G and M codes in any number of modal groups, what runs each code on the
/// controller, the words each code reads, the dialect's facts (G04 P units, block skip inside a block), tool count,
/// rapid rate and the tail the splitter appends. Loaded from JSON (<see cref="ProfileJson"/>); four are built in
/// (<see cref="BuiltInNames"/>), <see cref="Default"/> is <c>fanuc-mill</c>. Immutable after loading, so one
/// instance can be shared by threads.
/// </summary>
public sealed class MachineProfile
{
    /// <summary>The store's columns for the first nine G groups (GA-GI), in order.</summary>
    public static readonly IReadOnlyList<string> GGroupNames = ["GA", "GB", "GC", "GD", "GE", "GF", "GG", "GH", "GI"];

    /// <summary>The store's columns for the first three M groups (MA-MC), in order.</summary>
    public static readonly IReadOnlyList<string> MGroupNames = ["MA", "MB", "MC"];

    /// <summary>The built-in profiles, default first.</summary>
    public static readonly IReadOnlyList<string> BuiltInNames = ["fanuc-mill", "linuxcnc-mill", "grbl", "paper-24g7m"];

    /// <summary>Most G (and most M) modal groups a profile may have (FANUC has about 25).</summary>
    public const int MaxGroups = 64;

    /// <summary>The name of the default profile.</summary>
    public const string DefaultName = "fanuc-mill";

    private static readonly Dictionary<string, Lazy<MachineProfile>> BuiltIns =
        BuiltInNames.ToDictionary(n => n, n => new Lazy<MachineProfile>(() => LoadEmbedded(n + ".json")), StringComparer.OrdinalIgnoreCase);

    private readonly Dictionary<int, (CodeDefinition Def, int Group)> _g = new();
    private readonly Dictionary<int, (CodeDefinition Def, int Group)> _m = new();
    private readonly bool[] _letters = new bool[26];
    private readonly Dictionary<int, Point3> _offsets = new();
    private readonly Dictionary<int, Point3> _references = new();
    private string? _identity;
    private readonly Dictionary<int, double> _toolLengths = new();
    private readonly Dictionary<int, double> _toolRadii = new();

    internal MachineProfile(ProfileJson.Dto dto, string source)
    {
        Name = string.IsNullOrWhiteSpace(dto.Name) ? Path.GetFileNameWithoutExtension(source) : dto.Name;
        Source = source;
        Description = dto.Description ?? string.Empty;
        ToolCount = dto.ToolCount ?? 24;
        RapidRate = dto.RapidRate ?? 15000;
        AbsoluteEncoders = dto.AbsoluteEncoders ?? false;
        Axes = dto.Axes ?? [];
        CoordinateSystem = dto.CoordinateSystem ?? 1;
        if (CoordinateSystem is < 1 or > 16)
        {
            throw Bad(source, $"coordinateSystem: {CoordinateSystem} is not 1-16");
        }
        ArcTolerance = dto.ArcTolerance ?? ArcTolerance.LinuxCnc;
        DwellPInMilliseconds = dto.DwellPInMilliseconds ?? true;
        SlashInBlock = dto.SlashInBlock ?? false;
        ExtendedWorkOffsets = dto.ExtendedWorkOffsets ?? false;
        ExternalWorkOffset = dto.ExternalWorkOffset ?? false;
        Macros = MacroDialectOf(dto.Macros, source);
        ProgramTail = dto.ProgramTail ?? "M05";
        Startup = dto.Startup ?? "G00 G21 G90 G54 G17 G49 G40 M05 M09";
        Letters = (dto.Letters ?? "NOGMXYZIJKRFSTHDP").ToUpperInvariant();
        WorkOffsets = dto.WorkOffsets ?? new Dictionary<string, double[]>();
        ReferencePositions = dto.ReferencePositions ?? new Dictionary<string, double[]>();
        ToolLengths = dto.ToolLengths ?? new Dictionary<string, double>();
        ToolRadii = dto.ToolRadii ?? new Dictionary<string, double>();
        ToolChangePosition = dto.ToolChangePosition;
        if (ToolChangePosition is { Length: not 3 })
        {
            throw Bad(source, "toolChangePosition: expected [x, y, z]");
        }

        ReadToolTables(source);
        CheckRatesAndLetters(source);
        ReadPoints(WorkOffsets, "workOffsets", _offsets, source);
        ReadPoints(ReferencePositions, "referencePositions", _references, source);
        GCodes = dto.GCodes ?? [];
        MCodes = dto.MCodes ?? [];
        GGroups = Groups(dto.GGroups, GCodes, 'G', source);
        MGroups = Groups(dto.MGroups, MCodes, 'M', source);
        if (GGroups.Count > MaxGroups || MGroups.Count > MaxGroups)
        {
            throw Bad(source, $"more than {MaxGroups} G or M modal groups");
        }

        AddCodes(GCodes, 'G', GGroups, _g, source);
        AddCodes(MCodes, 'M', MGroups, _m, source);
    }

    /// <summary>The macro dialect the profile names (<c>macros</c>).</summary>
    private static Expansion.MacroDialect MacroDialectOf(string? macros, string source) => macros?.Trim().ToLowerInvariant() switch
    {
        null or "" or "none" => Expansion.MacroDialect.None,
        "fanuc" => Expansion.MacroDialect.Fanuc,
        "linuxcnc" => Expansion.MacroDialect.LinuxCnc,
        var other => throw Bad(source, $"macros: '{other}' is not fanuc, linuxcnc or none"),
    };

    /// <summary>The tool table: lengths by H number, radii by D number, each key a number.</summary>
    private void ReadToolTables(string source)
    {
        foreach (var (key, value) in ToolLengths)
        {
            if (!int.TryParse(key, NumberStyles.None, CultureInfo.InvariantCulture, out var h))
            {
                throw Bad(source, $"toolLengths.{key}: expected a tool length offset number (H)");
            }

            _toolLengths[h] = value;
        }

        foreach (var (key, value) in ToolRadii)
        {
            if (!int.TryParse(key, NumberStyles.None, CultureInfo.InvariantCulture, out var d) || value < 0)
            {
                throw Bad(source, $"toolRadii.{key}: expected a cutter radius offset number (D) and a radius of 0 or more");
            }

            _toolRadii[d] = value;
        }
    }

    /// <summary>The tool count, the rapid rate and the address letters the profile accepts.</summary>
    private void CheckRatesAndLetters(string source)
    {
        if (ToolCount < 0)
        {
            throw Bad(source, "toolCount must be 0 or more");
        }

        if (RapidRate <= 0)
        {
            throw Bad(source, "rapidRate must be greater than 0");
        }

        foreach (var c in Letters)
        {
            if (c is < 'A' or > 'Z')
            {
                throw Bad(source, $"letters: '{c}' is not an address letter A-Z");
            }

            _letters[c - 'A'] = true;
        }
    }

    /// <summary>Tool length offsets by H number, in millimetres (the machine's tool table; G43 H applies them).</summary>
    public IReadOnlyDictionary<string, double> ToolLengths { get; }

    /// <summary>
    /// Cutter radii by D number, in millimetres (FANUC's radius offsets; under RS274/NGC the tool table radius by tool
    /// number). G41/G42 take the radius from here; a D not listed has no radius and is refused at the check.
    /// </summary>
    public IReadOnlyDictionary<string, double> ToolRadii { get; }

    /// <summary>Where M06's default hook moves the tool to (machine coordinates), null when the machine has none.</summary>
    public double[]? ToolChangePosition { get; }

    /// <summary>The default profile: <c>fanuc-mill</c>, what FANUC/Haas-style milling posts write.</summary>
    public static MachineProfile Default => BuiltIns[DefaultName].Value;

    /// <summary>The checking paper's 24 G and 7 M codes in GA-GI / MA-MC, unchanged (<c>paper-24g7m</c>).</summary>
    public static MachineProfile Paper => BuiltIns["paper-24g7m"].Value;

    /// <summary>Short name.</summary>
    public string Name { get; }

    /// <summary>
    /// Where the profile came from, as <c>--profile</c> takes it again: the name of a built-in profile, the full path of
    /// a profile file (a job record keeps it, so a resume reads the same one), or the label given to <see cref="Parse"/>.
    /// </summary>
    public string Source { get; private set; }

    /// <summary>
    /// The name and the start of the SHA-256 of the profile's JSON (<c>fanuc-mill@1a2b3c4d5e6f7a8b</c>): two profiles of one
    /// name but other codes differ. A split records the identity it was checked under, a job the one it ran under.
    /// </summary>
    public string Identity => _identity ??= $"{Name}@{Convert.ToHexStringLower(System.Security.Cryptography.SHA256.HashData(System.Text.Encoding.UTF8.GetBytes(ToJson())).AsSpan(0, 8))}";

    /// <summary>What this profile describes.</summary>
    public string Description { get; }

    /// <summary>Highest tool number; a T word above it is an error.</summary>
    public int ToolCount { get; }

    /// <summary>Rapid traverse rate in millimetres per minute, for move-time estimates of G00.</summary>
    public double RapidRate { get; }

    /// <summary>
    /// The machine's encoders are absolute (<c>"absoluteEncoders": true</c>): its position is known at power-on, so a
    /// job may start without homing. False (the default): incremental encoders, home first.
    /// </summary>
    public bool AbsoluteEncoders { get; }

    /// <summary>
    /// The machine's axes and the motors that drive them (<c>"axes"</c>), for the operator's console (DRO, home, jog);
    /// empty (the built-in profiles): X, Y, Z on motors 1-3 at one count per millimetre.
    /// </summary>
    public IReadOnlyList<ProfileAxis> Axes { get; }

    /// <summary>The coordinate system the axes are in (<c>"coordinateSystem"</c>, 1 when not set).</summary>
    public int CoordinateSystem { get; }

    /// <summary>How far an arc's end may be off its circle, in the program's units (LinuxCNC's rule unless the profile says otherwise).</summary>
    public ArcTolerance ArcTolerance { get; }

    /// <summary>FANUC reads <c>G04 P</c> in milliseconds; false means seconds (LinuxCNC, grbl).</summary>
    public bool DwellPInMilliseconds { get; }

    /// <summary>
    /// FANUC's optional block skip inside a block: a <c>/</c> after the first word skips the rest of the block when
    /// block delete is on. False (LinuxCNC, grbl): <c>/</c> is block delete only at the start of a line.
    /// </summary>
    public bool SlashInBlock { get; }

    /// <summary>
    /// FANUC's extended work offsets: <c>G54.1 P</c> selects one and <c>G10 L20 P</c> sets one. False (LinuxCNC, grbl):
    /// <c>G10 L20 P</c> sets work offset P so that the current position reads as the values given.
    /// </summary>
    public bool ExtendedWorkOffsets { get; }

    /// <summary>
    /// FANUC's external work offset: <c>G10 L2 P0</c> sets an offset added to every work coordinate system. False
    /// (LinuxCNC, grbl): <c>G10 L2 P0</c> sets the work offset selected now.
    /// </summary>
    public bool ExternalWorkOffset { get; }

    /// <summary>
    /// The subprogram and macro language the host expands before checking and splitting (FANUC/Haas subprograms and
    /// Custom Macro B, or LinuxCNC o-words; <c>GCode/Expansion</c>); None: such lines are errors, as before.
    /// </summary>
    public Expansion.MacroDialect Macros { get; }

    /// <summary>Code the splitter appends after the last chunk (some machines want <c>M03 M05</c>).</summary>
    public string ProgramTail { get; }

    /// <summary>The modal codes in force at power-on, e.g. <c>G00 G21 G90 G54 G17 G49 G40 M05 M09</c>.</summary>
    public string Startup { get; }

    /// <summary>Address letters the machine accepts (others are errors); which code reads which is per code.</summary>
    public string Letters { get; }

    /// <summary>Work offsets by code (<c>G54</c>..<c>G59</c>) as [x, y, z]; missing ones are zero.</summary>
    public IReadOnlyDictionary<string, double[]> WorkOffsets { get; }

    /// <summary>Where <c>G28</c> and <c>G30</c> send the axes (machine coordinates) as [x, y, z]; missing ones are zero.</summary>
    public IReadOnlyDictionary<string, double[]> ReferencePositions { get; }

    /// <summary>The G modal groups in profile order (the first nine are the store's GA-GI columns).</summary>
    public IReadOnlyList<ModalGroup> GGroups { get; }

    /// <summary>The M modal groups in profile order (the first three are the store's MA-MC columns).</summary>
    public IReadOnlyList<ModalGroup> MGroups { get; }

    /// <summary>The supported G codes.</summary>
    public IReadOnlyList<CodeDefinition> GCodes { get; }

    /// <summary>The supported M codes.</summary>
    public IReadOnlyList<CodeDefinition> MCodes { get; }

    /// <summary>True when the machine takes O program numbers (W001 is only reported then).</summary>
    public bool TakesProgramNumbers => AcceptsLetter('O');

    /// <summary>A built-in profile by name (<see cref="BuiltInNames"/>), or null.</summary>
    public static MachineProfile? Named(string name) => BuiltIns.TryGetValue(name.Trim(), out var p) ? p.Value : null;

    /// <summary>
    /// A built-in profile by name, else a profile file: what <c>--profile NAME|FILE</c> takes; null gives the default.
    /// Throws <see cref="InvalidDataException"/> (invalid file, or neither a name nor a file) or an I/O exception.
    /// </summary>
    public static MachineProfile Resolve(string? nameOrPath)
    {
        if (string.IsNullOrWhiteSpace(nameOrPath))
        {
            return Default;
        }

        if (Named(nameOrPath) is { } builtIn)
        {
            return builtIn;
        }

        if (!File.Exists(nameOrPath))
        {
            throw new InvalidDataException(
                $"{nameOrPath}: not a built-in profile ({string.Join(", ", BuiltInNames)}) and no such file");
        }

        return Load(nameOrPath);
    }

    /// <summary>Loads a profile from a JSON file. Throws <see cref="InvalidDataException"/> with the reason when it is not valid.</summary>
    public static MachineProfile Load(string path)
    {
        var profile = Parse(File.ReadAllText(path), path);
        profile.Source = Path.GetFullPath(path);
        return profile;
    }

    /// <summary>Parses profile JSON. Throws <see cref="InvalidDataException"/> with the reason when it is not valid.</summary>
    public static MachineProfile Parse(string json, string source = "profile") => new(ProfileJson.Read(json, source), source);

    /// <summary>The profile as JSON (the same shape <see cref="Parse"/> reads).</summary>
    public string ToJson() => ProfileJson.Write(this);

    /// <summary>Looks up a G code by its number (1, 64.1). Returns its group's index in <see cref="GGroups"/>, or -1 when unknown.</summary>
    public int GGroupOf(double number) => _g.TryGetValue(Key(number), out var e) ? e.Group : -1;

    /// <summary>Looks up an M code by its number. Returns its group's index in <see cref="MGroups"/>, or -1 when unknown.</summary>
    public int MGroupOf(double number) => _m.TryGetValue(Key(number), out var e) ? e.Group : -1;

    /// <summary>The definition of a G or M code, or null when the profile does not know it.</summary>
    public CodeDefinition? Find(char letter, double number) =>
        (char.ToUpperInvariant(letter) == 'M' ? _m : _g).TryGetValue(Key(number), out var e) ? e.Def : null;

    /// <summary>Looks up a code by its key (number x 10): definition and group index, or false.</summary>
    internal bool TryGet(char letter, int key, out CodeDefinition definition, out int group)
    {
        if ((letter == 'M' ? _m : _g).TryGetValue(key, out var e))
        {
            (definition, group) = e;
            return true;
        }

        (definition, group) = (null!, -1);
        return false;
    }

    /// <summary>True when the address letter is accepted by this machine.</summary>
    public bool AcceptsLetter(char letter) => letter is >= 'A' and <= 'Z' && _letters[letter - 'A'];

    /// <summary>The work offset of G54..G59 (zero when the profile does not set it).</summary>
    public Point3 WorkOffset(int code) => _offsets.TryGetValue(code, out var v) ? v : default;

    /// <summary>Where G28 (<paramref name="code"/> 28) or G30 (30) sends the axes, in machine coordinates (zero when not set).</summary>
    public Point3 ReferencePosition(int code) => _references.TryGetValue(code, out var v) ? v : default;

    /// <summary>Tool length offset <paramref name="h"/> from the profile's tool table (0 when not listed).</summary>
    public double ToolLength(int h) => _toolLengths.TryGetValue(h, out var v) ? v : 0;

    /// <summary>Cutter radius <paramref name="d"/> from the profile's table, null when it is not listed.</summary>
    public double? ToolRadius(int d) => _toolRadii.TryGetValue(d, out var v) ? v : null;

    internal static int Key(double number) => (int)Math.Round(number * 10.0);

    private static void ReadPoints(IReadOnlyDictionary<string, double[]> points, string setting, Dictionary<int, Point3> into, string source)
    {
        foreach (var (key, value) in points)
        {
            if (value is not { Length: 3 })
            {
                throw Bad(source, $"{setting}.{key}: expected [x, y, z]");
            }

            if (key.Length < 2 || char.ToUpperInvariant(key[0]) != 'G' || !int.TryParse(key.AsSpan(1), NumberStyles.None, CultureInfo.InvariantCulture, out var code))
            {
                throw Bad(source, $"{setting}.{key}: expected a code such as G54");
            }

            into[code] = new Point3(value[0], value[1], value[2]);
        }
    }

    private static List<ModalGroup> Groups(List<ModalGroup>? declared, IReadOnlyList<CodeDefinition> codes, char letter, string source)
    {
        if (declared != null)
        {
            var names = new HashSet<string>(StringComparer.OrdinalIgnoreCase);
            foreach (var g in declared)
            {
                if (string.IsNullOrWhiteSpace(g.Name) || !names.Add(g.Name))
                {
                    throw Bad(source, $"{char.ToLowerInvariant(letter)}Groups: group '{g.Name}' is unnamed or listed twice");
                }
            }

            return declared;
        }

        // A profile without group declarations (the format before named groups): its groups in order of first use,
        // non-modal when every code in it acts only in its own block.
        var groups = new List<ModalGroup>();
        var standard = letter == 'M' ? MGroupNames : GGroupNames;
        var ordered = codes.All(c => standard.Contains(c.Group, StringComparer.OrdinalIgnoreCase))
            ? codes.OrderBy(c => standard.ToList().IndexOf(c.Group.ToUpperInvariant())).ToList() // GA..GI names keep their column order
            : codes.ToList();
        foreach (var c in ordered)
        {
            if (!groups.Exists(g => string.Equals(g.Name, c.Group, StringComparison.OrdinalIgnoreCase)))
            {
                var members = codes.Where(o => string.Equals(o.Group, c.Group, StringComparison.OrdinalIgnoreCase)).ToList();
                var modal = !members.TrueForAll(o => TryKey(o.Code, letter, out var key) && CodeRoles.ActsOnlyInItsBlock(letter, key));
                groups.Add(new ModalGroup(c.Group, string.Empty, modal));
            }
        }

        return groups;
    }

    private static bool TryKey(string code, char letter, out int key)
    {
        var text = code.Trim();
        key = 0;
        if (text.Length < 2 || char.ToUpperInvariant(text[0]) != letter ||
            !double.TryParse(text.AsSpan(1), NumberStyles.AllowDecimalPoint, CultureInfo.InvariantCulture, out var number))
        {
            return false;
        }

        key = Key(number);
        return true;
    }

    private static void AddCodes(IReadOnlyList<CodeDefinition> codes, char letter, IReadOnlyList<ModalGroup> groups,
        Dictionary<int, (CodeDefinition, int)> table, string source)
    {
        foreach (var def in codes)
        {
            if (!TryKey(def.Code ?? string.Empty, letter, out var key))
            {
                throw Bad(source, $"code '{def.Code}': expected {letter} followed by a number, e.g. {letter}01");
            }

            var group = -1;
            for (var i = 0; i < groups.Count; i++)
            {
                if (string.Equals(groups[i].Name, def.Group, StringComparison.OrdinalIgnoreCase))
                {
                    group = i;
                }
            }

            if (group < 0)
            {
                throw Bad(source, $"code '{def.Code}': group '{def.Group}' is not one of {string.Join(", ", groups.Select(g => g.Name))}");
            }

            foreach (var c in def.Words + def.Requires + string.Concat(def.Values.Keys))
            {
                if (c is < 'A' or > 'Z')
                {
                    throw Bad(source, $"code '{def.Code}': '{c}' is not an address letter A-Z");
                }
            }

            if (!table.TryAdd(key, (def, group)))
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
        var profile = Parse(r.ReadToEnd(), name);
        profile.Source = profile.Name;
        return profile;
    }

    internal static InvalidDataException Bad(string source, string why) => new($"{source}: invalid machine profile: {why}");
}

/// <summary>An axis of a machine profile: its letter, the motor that drives it and the motor's scale.</summary>
/// <param name="Name">The axis letter (X Y Z A B C U V W).</param>
/// <param name="Motor">The motor number, 1-32.</param>
/// <param name="CountsPerUnit">Motor counts per millimetre (per degree for a rotary axis): the scale of its axis definition.</param>
/// <param name="Rotary">A rotary axis: its unit is the degree.</param>
public sealed record ProfileAxis(string Name, int Motor, double CountsPerUnit = 1, bool Rotary = false);
