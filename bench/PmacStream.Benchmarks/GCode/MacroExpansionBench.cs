using System.Diagnostics;
using PmacStream.GCode;
using PmacStream.GCode.Expansion;

namespace PmacStream.Benchmarks.GCode;

/// <summary>
/// Issue 27 item 6: a Custom Macro B loop of N blocks (default 1,000,000) expanded on the host, blocks per second
/// (goal: more than 1M/s) and the memory it took (bounded: the expansion is streamed, never held); and, given a plain
/// program, what looking for macros adds to its check (<c>macro-expand [BLOCKS] [PLAIN.nc]</c>).
/// </summary>
public static class MacroExpansionBench
{
    /// <summary>Runs the measurement; returns the process exit code.</summary>
    public static int Run(string[] args)
    {
        var blocks = args.Length > 0 && long.TryParse(args[0], out var b) ? b : 1_000_000;
        var dir = Directory.CreateTempSubdirectory("pmacstream-macro-bench-").FullName;
        try
        {
            var path = Path.Combine(dir, "loop.nc");
            File.WriteAllText(path, $"""
                O0001 (MACRO LOOP)
                G21 G90 G17 G54 G94
                G00 X0 Y0 Z5.
                #1 = 0
                #2 = 0.01
                WHILE [#1 LT {blocks}] DO1
                G01 X[#1 * #2] Y[[#1 MOD 100] * 0.5] F1200.
                #1 = #1 + 1
                END1
                M30

                """);
            var buffer = new byte[1 << 16];
            var best = double.MaxValue;
            var bestCpu = double.MaxValue; // CPU time: what the expansion costs when the cores are shared
            long lines = 0;
            for (var run = 0; run < 3; run++)
            {
                var before = GC.GetAllocatedBytesForCurrentThread();
                var cpu = Process.GetCurrentProcess().TotalProcessorTime;
                var sw = Stopwatch.StartNew();
                var e = new MacroExpander(path, new ExpansionOptions { Dialect = MacroDialect.Fanuc });
                using (var s = new ExpandedStream(e))
                {
                    while (s.Read(buffer) > 0)
                    {
                    }
                }

                sw.Stop();
                var cpuSeconds = (Process.GetCurrentProcess().TotalProcessorTime - cpu).TotalSeconds;
                bestCpu = Math.Min(bestCpu, cpuSeconds);
                if (e.Error != null)
                {
                    Console.Error.WriteLine(e.Error.Format());
                    return 1;
                }

                lines = e.ExpandedLines;
                best = Math.Min(best, sw.Elapsed.TotalSeconds);
                Console.WriteLine($"run {run + 1}: {lines} lines in {sw.Elapsed.TotalSeconds:F3} s wall = {lines / sw.Elapsed.TotalSeconds / 1e6:F2}M lines/s, {cpuSeconds:F3} s CPU = {lines / cpuSeconds / 1e6:F2}M lines/s, {(GC.GetAllocatedBytesForCurrentThread() - before) / 1e6:F1} MB allocated");
            }

            Console.WriteLine($"macro loop: {blocks} blocks ({lines} expanded lines), best {best:F3} s wall = {lines / best / 1e6:F2}M lines/s, best {bestCpu:F3} s CPU = {lines / bestCpu / 1e6:F2}M lines/s; peak working set {Process.GetCurrentProcess().PeakWorkingSet64 / 1e6:F0} MB");

            // Expanded and checked together: what `check` does with such a program.
            var swc = Stopwatch.StartNew();
            var summary = new Checker(MachineProfile.Default).CheckFile(path, _ => { });
            Console.WriteLine($"check through the expansion: {summary.Blocks} blocks in {swc.Elapsed.TotalSeconds:F3} s, {summary.Errors} errors");

            if (args.Length > 1 && File.Exists(args[1]))
            {
                // The look for macros in a plain program (the only cost expansion adds to its check).
                for (var run = 0; run < 3; run++)
                {
                    var cpu = Process.GetCurrentProcess().TotalProcessorTime;
                    var needs = MacroExpander.Needs(args[1], MacroDialect.Fanuc);
                    var look = (Process.GetCurrentProcess().TotalProcessorTime - cpu).TotalSeconds;
                    cpu = Process.GetCurrentProcess().TotalProcessorTime;
                    var plain = new Checker(MachineProfile.Default).CheckFile(args[1], _ => { });
                    var whole = (Process.GetCurrentProcess().TotalProcessorTime - cpu).TotalSeconds;
                    Console.WriteLine($"plain {Path.GetFileName(args[1])}: look for macros {look * 1000:F1} ms CPU (needs: {needs}); whole check {whole * 1000:F0} ms CPU ({plain.Blocks} blocks), the look {100 * look / whole:F1} % of it");
                }
            }

            return 0;
        }
        finally
        {
            Directory.Delete(dir, recursive: true);
        }
    }
}
