using System.CommandLine;
using PmacStream.Pmac;
using PmacStream.Program;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream resume [--job ID] [--job-db PATH] [--sim | --tcp HOST[:PORT] | --serial DEV[,BAUD]] [--yes]`.</summary>
internal static class ResumeCommand
{
    public static Command Create()
    {
        var job = new Option<long?>("--job") { Description = "Job to resume (default: the latest unfinished one)." };
        var cmd = new Command("resume", "Continue an interrupted job from its checkpoint without losing or repeating a block.");
        cmd.Options.Add(job);
        var common = StreamRunner.AddCommonOptions(cmd);
        cmd.SetAction(async (parse, ct) =>
        {
            var settings = common.Settings(parse);
            var jobDb = settings.JobDb ?? JobStore.DefaultPath;
            if (!File.Exists(jobDb))
            {
                // Resume only reads jobs: do not leave an empty database (and its folders) behind a mistyped path.
                throw new CliException($"{jobDb}: no job database there; jobs are recorded by 'pmacstream stream'");
            }

            using var jobs = JobStore.Open(jobDb);
            var record = parse.GetValue(job) is { } id
                ? jobs.Get(id) ?? throw new CliException($"no job {id} in {jobs.Path}")
                : jobs.LatestUnfinished() ?? throw new CliException($"no unfinished job in {jobs.Path}");
            if (!record.Unfinished)
            {
                Console.WriteLine($"job {record.Id} already completed");
                return CliGlobals.Ok;
            }

            if (!File.Exists(record.ProgramPath))
            {
                throw new CliException($"job {record.Id}: the program {record.ProgramPath} is gone", CliGlobals.Failed);
            }

            if (!string.Equals(StreamRunner.Sha256Of(record.ProgramPath), record.ProgramSha256, StringComparison.OrdinalIgnoreCase))
            {
                throw new CliException($"job {record.Id}: {record.ProgramPath} changed since the job started (SHA-256 differs); refusing to resume. Start it again with pmacstream stream.", CliGlobals.Failed);
            }

            var folder = Path.GetDirectoryName(record.ManifestPath)!;
            var program = StreamRunner.Prepare(record.ProgramPath, folder, 1000);
            if (!string.Equals(program.Manifest.SourceSha256, record.ProgramSha256, StringComparison.OrdinalIgnoreCase))
            {
                throw new CliException($"job {record.Id}: the split in {folder} does not match the program", CliGlobals.Failed);
            }

            var spec = common.Target(parse) ?? record.Connection;
            await using var target = await StreamTarget.OpenAsync(spec, settings.SimSpeed, ct).ConfigureAwait(false);
            var session = StreamRunner.NewSession(target, program, record.Strategy, settings, jobs.SinkFor(record.Id), record.ProgramPath);
            var cp = record.Checkpoint;
            Console.WriteLine($"job {record.Id}: {Path.GetFileName(record.ProgramPath)}, last executed line {cp?.LastExecutedLine ?? 0}, chunk {cp?.CurrentChunk ?? 1} of {program.TotalChunks}, {record.Strategy.ToString().ToLowerInvariant()}, {target.Connection.Description}");

            int? restartLine = null;
            if (cp is not null && target.Sim is null)
            {
                try
                {
                    if (cp is { Loaded: false, Started: false })
                    {
                        Console.WriteLine($"the start broke off while loading the buffer (nothing ran): clearing and loading it again{(record.FromLine is { } from ? $" at line {from}" : string.Empty)}");
                        foreach (var l in record.Preamble ?? [])
                        {
                            Console.WriteLine("  " + l);
                        }
                    }

                    // From the record: its line probe, and a start that broke off while loading is loaded again.
                    await session.ResumeAsync(record, ct).ConfigureAwait(false);
                    Console.WriteLine($"controller still holds the job at line {session.Status.CurrentLine}; continuing at {session.Next}");
                    var reloaded = cp is { Loaded: false, Started: false } ? record.FromLine : null;
                    return await StreamRunner.RunAsync(session, target, jobs, record.Id, reloaded, _ => Task.CompletedTask, ct, "resume").ConfigureAwait(false);
                }
                catch (InvalidOperationException e)
                {
                    Console.WriteLine(e.Message);
                    restartLine = cp.LastExecutedLine;
                }
                catch (Exception e) when (e is PmacLinkException or PmacErrorException)
                {
                    throw new CliException($"cannot resume job {record.Id}: {e.Message}", CliGlobals.Failed);
                }
            }
            else if (cp is not null)
            {
                // A fresh simulator never holds the job: restart at the block that was executing.
                restartLine = cp.LastExecutedLine;
            }

            restartLine = restartLine is > 0 ? restartLine : record.FromLine;
            StartPlan? plan = null;
            if (restartLine is { } line)
            {
                Console.WriteLine($"restarting at the block of line {line} (re-runs the block that was executing from its start)");
                plan = StreamRunner.PlanStart(record.ProgramPath, program, line, settings);
                if (plan is null)
                {
                    return CliGlobals.UsageOrIo;
                }
            }

            return await StreamRunner.RunAsync(session, target, jobs, record.Id, plan?.Line, s => s.StartAsync(plan?.Line, plan?.PmacLines, ct), ct, "resume").ConfigureAwait(false);
        });
        return cmd;
    }
}
