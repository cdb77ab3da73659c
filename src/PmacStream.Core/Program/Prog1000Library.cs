using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Program;

/// <summary>Machine outputs the M-code routines drive (M-variables pointing at I/O bits).</summary>
public sealed record Prog1000Options
{
    /// <summary>M-variable of the spindle-on output (default M902, the spindle port).</summary>
    public string SpindleOn { get; init; } = "M902";

    /// <summary>M-variable of the spindle direction output (1 = counter-clockwise).</summary>
    public string SpindleReverse { get; init; } = "M903";

    /// <summary>M-variable of the coolant output.</summary>
    public string Coolant { get; init; } = "M904";

    /// <summary>Write <c>;</c> comment lines (PComm's download strips them; turn off for a raw terminal).</summary>
    public bool Comments { get; init; } = true;
}

/// <summary>One subroutine of the library: a label in PROG 10n0 (G) or 10n1 (M) and its PMAC statements.</summary>
/// <param name="Code">The code as the profile writes it (<c>G01</c>).</param>
/// <param name="Program">The PMAC program number the code calls (1000 for G00-G99, 1010 for G100-G199, 1001 for M).</param>
/// <param name="Label">The label the call jumps to: <c>N(code*1000)</c> of the code's last two digits.</param>
/// <param name="Body">PMAC statements before <c>RET</c> (empty: accepted and does nothing).</param>
/// <param name="Converted">False when the library knows no conversion for the code (it is accepted and ignored).</param>
/// <param name="Description">What the routine does.</param>
public sealed record Prog1000Routine(string Code, int Program, int Label, string Body, bool Converted, string Description);

/// <summary>
/// G and M code conversion: a PMAC treats <c>Gnn</c> in a motion program as a call of
/// PROG 1000 at label <c>N(nn*1000)</c> and <c>Mnn</c> as PROG 1001, so these programs turn machine-tool codes into
/// PMAC statements. Generated for every G and M code of a machine profile; spindle and coolant stops are preceded by
/// <c>DWELL0</c> so lookahead cannot stop the spindle before the moves ahead of it have run.
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

        Line("CLOSE");
        foreach (var program in new[] { 1000, 1001 }.Concat(routines.Select(r => r.Program)).Distinct().OrderBy(p => p))
        {
            Line($"OPEN PROG {program} CLEAR");
            foreach (var r in routines.Where(r => r.Program == program))
            {
                if (options.Comments)
                {
                    Line($"; {r.Code} {r.Description}{(r.Converted ? "" : " (no PMAC conversion: accepted, does nothing)")}");
                }

                Line(r.Body.Length == 0 ? $"N{r.Label} RET" : $"N{r.Label} {r.Body} RET");
            }

            Line("CLOSE");
        }

        return sb.ToString();
    }

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
        var body = letter == 'G' ? GBody(key, profile) : MBody(key, o);
        return new Prog1000Routine(text, program, label, body ?? "", body != null, def.Description);
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
        // Units and work offsets are fixed by the axis definitions (#1->1000X ...); the codes are accepted so that
        // programs run, and the checker reports a unit mismatch against the profile.
        200 or 210 => "",
        400 => "CC0",
        410 => "CC1",
        420 => "CC2",
        // READ(H) consumes the offset number so the H word is not taken as a command.
        430 => "READ(H)",
        490 => "",
        >= 540 and <= 590 when codeTimesTen % 10 == 0 => "",
        800 => "",
        900 => "ABS",
        910 => "INC",
        940 => "",
        _ => null,
    };

    private static string? MBody(int codeTimesTen, Prog1000Options o) => codeTimesTen switch
    {
        // Stops wait for the moves ahead (DWELL0 ends lookahead), so the spindle is not stopped early.
        0 or 10 => "DWELL0 STOP",
        20 or 300 => $"DWELL0 {o.SpindleOn}=0 {o.Coolant}=0",
        30 => $"DWELL0 {o.SpindleReverse}=0 {o.SpindleOn}=1",
        40 => $"DWELL0 {o.SpindleReverse}=1 {o.SpindleOn}=1",
        50 => $"DWELL0 {o.SpindleOn}=0",
        60 => "DWELL0",
        80 => $"{o.Coolant}=1",
        90 => $"DWELL0 {o.Coolant}=0",
        _ => null,
    };
}
