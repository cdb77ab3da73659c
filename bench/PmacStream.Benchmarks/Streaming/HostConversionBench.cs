using System.Diagnostics;
using System.Globalization;
using System.Text;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Benchmarks.Streaming;

/// <summary>
/// The host conversion on the split's reading thread (<c>host-conversion LINES [RUNS]</c>): one program of LINES
/// feed moves written in millimetres (G21, the axis lane) and the same in inches (G20: every block a host block,
/// converted to millimetres), split with the check against the default profile. Reports wall time, CPU time of the
/// process (reader and writer threads; steadier than wall time on a loaded machine) and bytes allocated (all
/// threads) per split, the median of RUNS (default 3).
/// </summary>
public static class HostConversionBench
{
    public static int Run(string[] args)
    {
        var lines = int.Parse(args[0], CultureInfo.InvariantCulture);
        var runs = args.Length > 1 ? int.Parse(args[1], CultureInfo.InvariantCulture) : 3;
        var dir = Path.Combine(Path.GetTempPath(), "pmacstream-bench", "host-conversion");
        if (Directory.Exists(dir))
        {
            Directory.Delete(dir, true);
        }

        Directory.CreateDirectory(dir);
        Console.WriteLine($"split with check (default profile), {lines} moves, median of {runs}");
        Console.WriteLine("units | wall s | CPU s | CPU ns/block | bytes/block | blocks");
        foreach (var (units, scale) in new[] { ("G21", 1.0), ("G20", 1 / 25.4) })
        {
            var src = Path.Combine(dir, $"{units}.nc");
            Write(src, lines, units, scale);
            var walls = new List<double>();
            var cpus = new List<double>();
            var bytes = new List<long>();
            long blocks = 0;
            for (var r = 0; r < runs; r++)
            {
                var outDir = Path.Combine(dir, $"{units}-chunks");
                if (Directory.Exists(outDir))
                {
                    Directory.Delete(outDir, true);
                }

                GC.Collect();
                var b0 = GC.GetTotalAllocatedBytes(precise: true);
                var cpu0 = Process.GetCurrentProcess().TotalProcessorTime;
                var sw = Stopwatch.StartNew();
                var split = Splitter.Split(src, new SplitOptions { OutDir = outDir, CheckProfile = MachineProfile.Default });
                walls.Add(sw.Elapsed.TotalSeconds);
                cpus.Add((Process.GetCurrentProcess().TotalProcessorTime - cpu0).TotalSeconds);
                bytes.Add(GC.GetTotalAllocatedBytes(precise: true) - b0);
                blocks = split.Manifest.TotalBlocks;
            }

            walls.Sort();
            cpus.Sort();
            bytes.Sort();
            var cpu = cpus[runs / 2];
            Console.WriteLine($"{units}   | {walls[runs / 2],6:0.000} | {cpu,5:0.00} | {1e9 * cpu / blocks,12:0} | {(double)bytes[runs / 2] / blocks,11:0.0} | {blocks}");
        }

        Directory.Delete(dir, true);
        return 0;
    }

    /// <summary>Zig-zag feed moves with an arc every tenth block, in the program's units.</summary>
    private static void Write(string path, int lines, string units, double scale)
    {
        using var w = new StreamWriter(path, false, new UTF8Encoding(false), 1 << 16);
        string N(double v) => (v * scale).ToString("0.####", CultureInfo.InvariantCulture);
        w.Write($"%\nO3001\n{units} G17 G90 G54\nG00 X0 Y0 Z{N(5)}\nG01 Z0 F{N(600)}\n");
        for (var i = 1; i <= lines; i++)
        {
            var x = (i % 1000) * 0.1;
            var y = (i / 1000) * 0.1;
            var xs = N((i / 1000) % 2 == 0 ? x : 100 - x);
            w.Write(i % 10 == 0 ? $"G02 X{xs} Y{N(y)} R{N(5)}\n" : $"G01 X{xs} Y{N(y)}\n");
        }

        w.Write("M30\n%\n");
    }
}
