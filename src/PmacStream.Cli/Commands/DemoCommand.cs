using System.CommandLine;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>
/// `pmacstream demo`: the walking skeleton. Prepares samples/demo.nc through the job service into a temporary folder,
/// streams it with the chunk strategy (timer tick reads M0, next chunk downloaded once in the 600-700 window) into the
/// in-process simulator on a fast virtual clock, and counts executed blocks from the simulator's executed-move log.
/// </summary>
internal static class DemoCommand
{
    public static Command Create()
    {
        var cmd = new Command("demo", "Stream the sample program into the built-in simulator, with progress.");
        var options = JobOptions.AddTo(cmd, JobFace.Demo);
        cmd.SetAction((parse, ct) => new DemoHandler().RunAsync(options.Bind(parse), CliConsole.Of(parse), ct));
        return cmd;
    }

    /// <summary>samples/demo.nc beside the executable, else in the repository (walking up to PmacStream.sln).</summary>
    internal static string? FindDemo()
    {
        var beside = Path.Combine(AppContext.BaseDirectory, "samples", "demo.nc");
        if (File.Exists(beside))
        {
            return beside;
        }

        foreach (var start in new[] { Environment.CurrentDirectory, AppContext.BaseDirectory })
        {
            for (var d = new DirectoryInfo(start); d is not null; d = d.Parent)
            {
                var candidate = Path.Combine(d.FullName, "samples", "demo.nc");
                if (File.Exists(Path.Combine(d.FullName, "PmacStream.sln")) && File.Exists(candidate))
                {
                    return candidate;
                }
            }
        }

        return null;
    }
}

/// <summary>
/// <c>pmacstream demo</c>: prepares the sample program into a temporary folder, streams it with the chunk strategy
/// into the built-in simulator, prints each chunk's download and entry, and the count.
/// </summary>
internal sealed class DemoHandler
{
    /// <summary>Runs the demo with the run settings and simulator clock of <paramref name="options"/>; returns the exit code.</summary>
    public async Task<int> RunAsync(JobArgs options, CliConsole console, CancellationToken ct)
    {
        var settings = options.Settings();
        var speed = options.SimSpeed();
        var source = DemoCommand.FindDemo() ?? throw new CliException("samples/demo.nc not found beside the executable or in the repository");
        var temp = Path.Combine(Path.GetTempPath(), $"pmacstream-demo-{Environment.ProcessId}-{Guid.NewGuid():N}");
        Directory.CreateDirectory(temp);
        try
        {
            using var sim = new CliSimulator(speed);
            var service = new JobService(new JobServiceOptions { Simulator = sim.OpenAsync });
            var prepared = await service.PrepareAsync(new PrepareRequest(source, settings) { OutDir = Path.Combine(temp, "chunks") }, null, ct).ConfigureAwait(false);
            var program = prepared.Program;
            await using var controller = await service.ConnectAsync(ConnectionSpec.Simulator, prepared.Profile, ct).ConfigureAwait(false);
            console.Out.WriteLine($"demo: {Path.GetFileName(source)} split into {program.TotalChunks} chunks of up to {settings.BlocksPerChunk} blocks ({program.Manifest.TotalMotionBlocks} motion blocks); simulator at {speed}");
            await using var job = await service.CreateJobAsync(controller, new JobRequest(program, StrategyKind.Chunk) { Settings = settings, Record = false }, ct)
                .ConfigureAwait(false);
            job.EventRaised += (_, e) =>
            {
                if (e.Kind is StreamingEventKind.ChunkDownloaded or StreamingEventKind.ChunkEntered)
                {
                    console.Out.WriteLine($"  {e.Message}");
                }
            };
            return await JobConsole.RunAsync(job, sim, start: true, null, console, ct, "demo", showUnderruns: false).ConfigureAwait(false);
        }
        finally
        {
            try
            {
                Directory.Delete(temp, true);
            }
            catch (IOException)
            {
            }
        }
    }
}
