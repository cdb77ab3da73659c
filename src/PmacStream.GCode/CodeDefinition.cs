using System.Globalization;

namespace PmacStream.GCode;

/// <summary>What runs a G or M code on the controller (the PMAC motion program the chunks call).</summary>
public enum ControllerSupport
{
    /// <summary>
    /// A PROG 1000/1001 routine runs it (<c>Preparation.Prog1000Library</c>). An empty routine counts where the controller
    /// already behaves as the code asks (G21 on axes defined in millimetres, G94 with F per minute, G80 with no cycle).
    /// </summary>
    Library,

    /// <summary>The host turns it into controller statements before the chunk is sent.</summary>
    Host,

    /// <summary>
    /// Nothing runs it yet: <c>check</c> warns (W006), the library has no routine for it, and a job gate must refuse a
    /// program that uses it (sending it would look as if it had run).
    /// </summary>
    NotYet,
}

/// <summary>Whether a code stops the program on the controller until the operator continues it.</summary>
public enum ProgramStopKind
{
    /// <summary>The program goes on.</summary>
    None,

    /// <summary>Always stops (<c>M00</c>; a tool change that ends in a stop).</summary>
    Program,

    /// <summary>Stops while the optional-stop switch is on (<c>M01</c>); the host sets the switch on the controller.</summary>
    Optional,
}

/// <summary>A modal group of a profile: the codes of which at most one may stand in a block.</summary>
/// <param name="Name">Name as the profile writes it (FANUC group numbers such as <c>01</c>, or <c>GA</c>..<c>GI</c>).</param>
/// <param name="Description">What the group selects, for people.</param>
/// <param name="Modal">False for a group whose codes act only in their own block (G04, G28, M00, M06).</param>
public sealed record ModalGroup(string Name, string Description, bool Modal);

/// <summary>One G or M code a machine supports.</summary>
/// <param name="Code">The code as written, e.g. <c>G01</c>, <c>G64.1</c>, <c>M30</c>.</param>
/// <param name="Group">Name of its modal group in the profile.</param>
/// <param name="Description">What the code does, for people.</param>
public sealed record CodeDefinition(string Code, string Group, string Description)
{
    private static readonly IReadOnlyDictionary<char, ValueSet> NoValues = new Dictionary<char, ValueSet>();

    /// <summary>What runs the code on the controller; a profile that does not say is taken as <see cref="ControllerSupport.NotYet"/>.</summary>
    public ControllerSupport Controller { get; init; } = ControllerSupport.NotYet;

    /// <summary>
    /// Parameter letters the code reads (Q, L, P, R, E, K, I, J ...): such a word in a block where no code reads it is
    /// reported as unused (W003). Axis words are not listed; the interpreter knows which codes take them as data.
    /// </summary>
    public string Words { get; init; } = string.Empty;

    /// <summary>Letters the code cannot go without (<c>G10</c> needs L and P): missing ones are an error (E124).</summary>
    public string Requires { get; init; } = string.Empty;

    /// <summary>Values a word must take with this code (<c>G10 L</c> in 2, 20, ...), by letter: others are an error (E125).</summary>
    public IReadOnlyDictionary<char, ValueSet> Values { get; init; } = NoValues;

    /// <summary>PMAC statements for the code's routine when the profile gives them (a machine's own outputs); null: the library's.</summary>
    public string? Routine { get; init; }

    /// <summary>
    /// Whether the code's routine stops the program (profile JSON <c>"stop": "program"</c> or <c>"optional"</c>): the
    /// splitter tracks such a block (<c>M0==line DWELL0 M00</c>) so a stop names its line, and a job waits there for
    /// the operator. The library's built-in <c>M00</c> and <c>M01</c> routines stop; a profile's own routine must say
    /// <c>STOP</c> itself.
    /// </summary>
    public ProgramStopKind Stop { get; init; }

    /// <summary>How the controller runs it, or why it does not yet, for people (the profile table and <c>pmacstream profiles</c>).</summary>
    public string Note { get; init; } = string.Empty;

    /// <summary>The code's letter, <c>G</c> or <c>M</c>.</summary>
    public char Letter => Code.Length > 0 ? char.ToUpperInvariant(Code[0]) : '?';

    /// <summary>The code number (1, 64.1).</summary>
    public double Number => double.Parse(Code.AsSpan(1), NumberStyles.AllowDecimalPoint, CultureInfo.InvariantCulture);

    /// <summary>The code number scaled by 10 (G01 -> 10, G54.1 -> 541): how profiles and the interpreter key codes.</summary>
    public int Key => MachineProfile.Key(Number);

    /// <summary>True when the code reads the letter (see <see cref="Words"/>).</summary>
    public bool Reads(char letter) => Words.Contains(letter, StringComparison.Ordinal);
}

/// <summary>
/// The values a word may take with a code, as a profile writes them: <c>1,2,10-13,20</c> (whole numbers; a range
/// includes both ends), or <c>&gt;0</c> (any number above a bound: a peck depth).
/// </summary>
public sealed class ValueSet
{
    private readonly (long From, long To)[] _ranges;
    private readonly double? _above;

    private ValueSet(string text, (long, long)[] ranges, double? above)
    {
        Text = text;
        _ranges = ranges;
        _above = above;
    }

    /// <summary>The set as written.</summary>
    public string Text { get; }

    /// <summary>Parses <c>1,2,10-13</c>. Throws <see cref="FormatException"/> naming the bad part.</summary>
    public static ValueSet Parse(string text)
    {
        var trimmed = text.Trim();
        if (trimmed.StartsWith('>'))
        {
            return double.TryParse(trimmed.AsSpan(1), NumberStyles.Float, CultureInfo.InvariantCulture, out var bound)
                ? new ValueSet(trimmed, [], bound)
                : throw new FormatException($"'{trimmed}' is not a bound such as >0");
        }

        var ranges = new List<(long, long)>();
        foreach (var raw in text.Split(',', StringSplitOptions.TrimEntries | StringSplitOptions.RemoveEmptyEntries))
        {
            var dash = raw.IndexOf('-', 1);
            var from = dash < 0 ? raw : raw[..dash];
            var to = dash < 0 ? raw : raw[(dash + 1)..];
            if (!long.TryParse(from, NumberStyles.AllowLeadingSign, CultureInfo.InvariantCulture, out var a) ||
                !long.TryParse(to, NumberStyles.AllowLeadingSign, CultureInfo.InvariantCulture, out var b) || b < a)
            {
                throw new FormatException($"'{raw}' is not a whole number or a range such as 1-48");
            }

            ranges.Add((a, b));
        }

        if (ranges.Count == 0)
        {
            throw new FormatException("no values");
        }

        return new ValueSet(trimmed, ranges.ToArray(), null);
    }

    /// <summary>True for a whole number inside one of the ranges (or a number above the bound).</summary>
    public bool Contains(double value)
    {
        if (_above is { } bound)
        {
            return value > bound;
        }

        if (value != Math.Floor(value))
        {
            return false;
        }

        foreach (var (from, to) in _ranges)
        {
            if (value >= from && value <= to)
            {
                return true;
            }
        }

        return false;
    }

    /// <inheritdoc />
    public override string ToString() => Text;
}
