using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>Machine outputs the M-code routines drive (M-variables pointing at I/O bits).</summary>
public sealed record Prog1000Options
{
    /// <summary>M-variable of the spindle-on output (default M902, the spindle port).</summary>
    public string SpindleOn { get; init; } = "M902";

    /// <summary>M-variable of the spindle direction output (1 = counter-clockwise).</summary>
    public string SpindleReverse { get; init; } = "M903";

    /// <summary>M-variable of the coolant output.</summary>
    public string Coolant { get; init; } = "M904";

    /// <summary>
    /// The optional-stop switch the <c>M01</c> routine reads (1: stop, 0: go on): a P-variable the host sets before a
    /// job and while it runs (<c>--optional-stop</c>, the HMI's check box), so switching it needs no new split.
    /// </summary>
    public string OptionalStop { get; init; } = PreparationDefaults.OptionalStopVariable;

    /// <summary>M-variable of the mist coolant output (M07).</summary>
    public string MistCoolant { get; init; } = "M905";

    /// <summary>M-variable of the spindle orientation output (M19).</summary>
    public string SpindleOrient { get; init; } = "M906";

    /// <summary>
    /// Variable the M19 routine sets to the orientation angle in degrees (R, or P where the profile's M19 takes no Q:
    /// Haas's whole-degree P), 0 when the block gives none. Assumed: the machine's orientation logic reads it.
    /// </summary>
    public string SpindleOrientAngle { get; init; } = "M907";

    /// <summary>
    /// Variable the M19 routine sets to the turning direction where the profile's M19 takes P beside Q (LinuxCNC: 0
    /// shortest way, 1 clockwise, 2 counter-clockwise), 0 when the block gives none. Assumed, like the angle.
    /// </summary>
    public string SpindleOrientDirection { get; init; } = "M908";

    /// <summary>M-variable of the through-spindle coolant output (M88 on, M89 off). Assumed, default M909.</summary>
    public string ThroughSpindleCoolant { get; init; } = "M909";

    /// <summary>M-variable of the 4th axis brake output (M10 clamp = 1, M11 unclamp = 0). Assumed, default M910.</summary>
    public string FourthAxisBrake { get; init; } = "M910";

    /// <summary>M-variable of the 5th axis brake output (M12 clamp = 1, M13 unclamp = 0). Assumed, default M911.</summary>
    public string FifthAxisBrake { get; init; } = "M911";

    /// <summary>M-variable of the chip conveyor run output (M31/M32 = 1, M33 = 0). Assumed, default M912.</summary>
    public string ChipConveyor { get; init; } = "M912";

    /// <summary>M-variable of the chip conveyor direction output (1 = reverse, M32). Assumed, default M913.</summary>
    public string ChipConveyorReverse { get; init; } = "M913";

    /// <summary>M-variable of the through-tool air blast output (M73 on, M74 off). Assumed, default M914.</summary>
    public string ThroughToolAir { get; init; } = "M914";

    /// <summary>M-variable of the air gun output (M83 on, M84 off). Assumed, default M915.</summary>
    public string AirGun { get; init; } = "M915";

    /// <summary>Write <c>;</c> comment lines (PComm's download strips them; turn off for a raw terminal).</summary>
    public bool Comments { get; init; } = true;

    /// <summary>
    /// M00, M01 and the default M06 hook end in <c>STOP</c> (a program stop the operator continues). Off: they only
    /// wait for the moves ahead (for a run with nobody at the machine, such as the position proof).
    /// </summary>
    public bool ProgramStops { get; init; } = true;

    /// <summary>
    /// PMAC statements M06 runs (the tool it changes to is in Q120, from <c>READ(T)</c>); null: the default hook,
    /// spindle off, a machine-coordinate move to the tool change position (Z first) when the profile has one, and a
    /// program stop.
    /// </summary>
    public string? ToolChangeHook { get; init; }

    /// <summary>Where the library keeps its tables and modal state.</summary>
    public LibraryMap Map { get; init; } = new();
}

