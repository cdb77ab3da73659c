using System.CommandLine;
using PmacStream.Jobs;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream resume [--job ID] [--job-db PATH] [--sim | --tcp HOST[:PORT] | --serial DEV[,BAUD]] [--profile NAME|FILE] [--load-library] [--force] [--yes]`.</summary>
internal static class ResumeCommand
{
    public static Command Create()
    {
        var jobOption = new Option<long?>("--job") { Description = "Job to resume (default: the latest unfinished one)." };
        var profileOption = CliProfiles.Option();
        profileOption.Description = "Machine profile: the job's own by default (the job record keeps it); a profile other than the one the job ran under is refused.";
        var force = new Option<bool>("--force") { Description = "Resume a job whose program uses codes the controller cannot run yet, or whose split was forced past the check's errors (as stream --force started it), or on a controller that runs no library or another one than the program was checked against." };
        var cmd = new Command("resume", "Continue an interrupted job from its checkpoint without losing or repeating a block.");
        cmd.Options.Add(jobOption);
        cmd.Options.Add(profileOption);
        cmd.Options.Add(force);
        var options = JobOptions.AddTo(cmd, JobFace.Resume);
        cmd.SetAction(async (parse, ct) =>
        {
            using var sim = new CliSimulator(options.SimSpeed(parse));
            var service = new JobService(new JobServiceOptions
            {
                Store = options.Store(parse), Simulator = sim.OpenAsync, Rules = new Machine.MachineRules(Machine.MachineAxis.Default, !options.NoHomeCheck(parse)),
            });
            var record = service.FindJob(parse.GetValue(jobOption));
            if (!record.Unfinished)
            {
                Console.WriteLine($"job {record.Id} already completed");
                return CliGlobals.Ok;
            }

            var resumable = service.OpenResumable(record, ct);
            // The job's own profile, unchanged, with the tool table at the machine over it as stream read it.
            var tables = Machine.MachineTables.Load(Machine.MachineTables.DefaultPath(options.SettingsPath(parse)));
            var machine = JobService.ProfileOf(record, parse.GetValue(profileOption), p => Machine.ToolTableProfile.Apply(p, tables));
            var forced = parse.GetValue(force);
            ProgramGate.EnsureRunnable(record.ProgramPath, resumable.Program.Manifest, machine, forced, ct); // before anything reaches the controller
            JobConsole.WarnForced(resumable.Program.Manifest, machine, forced);
            var settings = options.Settings(parse, resumable.Settings); // the job's own settings unless told otherwise
            var program = resumable.Program;
            var continueAtStops = options.ContinueAtStops(parse, program.Manifest, machine);
            var target = options.Target(parse) ?? JobOptions.RecordedTarget(record.Connection);
            await using var lease = options.Lease(parse, target, record.History.Machine, record.Id); // before the controller hears anything
            await using var controller = await service.ConnectAsync(target, machine, ct).ConfigureAwait(false);
            var cp = record.Checkpoint;
            Console.WriteLine($"job {record.Id}: {Path.GetFileName(record.ProgramPath)}, last executed line {cp?.LastExecutedLine ?? 0}{CliExpansion.Where(cp?.LastExecutedLine ?? 0, CliExpansion.Map(program.Folder))}, chunk {cp?.CurrentChunk ?? 1} of {program.TotalChunks}, {record.Strategy.ToString().ToLowerInvariant()}, {controller.Description}");

            var result = await ResumeOrRestartAsync(service, controller, resumable, settings, options, parse, machine, forced, ct).ConfigureAwait(false);
            if (result.Kind == ResumeKind.Refused)
            {
                // Both positions and the choices are in the reason; name the command that starts again from a line.
                var line = result.RestartLine is { } l ? l.ToString(System.Globalization.CultureInfo.InvariantCulture) : "LINE";
                // An expanded program's line is named by its source line, run and file (what stream --from-line takes).
                var start = result.RestartLine is { } r && SourceLocations.MapOf(program.Folder) is { } map
                    ? $"{SourceLocations.StartOptions(map, r)} ({map.Describe(r)})" : $"--from-line {line}";
                throw new CliException($"{result.Reason}{Environment.NewLine}to start again from a line: pmacstream stream {record.ProgramPath} {start}", CliGlobals.Failed);
            }

            if (result.Job is not { } job)
            {
                return CliGlobals.UsageOrIo;
            }

            await using (job)
            {
                if (result.Kind == ResumeKind.Restart)
                {
                    return await JobConsole.RunAsync(job, sim, start: true, job.Plan?.Line, ct, "resume", continueAtStops: continueAtStops).ConfigureAwait(false);
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
                return await JobConsole.RunAsync(job, sim, start: false, countFrom, ct, "resume", continueAtStops: continueAtStops).ConfigureAwait(false);
            }
        });
        return cmd;
    }

    /// <summary>The service's resume; a restart is shown with its preamble and asked for (<c>--yes</c> answers).</summary>
    private static Task<ResumeResult> ResumeOrRestartAsync(JobService service, ControllerLink controller, ResumableJob resumable, RunSettings settings, JobOptions options,
        ParseResult parse, GCode.MachineProfile machine, bool forced, CancellationToken ct) =>
        service.ResumeAsync(controller, new ResumeRequest(resumable, settings, proposal =>
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
            })
        {
            FeedOverride = options.FeedOverride(parse),
            Profile = machine,
            Force = forced,
            OptionalStop = options.OptionalStop(parse),
            Library = options.Library(parse, forced),
            Station = options.Station(parse),
        }, ct);
}
