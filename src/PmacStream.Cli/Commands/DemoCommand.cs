using System.CommandLine;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>
/// `pmacstream demo`: the walking skeleton. Splits samples/demo.nc with the paper's method into a temporary folder,
/// streams it with the chunk strategy (timer tick reads M0, next chunk downloaded once in the 600-700 window) into the
/// in-process simulator on a fast virtual clock, and counts executed blocks from the simulator's executed-move log.
/// </summary>
internal static class DemoCommand
{
    public static Command Create()
    {
        var cmd = new Command("demo", "Stream the sample program into the built-in simulator, with progress.");
        var common = StreamRunner.AddCommonOptions(cmd, forDemo: true);
        cmd.SetAction(async (parse, ct) =>
        {
            var settings = common.Settings(parse);
            var source = FindDemo() ?? throw new CliException("samples/demo.nc not found beside the executable or in the repository");
            var temp = Path.Combine(Path.GetTempPath(), $"pmacstream-demo-{Environment.ProcessId}-{Guid.NewGuid():N}");
            Directory.CreateDirectory(temp);
            try
            {
                var program = StreamRunner.Prepare(source, Path.Combine(temp, "chunks"), 1000);
                await using var target = await StreamTarget.OpenAsync("sim", settings.SimSpeed, ct).ConfigureAwait(false);
                Console.WriteLine($"demo: {Path.GetFileName(source)} split into {program.TotalChunks} chunks of up to 1000 lines ({program.Manifest.TotalMotionBlocks} motion blocks); simulator at {settings.SimSpeed}");
                var session = StreamRunner.NewSession(target, program, StrategyKind.Chunk, settings, null, source);
                session.EventRaised += (_, e) =>
                {
                    if (e.Kind is StreamingEventKind.ChunkDownloaded or StreamingEventKind.ChunkEntered)
                    {
                        Console.WriteLine($"  {e.Message}");
                    }
                };
                return await StreamRunner.RunAsync(session, target, null, 0, null, s => s.StartAsync(), ct, "demo", showUnderruns: false).ConfigureAwait(false);
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
        });
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
