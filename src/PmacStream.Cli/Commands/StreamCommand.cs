using System.CommandLine;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream stream FILE (--sim | --tcp HOST[:PORT] | --serial DEV[,BAUD]) [--profile NAME|FILE] [--strategy ...] [--from-line N] [--feed-override PCT] [--load-library] [--force] [--yes] [--job-db PATH]`.</summary>
internal static class StreamCommand
{
    public static Command Create()
    {
        var file = new Argument<string?>("file") { Description = "G-code program to run (imported into the store first).", Arity = ArgumentArity.ZeroOrOne };
        var programId = new Option<long?>("--program") { Description = "Run the program revision with this id from the store (pmacstream programs)." };
        var strategy = new Option<string>("--strategy") { Description = "full (the default: a rotary buffer as large as the controller allows, kept full, so link stalls do not starve the motion), chunk (the paper's chunk method: the next chunk once, in the download window), pr (poll PR, top up line by line) or adaptive (time-based lead).", DefaultValueFactory = _ => "full" };
        var fromLine = new Option<int?>("--from-line") { Description = "Start at the block of this source line, with a preamble restoring modal state and a safe approach." };
        var toLine = new Option<int?>("--to-line") { Description = "Selected blocks: end after the block of this source line (a move); with --from-line A, runs lines A..B and nothing after." };
        var force = new Option<bool>("--force") { Description = "Stream even if the program has errors under the machine profile (what is not G-code is dropped, as split --force does) or uses codes the controller cannot run yet (the PMAC skips such a code and runs the rest of its block), or on a controller that runs no library or another one than the program was checked against." };
        var profile = CliProfiles.Option();
        var cmd = new Command("stream", "Check, split and stream a program to a controller or the simulator.");
        cmd.Arguments.Add(file);
        cmd.Options.Add(strategy);
        cmd.Options.Add(fromLine);
        cmd.Options.Add(toLine);
        var (call, sourceFile) = AddStartChoice(cmd);
        cmd.Options.Add(force);
        cmd.Options.Add(profile);
        cmd.Options.Add(programId);
        var options = JobOptions.AddTo(cmd, JobFace.Stream);
        cmd.SetAction((parse, ct) => new StreamHandler().RunAsync(
            new StreamOptions(parse.GetValue(file), parse.GetValue(programId), parse.GetValue(strategy)!, parse.GetValue(fromLine), parse.GetValue(call), parse.GetValue(sourceFile),
                parse.GetValue(force), parse.GetValue(profile), options.Bind(parse)) { ToLine = parse.GetValue(toLine) },
            CliConsole.Of(parse),
            ct));
        return cmd;
    }

    /// <summary>The strategy named, and a start line if any is 1 or more; else a usage error.</summary>
    internal static StrategyKind Validate(string strategy, int? fromLine)
    {
        if (fromLine is < 1)
        {
            throw new CliException("--from-line must be 1 or more");
        }

        try
        {
            return StreamingStrategies.Parse(strategy);
        }
        catch (ArgumentException e)
        {
            throw new CliException(e.Message);
        }
    }

    /// <summary>A selected-block range that no program can hold (B below 1 or before A): refused before anything is prepared, exit 1.</summary>
    internal static void ValidateRange(int? fromLine, int? toLine)
    {
        if (toLine is not { } to)
        {
            return;
        }

        try
        {
            Preparation.Store.StoredRange.Basic(fromLine, to, int.MaxValue);
        }
        catch (ArgumentException e)
        {
            throw new CliException(e.Message, CliGlobals.Failed);
        }
    }

    /// <summary><c>--call N</c> and <c>--file NAME</c>: which run of a <c>--from-line</c> in an expanded program.</summary>
    private static (Option<int?> Call, Option<string?> File) AddStartChoice(Command cmd)
    {
        var call = new Option<int?>("--call") { Description = "With --from-line in a program with subprograms, macros or loops: start at the Nth time that source line runs (1-based; needed when it runs more than once)." };
        var file = new Option<string?>("--file") { Description = "With --from-line in a program with subprograms in other files: the file (O1002.nc, O1002) or called program (O1002) the line is a line of, when more than one has that line number." };
        cmd.Options.Add(call);
        cmd.Options.Add(file);
        return (call, file);
    }

    /// <summary>
    /// The line a start means: a source line of a program without subprograms or macros; in an expanded one, the
    /// expanded line of that source line's run (<c>--call</c>) in its file (<c>--file</c>), refused with the choices when ambiguous.
    /// </summary>
    internal static int StartLine(string chunkFolder, int line, int? call, string? file, CliConsole console)
    {
        if (SourceLocations.MapOf(chunkFolder) is not { } map)
        {
            return call is null && file is null ? line
                : throw new CliException("--call and --file choose a run of a line in a program with subprograms, macros or loops; this program has none: --from-line is its source line");
        }

        try
        {
            var expanded = SourceLocations.Resolve(map, line, call, file);
            console.Out.WriteLine($"starting at {map.Describe(expanded)} (expanded line {expanded})");
            return expanded;
        }
        catch (JobException e)
        {
            throw new CliException(e.Message);
        }
    }
}

/// <summary>What a <c>stream</c> command line asks for.</summary>
/// <param name="File">The program file, or null with <paramref name="ProgramId"/>.</param>
/// <param name="ProgramId">A stored revision (<c>--program</c>).</param>
/// <param name="Strategy">The streaming strategy's name.</param>
/// <param name="FromLine">The source line to start at, if any.</param>
/// <param name="Call">Which run of that line in an expanded program.</param>
/// <param name="SourceFile">Which file that line is in, in an expanded program.</param>
/// <param name="Force">Stream despite errors or codes the controller cannot run yet.</param>
/// <param name="Profile">The machine profile named, if any.</param>
/// <param name="Job">The controller, store and run settings.</param>
internal sealed record StreamOptions(string? File, long? ProgramId, string Strategy, int? FromLine, int? Call, string? SourceFile, bool Force, string? Profile, JobArgs Job)
{
    /// <summary>Selected blocks: the last source line to run (<c>--to-line</c>), if any.</summary>
    public int? ToLine { get; init; }
}

/// <summary>
/// <c>pmacstream stream</c>: checks and prepares the program through the job service, plans a start from a line,
/// takes the machine's lease, runs the job and prints its progress and count.
/// </summary>
internal sealed class StreamHandler
{
    /// <summary>Runs the command; returns the exit code.</summary>
    public async Task<int> RunAsync(StreamOptions o, CliConsole console, CancellationToken ct)
    {
        var options = o.Job;
        var target = options.Target() ?? throw new CliException("say where to stream: --sim, --tcp HOST[:PORT] or --serial DEV[,BAUD]");
        var kind = StreamCommand.Validate(o.Strategy, o.FromLine);
        StreamCommand.ValidateRange(o.FromLine, o.ToLine);

        // The tool table at the machine (the host's copy) over the profile's: G41 D1 reads tool 1's radius as set there.
        // A stored revision runs under the profile it was checked and imported with, unless --profile says otherwise.
        var location = options.Store();
        var profileName = o.Profile ?? (o.ProgramId is { } stored ? StoredPrograms.ProfileOf(location, stored) : null);
        var machine = Machine.ToolTableProfile.Apply(CliProfiles.Load(profileName), Machine.MachineTables.Load(Machine.MachineTables.DefaultPath(options.SettingsPath)));
        var settings = options.Settings();
        var feedOverride = options.FeedOverride() ?? FeedOverrides.Default;
        using var sim = new CliSimulator(options.SimSpeed(), machine.RapidRate);
        var service = new JobService(new JobServiceOptions
        {
            Store = location, Simulator = sim.OpenAsync, Rules = new Machine.MachineRules(Machine.MachineAxis.Default, !options.NoHomeCheck),
        });
        var (source, revision) = StoredPrograms.Source(location, o.File, o.ProgramId);

        // The gate: checked under the machine profile in the split's own pass and refused with every error, or with
        // every code the controller cannot run yet; nothing sent.
        // A file is imported first (found by its SHA-256 when stored already) so that its job names its revision.
        var prepared = await service.PrepareAsync(new PrepareRequest(source, settings) { Profile = machine, Force = o.Force, ProgramId = revision, Import = revision is null }, null, ct).ConfigureAwait(false);
        revision = prepared.ProgramId;
        JobConsole.WarnForced(prepared.Program.Manifest, machine, o.Force, console);
        var program = prepared.Program;
        StartPlan? plan = null;
        if (o.FromLine is { } line)
        {
            // A stored revision's start reads the block's state from the store (every stream names its revision);
            // in an expanded program the line named is found among the expanded blocks (--call, --file).
            line = StreamCommand.StartLine(program.Folder, line, o.Call, o.SourceFile, console);
            plan = service.PlanStartFor(revision, program, line, settings, prepared.Profile, ct);
            if (o.ToLine is null && !JobConsole.Confirm(plan, options.Yes, console))
            {
                return CliGlobals.UsageOrIo;
            }
        }

        if (o.ToLine is { } to && !ConfirmRange(service, (revision, program, plan, to), settings, prepared.Profile, o, console, ct))
        {
            return CliGlobals.UsageOrIo;
        }

        var continueAtStops = options.ContinueAtStops(program.Manifest, machine);
        // One station at a time drives a machine: the lease is taken before the controller hears anything.
        await using var lease = options.Lease(target);
        await using var controller = await service.ConnectAsync(target, prepared.Profile, ct).ConfigureAwait(false);
        await using var job = await service.CreateJobAsync(controller, new JobRequest(program, kind)
        {
            Settings = settings, Plan = plan, ToLine = o.ToLine, Profile = prepared.Profile, FeedOverride = feedOverride, OptionalStop = options.OptionalStop(),
            Library = options.Library(o.Force),
            ProgramId = revision, Station = options.Station(), Machine = options.Machine,
        }, ct).ConfigureAwait(false);
        lease?.SetJob(job.Id);
        program = job.Program; // a selected-block job runs its range's own chunks
        await console.Out.WriteLineAsync($"job {job.Id}: {Path.GetFileName(prepared.SourcePath)}, {program.TotalChunks} chunks, {program.Manifest.TotalMotionBlocks} blocks, strategy {kind.ToString().ToLowerInvariant()}, {controller.Description}").ConfigureAwait(false);
        return await JobConsole.RunAsync(job, sim, start: true, plan?.Line, console, ct, continueAtStops: continueAtStops).ConfigureAwait(false);
    }

    /// <summary>
    /// Selected blocks: the range checked by the job service (refused with why, exit 1, nothing sent), shown with its
    /// preamble and confirmed (<c>--yes</c>).
    /// </summary>
    private static bool ConfirmRange(JobService service, (long? Revision, ChunkedProgram Program, StartPlan? Plan, int To) range, RunSettings settings, GCode.MachineProfile profile,
        StreamOptions o, CliConsole console, CancellationToken ct)
    {
        var (revision, program, plan, to) = range;
        if (o.Call is not null || o.SourceFile is not null)
        {
            throw new CliException("--to-line runs lines of one program in order; --call and --file choose a run of a line in an expanded program, which a range cannot cut", CliGlobals.Failed);
        }

        long? blocks;
        try
        {
            blocks = service.CheckRange(revision, program, o.FromLine, to, settings, profile, ct);
        }
        catch (JobException e)
        {
            throw new CliException($"lines {o.FromLine ?? 1}..{to}: {e.Message}", CliGlobals.Failed);
        }

        console.Out.WriteLine($"selected blocks: lines {o.FromLine ?? 1}..{to}{(blocks is { } n ? $", {n} blocks" : string.Empty)}; the job ends after line {to}");
        return plan is null || JobConsole.Confirm(plan, o.Job.Yes, console);
    }
}
