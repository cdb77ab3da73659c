using System.Globalization;
using System.Text;

namespace PmacStream.Testing;

/// <summary>A zig-zag raster of short G01 moves (0.25 mm at F1500: 10 ms each), 200 moves a row, ending in M30.</summary>
public static class RasterProgram
{
    /// <summary>Writes a raster of <paramref name="moves"/> moves to <paramref name="path"/> and returns the path.</summary>
    public static string Write(string path, int moves)
    {
        var sb = new StringBuilder("G21 G17 G90\nG00 X0 Y0\nF1500\n");
        for (var i = 0; i < moves; i++)
        {
            var (row, col) = Math.DivRem(i, 200);
            sb.Append(CultureInfo.InvariantCulture, $"G01 X{(row % 2 == 0 ? col : 199 - col) * 0.25:0.00} Y{row * 0.25:0.00}\n");
        }

        File.WriteAllText(path, sb.Append("M30\n").ToString());
        return path;
    }
}
