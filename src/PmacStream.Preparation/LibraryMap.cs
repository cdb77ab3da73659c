namespace PmacStream.Preparation;

/// <summary>
/// Where the generated library keeps the machine's tables (global P-variables the host downloads and reads back) and
/// its modal state (Q-variables of the coordinate system). Configurable because a machine may already use a range;
/// <c>docs/pmac-library.md</c> lists every variable.
/// </summary>
public sealed record LibraryMap
{
    /// <summary>P(n): the library's profile id; P(n+1): the 24-bit hash of its text.</summary>
    public int Identity { get; init; } = 7000;

    /// <summary>P(n)..P(n+2): the tool change position X, Y, Z (machine coordinates).</summary>
    public int ToolChangePosition { get; init; } = 7010;

    /// <summary>P(n + 3*index + axis): work offset tables, index 1-6 G54-G59, 7-9 G59.1-G59.3, 10.. G54.1 P1..P48.</summary>
    public int WorkOffsets { get; init; } = 7100;

    /// <summary>P(n + H): tool length of offset number H (H 0-199).</summary>
    public int ToolLengths { get; init; } = 7300;

    /// <summary>
    /// P(n + D): cutter radius of offset D (D 0-199), as the operator's tool table sets it. The host's cutter
    /// compensation reads it (the library does not); kept on the controller so the table survives with it.
    /// </summary>
    public int ToolRadii { get; init; } = 7500;

    /// <summary>P(n + H): length wear of offset H. <see cref="ToolLengths"/> holds length plus wear (what G43 applies).</summary>
    public int ToolLengthWear { get; init; } = 7700;

    /// <summary>P(n + D): radius wear of offset D; the compensation uses radius plus wear.</summary>
    public int ToolRadiusWear { get; init; } = 7900;

    /// <summary>
    /// Q(n)..Q(n+16): the modal state. n work offset index; n+1..3 G52 shift; n+4..6 G92 shift; n+7 tool length
    /// applied; n+8 H; n+9 length mode (0, 43, 44); n+10 distance mode (90, 91); n+11 motion mode (0-3); n+12 tool in
    /// the spindle; n+13 1 while a block runs in machine coordinates; n+14..16 the displacement ADIS applies.
    /// </summary>
    public int State { get; init; } = 20;

    /// <summary>The axis transformation matrix the library selects (<c>DEFINE TBUF</c> must reserve at least this many).</summary>
    public int Matrix { get; init; } = 1;

    /// <summary>Q-variable <paramref name="offset"/> of the state block, as PMAC text (<c>Q27</c>).</summary>
    public string Q(int offset) => "Q" + (State + offset).ToString(System.Globalization.CultureInfo.InvariantCulture);

    /// <summary>P-variable <paramref name="n"/> as PMAC text.</summary>
    public static string P(int n) => "P" + n.ToString(System.Globalization.CultureInfo.InvariantCulture);
}
