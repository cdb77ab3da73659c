namespace PmacStream.Testing;

/// <summary>A zig-zag raster of short G01 moves (0.25 mm at F1500: 10 ms each), 200 moves a row, ending in M30.</summary>
public static class RasterProgram
{
    /// <summary>Writes a raster of <paramref name="moves"/> moves to <paramref name="path"/> and returns the path.</summary>
    public static string Write(string path, int moves) => TestPrograms.Write(path, TestPrograms.Text(TestPrograms.Metric + "F1500\n", moves, TestPrograms.Raster));
}
