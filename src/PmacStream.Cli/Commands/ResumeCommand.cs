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
        cmd.SetAction((parse, ct) => new ResumeHandler().RunAsync(
            new ResumeOptions(parse.GetValue(jobOption), parse.GetValue(profileOption), parse.GetValue(force), options.Bind(parse)), CliConsole.Of(parse), ct));
        return cmd;
    }
}

/// <summary>What a <c>resume</c> command line asks for.</summary>
/// <param name="JobId">The job to resume, or null for the latest unfinished one.</param>
/// <param name="Profile">The machine profile named, if any (the job's own by default).</param>
/// <param name="Force">Resume despite codes the controller cannot run yet or a forced split.</param>
/// <param name="Job">The controller, store and run settings.</param>
internal sealed record ResumeOptions(long? JobId, string? Profile, bool Force, JobArgs Job);

/// <summary>
/// <c>pmacstream resume</c>: finds the job, checks its program and profile are unchanged, takes the machine's lease,
/// continues where the controller is or restarts at the checkpoint's block (asking first), and follows the job.
/// </summary>
internal sealed class ResumeHandler
{
    /// <summary>Runs the command; returns the exit code.</summary>
    public async Task<int> RunAsync(ResumeOptions o, CliConsole console, CancellationToken ct)
    {
        var options = o.Job;
        using var sim = new CliSimulator(options.SimSpeed());
        var service = new JobService(new JobServiceOptions
        {
            Store = options.Store(), Simulator = sim.OpenAsync, Rules = new Machine.MachineRules(Machine.MachineAxis.Default, !options.NoHomeCheck),
        });
        var record = service.FindJob(o.JobId);
        if (!record.Unfinished)
        {
            console.Out.WriteLine($"job {record.Id} already completed");
            return CliGlobals.Ok;
        }

        var resumable = service.OpenResumable(record, ct);
        // The job's own profile, unchanged, with the tool table at the machine over it as stream read it.
        var tables = Machine.MachineTables.Load(Machine.MachineTables.DefaultPath(options.SettingsPath));
        var machine = JobService.ProfileOf(record, o.Profile, p => Machine.ToolTableProfile.Apply(p, tables));
        var forced = o.Force;
        ProgramGate.EnsureRunnable(record.ProgramPath, resumable.Program.Manifest, machine, forced, ct); // before anything reaches the controller
        JobConsole.WarnForced(resumable.Program.Manifest, machine, forced, console);
        var settings = options.Settings(resumable.Settings); // the job's own settings unless told otherwise
        var program = resumable.Program;
        var continueAtStops = options.ContinueAtStops(program.Manifest, machine);
        var target = options.Target() ?? JobOptions.RecordedTarget(record.Connection);
        await using var lease = options.Lease(target, record.History.Machine, record.Id); // before the controller hears anything
        await using var controller = await service.ConnectAsync(target, machine, ct).ConfigureAwait(false);
        var cp = record.Checkpoint;
        console.Out.WriteLine($"job {record.Id}: {Path.GetFileName(record.ProgramPath)}, last executed line {cp?.LastExecutedLine ?? 0}{CliExpansion.Where(cp?.LastExecutedLine ?? 0, CliExpansion.Map(program.Folder))}, chunk {cp?.CurrentChunk ?? 1} of {program.TotalChunks}, {record.Strategy.ToString().ToLowerInvariant()}, {controller.Description}");

        var result = await ResumeOrRestartAsync(service, controller, resumable, settings, options, machine, forced, console, ct).ConfigureAwait(false);
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
                return await JobConsole.RunAsync(job, sim, start: true, job.Plan?.Line, console, ct, "resume", continueAtStops: continueAtStops).ConfigureAwait(false);
            }

            if (result.Kind == ResumeKind.Reloaded)
            {
                console.Out.WriteLine($"the start broke off while loading the buffer (nothing ran): cleared and loaded again{(record.FromLine is { } from ? $" at line {from}" : string.Empty)}");
                foreach (var l in record.Preamble ?? [])
                {
                    console.Out.WriteLine("  " + l);
                }
            }

            console.Out.WriteLine($"controller still holds the job at line {job.Status.CurrentLine}; continuing at {job.Session.Next}");
            var countFrom = result.Kind == ResumeKind.Reloaded ? record.FromLine : null;
            return await JobConsole.RunAsync(job, sim, start: false, countFrom, console, ct, "resume", continueAtStops: continueAtStops).ConfigureAwait(false);
        }
    }

    /// <summary>The service's resume; a restart is shown with its preamble and asked for (<c>--yes</c> answers).</summary>
    private static Task<ResumeResult> ResumeOrRestartAsync(JobService service, ControllerLink controller, ResumableJob resumable, RunSettings settings, JobArgs options,
        GCode.MachineProfile machine, bool forced, CliConsole console, CancellationToken ct) =>
        service.ResumeAsync(controller, new ResumeRequest(resumable, settings, proposal =>
            {
                if (proposal.Reason is { } reason)
                {
                    console.Out.WriteLine(reason);
                }

                if (proposal.Plan is not { } plan)
                {
                    return Task.FromResult(true);
                }

                console.Out.WriteLine($"restarting at the block of line {proposal.Line} (re-runs the block that was executing from its start)");
                return Task.FromResult(JobConsole.Confirm(plan, options.Yes, console));
            })
        {
            FeedOverride = options.FeedOverride(),
            Profile = machine,
            Force = forced,
            OptionalStop = options.OptionalStop(),
            Library = options.Library(forced),
            Station = options.Station(),
        }, ct);
}
