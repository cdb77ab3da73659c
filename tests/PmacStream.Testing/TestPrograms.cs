using System.Globalization;
using System.Text;

namespace PmacStream.Testing;

/// <summary>
/// The tests' G-code generators, one family: a header, <c>n</c> numbered moves from a move pattern (a grid walked row
/// by row, the raster of <see cref="RasterProgram"/>, or the test's own), lines inserted after chosen moves (stops,
/// coolant, a code under test) and a footer. The text is byte for byte what each test wrote by hand before, so the
/// line numbers its assertions name stay where they were.
/// </summary>
public static class TestPrograms
{
    /// <summary>Millimetres, XY plane, absolute, at the origin: the header most tests start from (add a feed).</summary>
    public const string Metric = "G21 G17 G90\nG00 X0 Y0\n";

    /// <summary>The footer of a program written as a CAM post writes it: spindle off, end, tape mark.</summary>
    public const string TapeEnd = "M05\nM30\n%\n";

    /// <summary>
    /// A program's text: <paramref name="header"/>, then <paramref name="move"/>(i) for i = 1..<paramref name="moves"/>,
    /// each followed by <paramref name="after"/>(i) when that is not null, then <paramref name="footer"/>. Every line
    /// ends in LF.
    /// </summary>
    public static string Text(string header, int moves, Func<int, string> move, string footer = "M30\n", Func<int, string?>? after = null)
    {
        var sb = new StringBuilder(header);
        for (var i = 1; i <= moves; i++)
        {
            sb.Append(move(i)).Append('\n');
            if (after?.Invoke(i) is { } extra)
            {
                sb.Append(extra).Append('\n');
            }
        }

        return sb.Append(footer).ToString();
    }

    /// <summary>
    /// <c>G01 X(i mod columns × step) Y(i div columns)</c>: a grid walked row by row, one row every
    /// <paramref name="columns"/> moves; <paramref name="decimals"/> writes the values as <c>4.0</c> rather than <c>4</c>.
    /// </summary>
    public static Func<int, string> Grid(int columns, int step = 1, bool decimals = false)
    {
        var dot = decimals ? ".0" : string.Empty;
        return i => string.Create(CultureInfo.InvariantCulture, $"G01 X{i % columns * step}{dot} Y{i / columns}{dot}");
    }

    /// <summary>
    /// The raster's move i (1-based): 0.25 mm steps, 200 a row, zig-zag (<see cref="RasterProgram"/> writes it whole with
    /// <c>F1500</c>: 10 ms a move).
    /// </summary>
    public static string Raster(int i) => RasterOf(200)(i);

    /// <summary>A raster's moves with <paramref name="perRow"/> moves a row (0.25 mm steps, zig-zag), move i 1-based.</summary>
    public static Func<int, string> RasterOf(int perRow) => i =>
    {
        var (row, col) = Math.DivRem(i - 1, perRow);
        return string.Create(CultureInfo.InvariantCulture, $"G01 X{(row % 2 == 0 ? col : perRow - 1 - col) * 0.25:0.00} Y{row * 0.25:0.00}");
    };

    /// <summary>
    /// A surfacing pass's block <c>N i</c>: X steps 0.25 mm, Y 0.5 mm every 100 blocks, Z wandering below -1.5 (a CAM
    /// post's numbered, modal XYZ lines without a G word, four decimals).
    /// </summary>
    public static string Surfacing(int i) =>
        string.Create(CultureInfo.InvariantCulture, $"N{i} X{i * 0.25:0.0000} Y{(i / 100) * 0.5:0.0000} Z{-1.5 - (i % 37) * 0.0061:0.0000}");

    /// <summary>Writes <paramref name="text"/> to <paramref name="path"/> and returns the path.</summary>
    public static string Write(string path, string text)
    {
        File.WriteAllText(path, text);
        return path;
    }
}
