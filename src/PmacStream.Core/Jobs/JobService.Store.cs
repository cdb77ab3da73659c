using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>Execution that reads the program store: a start from a line of a stored revision.</summary>
public sealed partial class JobService
{
    private long _startsFromStore;
    private long _startFallbacks;

    /// <summary>Starts planned from the store's stored states (<see cref="PlanStartFromStore"/>) by this service.</summary>
    public long StartsFromStore => Interlocked.Read(ref _startsFromStore);

    /// <summary>Starts of a stored revision that had to re-interpret the source from the top instead (each logged as a warning with why).</summary>
    public long StartFallbacks => Interlocked.Read(ref _startFallbacks);

    /// <summary>
    /// Plans a start at the block of <paramref name="line"/> of the stored revision <paramref name="programId"/> (the
    /// program <paramref name="program"/> was split from): the modal state, offsets, shifts, tables and highest Z in
    /// force there are read from the store (<see cref="StartFromLine.Plan(IProgramRevisions, long, int, StartPlanOptions)"/>),
    /// not re-interpreted from the top, and give the same preamble <see cref="PlanStart"/> gives. The store is
    /// re-interpreted instead (a warning says why, <see cref="StartFallbacks"/> counts it) when the revision was stored
    /// before its states were, under another machine profile (another tool table or offsets), or the store cannot be read.
    /// </summary>
    /// <exception cref="JobException">No such revision, it is not the split's program, or the line has no block after it (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public StartPlan PlanStartFromStore(long programId, ChunkedProgram program, int line, RunSettings settings, MachineProfile? profile = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(program);
        ArgumentNullException.ThrowIfNull(settings);
        if (line < 1)
        {
            throw new JobException($"start line must be 1 or more (got {line})", JobErrorKind.BadRequest);
        }

        var machine = profile ?? MachineProfile.Default;
        string why;
        try
        {
            using var store = ProgramStores.Open(Store);
            var info = store.GetProgram(programId) ?? throw new JobException($"no program {programId} in {Store.Display}", JobErrorKind.BadRequest);
            if (!FileHash.SameDigest(info.Sha256, program.Manifest.SourceSha256))
            {
                throw new JobException($"program {programId} is not the program of the split in {program.Folder} (SHA-256 differs)", JobErrorKind.BadRequest);
            }

            if (info.ProfileIdentity == machine.Identity)
            {
                var plan = StartFromLine.Plan(store, programId, line, settings.ToStartPlanOptions(program.Manifest, machine));
                Interlocked.Increment(ref _startsFromStore);
                Log.Information("Start at line {Line} of program {Id}: the state of block {Block} read from the store", line, programId, plan.Line);
                return Checked(program, line, plan);
            }

            why = $"it was interpreted under {info.ProfileIdentity ?? "a profile the store did not record"}, the job runs under {machine.Identity}";
        }
        catch (ArgumentOutOfRangeException e)
        {
            throw new JobException(e.Message.Split(Environment.NewLine)[0], JobErrorKind.BadRequest, e);
        }
        catch (StoredStateMissingException e)
        {
            why = e.Message;
        }
        catch (System.Data.Common.DbException e)
        {
            why = $"the store {Store.Display} cannot be read: {StoreLocation.Redact(e.Message)}";
        }

        Interlocked.Increment(ref _startFallbacks);
        Log.Warning("Start at line {Line} of program {Id}: re-interpreting the source from the top, as {Why:l}", line, programId, why);
        return PlanStart(program, line, settings, profile, cancellationToken);
    }

    /// <summary><see cref="PlanStartFromStore"/> when the program is a stored revision, else <see cref="PlanStart"/>.</summary>
    /// <exception cref="JobException">The line is out of the program or has no block after it.</exception>
    public StartPlan PlanStartFor(long? programId, ChunkedProgram program, int line, RunSettings settings, MachineProfile? profile = null, CancellationToken cancellationToken = default) =>
        programId is { } id
            ? PlanStartFromStore(id, program, line, settings, profile, cancellationToken)
            : PlanStart(program, line, settings, profile, cancellationToken);

    /// <summary>How a job plans a start at a line of its program (the alarm's check of where the next block starts): from the store for a revision.</summary>
    private Func<int, StartPlan> PlannerOf(long? programId, ChunkedProgram program, RunSettings settings, MachineProfile profile) =>
        line =>
        {
            try
            {
                return PlanStartFor(programId, program, line, settings, profile);
            }
            catch (JobException e) when (e.Kind == JobErrorKind.BadRequest)
            {
                // No block after it (or none the split tracks): the planner's word for it, as the job expects.
                throw new ArgumentOutOfRangeException(nameof(line), e.Message);
            }
        };

    private static StartPlan Checked(ChunkedProgram program, int line, StartPlan plan) =>
        program.PositionOfBlock(plan.Line) is null
            ? throw new JobException($"line {line}: no block to start at after it", JobErrorKind.BadRequest)
            : plan;
}