/// <summary>One subroutine of the library: a label in PROG 10n0 (G) or 10n1 (M) and its PMAC statements.</summary>
/// <param name="Code">The code as the profile writes it (<c>G01</c>).</param>
/// <param name="Program">The PMAC program number the code calls (1000 for G00-G99, 1010 for G100-G199, 1001 for M).</param>
/// <param name="Label">The label the call jumps to: <c>N(code*1000)</c> of the code's last two digits.</param>
/// <param name="Body">PMAC statements before <c>RET</c> (empty: the controller already does what the code asks).</param>
/// <param name="Converted">True when the library has the routine (the profile says <see cref="ControllerSupport.Library"/>); false: no routine is written.</param>
/// <param name="Description">What the routine does.</param>
public sealed record Prog1000Routine(string Code, int Program, int Label, string Body, bool Converted, string Description)
{
    /// <summary>What runs the code, as the profile says.</summary>
    public ControllerSupport Controller { get; init; }

    /// <summary>Why the routine is empty or missing (the profile's note).</summary>
    public string Note { get; init; } = string.Empty;
}

/// <summary>
/// G and M code conversion: a PMAC treats <c>Gnn</c> in a motion program as a call of
/// PROG 1000 at label <c>N(nn*1000)</c> and <c>Mnn</c> as PROG 1001, so these programs turn machine-tool codes into
/// PMAC statements. Generated for the G and M codes a machine profile marks <see cref="ControllerSupport.Library"/>
/// (the profile's own <c>routine</c>, else the built-in one); a code the controller cannot run yet gets no routine
/// (a missing label is ignored by the PMAC, which is why a job gate must refuse programs using such codes). Spindle
/// and coolant stops are preceded by <c>DWELL0</c> so lookahead cannot stop the spindle before the moves ahead of
/// it have run.
/// </summary>
public static class Prog1000Library
{
    /// <summary>The routines for a profile's codes, in program then label order.</summary>
    public static IReadOnlyList<Prog1000Routine> Routines(MachineProfile profile, Prog1000Options? options = null)
    {
        options ??= new Prog1000Options();
        var list = new List<Prog1000Routine>();
        foreach (var c in profile.GCodes)
        {
            list.Add(Make(c, 'G', profile, options));
        }

        foreach (var c in profile.MCodes)
        {
            list.Add(Make(c, 'M', profile, options));
        }

        return list.GroupBy(r => (r.Program, r.Label)).Select(g => g.First()).OrderBy(r => r.Program).ThenBy(r => r.Label).ToList();
    }

