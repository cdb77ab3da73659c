using System.CommandLine;
using PmacStream.Jobs;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream resume [--job ID] [--job-db PATH] [--sim | --tcp HOST[:PORT] | --serial DEV[,BAUD]] [--yes]`.</summary>
internal static class ResumeCommand
{
    public static Command Create()
    {
        var jobOption = new Option<long?>("--job") { Description = "Job to resume (default: the latest unfinished one)." };
        var cmd = new Command("resume", "Continue an interrupted job from its checkpoint without losing or repeating a block.");
        cmd.Options.Add(jobOption);
        var loadLibrary = new Option<bool>("--load-library") { Description = "Download the PROG 1000/1001 library and the machine's tables before resuming." };
        var force = new Option<bool>("--force") { Description = "Resume even if the controller runs no library or another one than the program was checked against." };
        cmd.Options.Add(loadLibrary);
        cmd.Options.Add(force);
        var options = JobOptions.AddTo(cmd, JobFace.Resume);
        cmd.SetAction(async (parse, ct) =>
        {
            using var sim = new CliSimulator(options.SimSpeed(parse));
            var service = new JobService(new JobServiceOptions { JobDatabase = options.JobDatabase(parse), Simulator = sim.OpenAsync });
            var record = service.FindJob(parse.GetValue(jobOption));
            if (!record.Unfinished)
            {
                Console.WriteLine($"job {record.Id} already completed");
                return CliGlobals.Ok;
            }

            var resumable = service.OpenResumable(record, ct);
            var settings = options.Settings(parse, resumable.Settings); // the job's own settings unless told otherwise
            var program = resumable.Program;
            var libraryPolicy = parse.GetValue(loadLibrary) ? LibraryPolicy.Load : parse.GetValue(force) ? LibraryPolicy.Force : LibraryPolicy.Verify;
            await using var controller = await service.ConnectAsync(options.Target(parse) ?? JobOptions.RecordedTarget(record.Connection), null, libraryPolicy, ct).ConfigureAwait(false);
            var cp = record.Checkpoint;
            Console.WriteLine($"job {record.Id}: {Path.GetFileName(record.ProgramPath)}, last executed line {cp?.LastExecutedLine ?? 0}, chunk {cp?.CurrentChunk ?? 1} of {program.TotalChunks}, {record.Strategy.ToString().ToLowerInvariant()}, {controller.Description}");

            var result = await service.ResumeAsync(controller, resumable, settings, proposal =>
            {
                if (proposal.Reason is { } reason)
                {
                    Console.WriteLine(reason);
                }

                if (proposal.Plan is not { } plan)
                {
                    return Task.FromResult(true);
                }

                Console.WriteLine($"restarting at the block of line {proposal.Line} (re-runs the block that was executing from its start)");
                return Task.FromResult(JobConsole.Confirm(plan, options.Yes(parse)));
            }, options.FeedOverride(parse), cancellationToken: ct).ConfigureAwait(false);
            if (result.Job is not { } job)
            {
                return CliGlobals.UsageOrIo;
            }

            await using (job)
            {
                if (result.Kind == ResumeKind.Restart)
                {
                    return await JobConsole.RunAsync(job, sim, start: true, job.Plan?.Line, ct, "resume").ConfigureAwait(false);
                }

                if (result.Kind == ResumeKind.Reloaded)
                {
                    Console.WriteLine($"the start broke off while loading the buffer (nothing ran): cleared and loaded again{(record.FromLine is { } from ? $" at line {from}" : string.Empty)}");
                    foreach (var l in record.Preamble ?? [])
                    {
                        Console.WriteLine("  " + l);
                    }
                }

                Console.WriteLine($"controller still holds the job at line {job.Status.CurrentLine}; continuing at {job.Session.Next}");
                var countFrom = result.Kind == ResumeKind.Reloaded ? record.FromLine : null;
                return await JobConsole.RunAsync(job, sim, start: false, countFrom, ct, "resume").ConfigureAwait(false);
            }
        });
        return cmd;
    }
}
