using System.Text;

namespace PmacStream.Benchmarks.Generators;

/// <summary>
/// Deterministic CAM-like 3-axis surfacing program: a zig-zag raster over a 250 x 250 mm patch of a wavy surface,
/// every block a modal G01 move with X, Y and Z at four decimals and an N number (about 36 bytes a line, so
/// 1,000,000 lines are about 36 MB). When the patch is done the next pass runs back over it 0.1 mm deeper, so any
/// line count (up to gigabytes) stays within the machine envelope. Written streamed through a fixed buffer.
/// The same line count always gives the same bytes; the program checks clean under the default machine profile.
/// </summary>
public static class SurfacingGenerator
{
    private const int PointsPerRow = 1001;      // X 0..250 in 0.25 mm steps
    private const int RowsPerPass = 1001;       // Y 0..250 in 0.25 mm steps
    private const long StepTenThousandths = 2500; // 0.25 mm in units of 0.0001 mm

    /// <summary>Lines before the raster body.</summary>
    public static readonly string[] Header =
    [
        "%",
        "O0001 (PMACSTREAM SURFACING BENCHMARK)",
        "N1 G21 G17 G90 G40 G49 G54",
        "N2 T1 (6MM BALL END MILL)",
        "N3 S8000 M03",
        "N4 M08",
        "N5 G00 Z5.0000",
        "N6 G00 X0.0000 Y0.0000",
        "N7 G01 Z-1.0000 F1500.",
    ];

    /// <summary>Number of tail lines (retract, coolant off, spindle off, end, tape mark).</summary>
    public const int TailLines = 5;

    /// <summary>Writes a program of exactly <paramref name="lines"/> lines (at least 15) to a file.</summary>
    public static void Write(string path, long lines)
    {
        using var fs = new FileStream(path, FileMode.Create, FileAccess.Write, FileShare.None, 1 << 16);
        Write(fs, lines);
    }

    /// <summary>Writes a program of exactly <paramref name="lines"/> lines (at least 15) to a stream.</summary>
    public static void Write(Stream output, long lines)
    {
        var minimum = Header.Length + TailLines + 1;
        if (lines < minimum)
        {
            throw new ArgumentOutOfRangeException(nameof(lines), $"at least {minimum} lines are needed");
        }

        var buf = new byte[1 << 20];
        var pos = 0;

        void Flush()
        {
            output.Write(buf, 0, pos);
            pos = 0;
        }

        void Text(string s)
        {
            if (pos + s.Length + 2 > buf.Length)
            {
                Flush();
            }

            pos += Encoding.ASCII.GetBytes(s, 0, s.Length, buf, pos);
            buf[pos++] = (byte)'\n';
        }

        foreach (var h in Header)
        {
            Text(h);
        }

        var n = 7L;
        var body = lines - Header.Length - TailLines;
        for (long k = 0; k < body; k++)
        {
            if (pos + 96 > buf.Length)
            {
                Flush();
            }

            var pass = k / ((long)PointsPerRow * RowsPerPass);
            var inPass = k % ((long)PointsPerRow * RowsPerPass);
            var row = inPass / PointsPerRow;
            var col = inPass % PointsPerRow;
            if ((row & 1) == 1)
            {
                col = PointsPerRow - 1 - col;       // zig-zag in X
            }

            if ((pass & 1) == 1)
            {
                row = RowsPerPass - 1 - row;        // every other pass runs back in Y
            }

            var x = col * StepTenThousandths;
            var y = row * StepTenThousandths;
            var z = SurfaceZ(x, y, pass);

            n++;
            buf[pos++] = (byte)'N';
            pos += WriteLong(buf, pos, n);
            buf[pos++] = (byte)' ';
            buf[pos++] = (byte)'X';
            pos += WriteFixed4(buf, pos, x);
            buf[pos++] = (byte)' ';
            buf[pos++] = (byte)'Y';
            pos += WriteFixed4(buf, pos, y);
            buf[pos++] = (byte)' ';
            buf[pos++] = (byte)'Z';
            pos += WriteFixed4(buf, pos, z);
            buf[pos++] = (byte)'\n';
        }

        Text($"N{++n} G00 Z5.0000");
        Text($"N{++n} M09");
        Text($"N{++n} M05");
        Text($"N{++n} M30");
        Text("%");
        Flush();
        output.Flush();
    }

    /// <summary>Surface height in 0.0001 mm: a gentle wave 1..2 mm deep, 0.1 mm deeper on every pass.</summary>
    internal static long SurfaceZ(long x, long y, long pass)
    {
        var xm = x / 10000.0;
        var ym = y / 10000.0;
        var z = -1.5 - (0.5 * Math.Sin(xm * 0.05) * Math.Cos(ym * 0.04)) - (0.1 * pass);
        return (long)Math.Round(z * 10000.0, MidpointRounding.AwayFromZero);
    }

    private static int WriteLong(byte[] buf, int pos, long v)
    {
        Span<byte> tmp = stackalloc byte[20];
        var len = 0;
        do
        {
            tmp[len++] = (byte)('0' + (v % 10));
            v /= 10;
        }
        while (v > 0);

        for (var i = 0; i < len; i++)
        {
            buf[pos + i] = tmp[len - 1 - i];
        }

        return len;
    }

    /// <summary>Writes a value given in 0.0001 units as <c>-12.3456</c>.</summary>
    private static int WriteFixed4(byte[] buf, int pos, long v)
    {
        var start = pos;
        if (v < 0)
        {
            buf[pos++] = (byte)'-';
            v = -v;
        }

        pos += WriteLong(buf, pos, v / 10000);
        buf[pos++] = (byte)'.';
        var frac = v % 10000;
        buf[pos++] = (byte)('0' + (frac / 1000));
        buf[pos++] = (byte)('0' + (frac / 100 % 10));
        buf[pos++] = (byte)('0' + (frac / 10 % 10));
        buf[pos++] = (byte)('0' + (frac % 10));
        return pos - start;
    }
}