    /// <summary>The downloadable file: <c>OPEN PROG 1000 CLEAR</c> ... <c>CLOSE</c>, <c>OPEN PROG 1001 CLEAR</c> ... <c>CLOSE</c>.</summary>
    public static string Generate(MachineProfile profile, Prog1000Options? options = null)
    {
        options ??= new Prog1000Options();
        var routines = Routines(profile, options);
        var sb = new StringBuilder();
        void Line(string s) => sb.Append(s).Append("\r\n");
        if (options.Comments)
        {
            Line($"; PmacStream G/M code library for profile '{profile.Name}'");
            Line("; Gnn calls PROG 1000 at N(nn*1000), Mnn calls PROG 1001 (codes 100-199: PROG 1010/1011).");
            Line($"; Outputs: spindle on {options.SpindleOn}, spindle reverse {options.SpindleReverse}, coolant {options.Coolant}.");
        }

        if (options.Comments)
        {
            var m = options.Map;
            Line($"; Work offsets: P{m.WorkOffsets + 3}.. (X Y Z of index 1 = G54 .. 6 = G59, 7-9 G59.1-G59.3, 10.. G54.1 P1..); tool lengths P{m.ToolLengths}+H;");
            Line($"; modal state Q{m.State}..Q{m.State + 19}; identity P{m.Identity} (profile id), P{m.Identity + 1} (hash). See docs/pmac-library.md.");
        }

        var notYet = routines.Where(r => r.Controller == ControllerSupport.NotYet).Select(r => r.Code).ToList();
        var host = routines.Where(r => r.Controller == ControllerSupport.Host).Select(r => r.Code).ToList();
        if (options.Comments && host.Count > 0)
        {
            Line($"; Converted by the host before sending (no routine): {string.Join(' ', host)}");
        }

        if (options.Comments && notYet.Count > 0)
        {
            Line($"; Not run on this controller yet (no routine; a job using them is refused): {string.Join(' ', notYet)}");
        }

        Line("CLOSE");
        // The axis transformation matrices the library's displacement lives in (an online command, before the programs).
        Line($"DEFINE TBUF {options.Map.Matrix}");
        foreach (var program in new[] { 1000, 1001 }.Concat(routines.Where(r => r.Converted).Select(r => r.Program)).Distinct().OrderBy(p => p))
        {
            Line($"OPEN PROG {program} CLEAR");
            if (program == 1000)
            {
                foreach (var (label, body, what) in LibraryRoutines.Private(profile, options))
                {
                    if (options.Comments)
                    {
                        Line("; " + what);
                    }

                    Line(LabelLine(label, body));
                }
            }

            foreach (var r in routines.Where(r => r.Program == program && r.Converted))
            {
                if (options.Comments)
                {
                    Line($"; {r.Code} {r.Description}{(r.Body.Length == 0 && r.Note.Length > 0 ? $" ({r.Note})" : "")}");
                }

                Line(r.Body.Length == 0 ? $"N{r.Label} RET" : LabelLine(r.Label, r.Body));
            }

            Line("CLOSE");
        }

        // Last: which library this is, for the host to read before a job (P-variables, so any port can read them).
        var text = sb.ToString();
        var (id, hash) = Identity(profile, text);
        if (options.Comments)
        {
            Line($"; Library identity: P{options.Map.Identity}=profile id, P{options.Map.Identity + 1}=24-bit hash of the text above");
        }

        Line($"P{options.Map.Identity}={id} P{options.Map.Identity + 1}={hash}");
        return sb.ToString();
    }

    /// <summary>
    /// The identity the generated library records: a profile id (1-4 for the built-in profiles in their order, 9 for
    /// any other) and a 24-bit hash of the library's text (exactly representable in a PMAC variable).
    /// </summary>
    public static (int ProfileId, int Hash) Identity(MachineProfile profile, string libraryText)
    {
        var index = MachineProfile.BuiltInNames.ToList().IndexOf(profile.Name);
        // Comments do not count: the library downloaded without them is the same library.
        var statements = string.Join('\n', libraryText.Split('\n').Select(l => l.TrimEnd('\r')).Where(l => l.Length > 0 && l[0] != ';'));
        var digest = System.Security.Cryptography.SHA256.HashData(Encoding.UTF8.GetBytes(statements));
        return (index >= 0 ? index + 1 : 9, (digest[0] << 16) | (digest[1] << 8) | digest[2]);
    }

    /// <summary>The identity written at the end of <see cref="Generate"/>'s text for these options.</summary>
    public static (int ProfileId, int Hash) IdentityOf(MachineProfile profile, Prog1000Options? options = null)
    {
        var text = Generate(profile, options);
        var cut = text.LastIndexOf("P" + (options ?? new Prog1000Options()).Map.Identity.ToString(CultureInfo.InvariantCulture) + "=", StringComparison.Ordinal);
        var body = text[..cut];
        if ((options ?? new Prog1000Options()).Comments)
        {
            body = body[..body.LastIndexOf(';')];
        }

        return Identity(profile, body);
    }

    /// <summary>A routine's line(s): <c>RET</c> on a line of its own after a multi-line body, whose last line may be a one-line IF.</summary>
    private static string LabelLine(int label, string body) =>
        body.Contains('\n') ? $"N{label} {body}\r\nRET" : $"N{label} {body} RET";

