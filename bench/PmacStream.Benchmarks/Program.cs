using BenchmarkDotNet.Running;
using PmacStream.Benchmarks.Generators;

// Verbs for whole-process scripts come first; anything else goes to BenchmarkDotNet.
if (args.Length > 0 && args[0] == "gen-surfacing")
{
    if (args.Length != 3 || !long.TryParse(args[2], out var lines))
    {
        Console.Error.WriteLine("usage: gen-surfacing OUT.nc LINES");
        return 2;
    }

    var sw = System.Diagnostics.Stopwatch.StartNew();
    SurfacingGenerator.Write(args[1], lines);
    Console.WriteLine($"wrote {lines} lines, {new FileInfo(args[1]).Length} bytes to {args[1]} in {sw.Elapsed.TotalSeconds:F1} s");
    return 0;
}

if (args.Length > 0 && args[0] == "hmi-toolpath")
{
    return PmacStream.Benchmarks.Hmi.ToolpathPaneBench.Run(args[1..]);
}

if (args.Length > 1 && args[0] == "tcp-packets")
{
    return PmacStream.Benchmarks.Transport.PacketCostBench.Run(args[1..]).GetAwaiter().GetResult();
}

if (args.Length > 1 && args[0] == "host-conversion")
{
    return PmacStream.Benchmarks.Streaming.HostConversionBench.Run(args[1..]);
}

if (args.Length > 0 && args[0] == "macro-expand")
{
    return PmacStream.Benchmarks.GCode.MacroExpansionBench.Run(args[1..]);
}

if (args.Length > 0 && args[0] == "prepare-import")
{
    return PmacStream.Benchmarks.Store.PrepareImportBench.Run(args[1..]);
}

if (args.Length > 0 && args[0] == "stream-bench")
{
    return PmacStream.Benchmarks.Streaming.StreamBench.Run(args[1..]);
}

BenchmarkSwitcher.FromAssembly(typeof(SurfacingGenerator).Assembly).Run(args);
return 0;
