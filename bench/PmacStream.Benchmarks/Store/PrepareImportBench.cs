using System.Diagnostics;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;

namespace PmacStream.Benchmarks.Store;

/// <summary>
/// <c>prepare-import FILE STORE one-pass|two-pass OUTDIR</c>: what <c>stream FILE</c> does before streaming a file the
/// store does not hold yet. <c>one-pass</c> is the job service's preparation with the import (check, decode, store and
/// split in one read); <c>two-pass</c> is how it was done before: <c>programs import</c>, then the preparation of that
/// revision (a second read, check and split). The whole-process script (<c>bench/scripts/one-pass-bench.sh</c>)
/// measures wall and CPU time and peak RSS around it.
/// </summary>
internal static class PrepareImportBench
{
    public static int Run(string[] args)
    {
        if (args.Length != 4 || args[2] is not ("one-pass" or "two-pass"))
        {
            Console.Error.WriteLine("usage: prepare-import FILE STORE one-pass|two-pass OUTDIR");
            return 2;
        }

        var (file, store, mode, outDir) = (args[0], StoreLocation.Parse(args[1]), args[2], args[3]);
        var service = new JobService(new JobServiceOptions { Store = store });
        var sw = Stopwatch.StartNew();
        long? id = null;
        if (mode == "two-pass")
        {
            using var programs = ProgramStores.Open(store);
            id = programs.ImportRevision(file, MachineProfile.Default).Id;
            Console.WriteLine($"imported program {id} in {sw.Elapsed.TotalSeconds:F2} s, {Cpu():F2} CPU s");
        }

        var prepared = service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = id is null, ProgramId = id, OutDir = outDir })
            .GetAwaiter().GetResult();
        Console.WriteLine($"{mode}: program {prepared.ProgramId}, {prepared.Program.TotalChunks} chunks in {sw.Elapsed.TotalSeconds:F2} s " +
                          $"(imported in the split's pass: {service.ImportedInSplitPass}, preparations stored: {service.PreparationsStored}), {Cpu():F2} CPU s");
        return 0;
    }

    private static double Cpu() => Process.GetCurrentProcess().TotalProcessorTime.TotalSeconds;
}