    private static Prog1000Routine Make(CodeDefinition def, char letter, MachineProfile profile, Prog1000Options o)
    {
        var text = def.Code.Trim().ToUpperInvariant();
        if (text.Length < 2 || text[0] != letter ||
            !double.TryParse(text.AsSpan(1), NumberStyles.AllowDecimalPoint, CultureInfo.InvariantCulture, out var value) ||
            value < 0 || value >= 1000)
        {
            throw new InvalidDataException($"profile '{profile.Name}': '{def.Code}' is not a {letter} code between 0 and 999.999");
        }

        // Turbo PMAC: G{data} is CALL 10n0.(data'*1000), n the hundreds digit, data' the rest.
        var hundreds = (int)(value / 100);
        var label = (int)Math.Round((value - (hundreds * 100)) * 1000);
        var program = (letter == 'G' ? 1000 : 1001) + (hundreds * 10);
        var key = (int)Math.Round(value * 10);
        if (def.Controller != ControllerSupport.Library)
        {
            return new Prog1000Routine(text, program, label, string.Empty, false, def.Description) { Controller = def.Controller, Note = def.Note };
        }

        var body = def.Routine ?? (letter == 'G' ? LibraryRoutines.G(key, profile, o) ?? GBody(key, profile) : LibraryRoutines.M(key, profile, o) ?? MBody(key, o))
            ?? throw new InvalidDataException($"profile '{profile.Name}': {text} is marked \"controller\": \"library\" but the library has no routine for it: give it a \"routine\" or mark it \"not-yet\"");
        if (body.Length == 0 && def.Words.Length > 0)
        {
            // The code's words follow it on the line: read them, or the controller would run them as statements.
            body = $"READ({string.Join(',', def.Words.ToCharArray())})";
        }

        return new Prog1000Routine(text, program, label, body, true, def.Description) { Controller = def.Controller, Note = def.Note };
    }

    private static string? GBody(int codeTimesTen, MachineProfile profile) => codeTimesTen switch
    {
        0 => "RAPID",
        10 => "LINEAR",
        20 => "CIRCLE1",
        30 => "CIRCLE2",
        // READ(P) puts P in Q116 (Turbo convention: letter n -> Q100+n); DWELL is in milliseconds.
        40 => profile.DwellPInMilliseconds ? "READ(P) DWELL(Q116)" : "READ(P) DWELL(Q116*1000)",
        90 => "DWELL0",
        170 => "NORMAL K-1",
        180 => "NORMAL J-1",
        190 => "NORMAL I-1",
        400 => "CC0",
        900 => "ABS",
        910 => "INC",
        // Codes that ask for what the coordinate system already does (the profile's note says why for each):
        // millimetres (G21), the G54 origin, no length offset (G49), no cycle (G80), feed per minute (G94), blending
        // (G64), cancels of what is never applied (G15, G23, G67; G50, G50.1, G69 in a profile that does not have the host transform positions), rpm (G97), cycle
        // return levels only cycles read (G98, G99), incremental circle centres (G91.1), lookahead on the
        // controller (G05.1, G08, G187).
        210 or 540 or 490 or 800 or 940 or 640 or 150 or 230 or 500 or 501 or 670 or 690 or 970 or 980 or 990 or 911 or 51 or 80 or 1870 => "",
        _ => null,
    };

    private static string? MBody(int codeTimesTen, Prog1000Options o) => codeTimesTen switch
    {
        // Stops wait for the moves ahead (DWELL0 ends lookahead), so the spindle is not stopped early (M00/M01: LibraryRoutines).
        20 or 300 => $"DWELL0 {o.SpindleOn}=0 {o.Coolant}=0",
        30 => $"DWELL0 {o.SpindleReverse}=0 {o.SpindleOn}=1",
        40 => $"DWELL0 {o.SpindleReverse}=1 {o.SpindleOn}=1",
        50 => $"DWELL0 {o.SpindleOn}=0",
        80 => $"{o.Coolant}=1",
        90 => $"DWELL0 {o.Coolant}=0",
        _ => null,
    };
}
