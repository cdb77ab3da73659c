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
    private long _preparationsReused;
    private long _preparationsStored;
    private long _importedInSplitPass;

    /// <summary>Preparations taken from the store as they were (nothing split) by this service.</summary>
    public long PreparationsReused => Interlocked.Read(ref _preparationsReused);

    /// <summary>Revisions split by this service and stored as a new preparation (a first run, or other inputs than every stored one).</summary>
    public long PreparationsStored => Interlocked.Read(ref _preparationsStored);

    /// <summary>Files checked, stored as a revision and split in one pass by this service (<see cref="Splitter.SplitAndImport"/>).</summary>
    public long ImportedInSplitPass => Interlocked.Read(ref _importedInSplitPass);

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

    /// <summary>
    /// Prepares a stored revision with the preparation stored with it when one was made from the same inputs
    /// (<see cref="PreparationInputs.Of"/>: the chunk shape, the profile with the machine's tool table, force, the
    /// splitter's version): its chunk files are written from the store into <paramref name="outDir"/> unless that folder
    /// holds them already, and nothing is split. Else the revision is split and the result stored as another
    /// preparation. Null (the caller prepares beside the file, as for a file) when the program expands subprograms or
    /// macros (its split reads other files and the persistent variables, which the key cannot name) or the store
    /// cannot be used (a warning says why).
    /// </summary>
    private PreparedProgram? PrepareStored(long programId, PrepareRequest request, string source, SplitOptions options, string outDir,
        IProgress<SplitProgress>? progress, CancellationToken cancellationToken)
    {
        if (GCode.Expansion.ProgramExpansion.Applies(source, request.Profile))
        {
            Log.Information("Program {Id}: its split reads subprogram files and persistent variables; prepared beside {Source:l}, not stored", programId, source);
            return null;
        }

        try
        {
            using var store = ProgramStores.Open(Store);
            var info = store.GetProgram(programId) ?? throw new JobException($"no program {programId} in {Store.Display}", JobErrorKind.BadRequest);
            if (!FileHash.SameDigest(info.Sha256, FileHash.Sha256Hex(source, cancellationToken)))
            {
                throw new JobException($"{source} is not program {programId} (SHA-256 differs)", JobErrorKind.BadRequest);
            }

            var inputs = PreparationInputs.Of(info.Sha256, options);
            if (store.FindPreparation(programId, StoredPreparation.KeyOf(inputs)) is { } stored)
            {
                var held = PreparationFiles.Holds(outDir, stored);
                var manifest = held ? ChunkManifest.Load(Path.Combine(outDir, ChunkManifest.FileName)) : PreparationFiles.Write(stored, store.ReadPreparationFiles(stored.Id), outDir, source);
                Interlocked.Increment(ref _preparationsReused);
                Log.Information("Prepared program {Id}: its stored preparation {Preparation} (the same chunk shape and machine inputs){How:l}; nothing split",
                    programId, stored.Id, held ? $", already in {outDir}" : $", written into {outDir}");
                return new PreparedProgram(source, ChunkedProgram.FromManifest(manifest, outDir), request.Profile, true, 0);
            }

            var split = Split(request, source, options with { OutDir = outDir }, progress, cancellationToken);
            var kept = store.StorePreparation(programId, inputs, outDir);
            Interlocked.Increment(ref _preparationsStored);
            Log.Information("Prepared program {Id}: split and stored as its preparation {Preparation}", programId, kept.Id);
            return split;
        }
        catch (System.Data.Common.DbException e)
        {
            Log.Warning("Program {Id}: the store {Store:l} cannot keep its preparation ({Message:l}); prepared beside {Source:l}", programId, Store.Display, StoreLocation.Redact(e.Message), source);
            return null;
        }
    }

    /// <summary>
    /// The revision a file is under the request's profile: found by its SHA-256 (hashing is a fraction of a check, so a
    /// file streamed again is not imported again; it is then prepared from the store like any revision), else checked,
    /// decoded and stored in the same pass as its split (<see cref="Splitter.SplitAndImport"/>), which is also the
    /// preparation (returned, and stored with the revision). A program with errors is stored with its diagnostics and
    /// refused with them. A program that expands subprograms or macros is imported by itself first (its split reads its
    /// expansion, not the file), and so is one the split cannot import in its pass (block delete on and a block-delete
    /// block: the store decodes every block).
    /// </summary>
    /// <exception cref="JobException">The store cannot be read or written, or the file read (<see cref="JobErrorKind.BadRequest"/>).</exception>
    /// <exception cref="ProgramRefusedException">The program has errors (it is stored with them).</exception>
    private (long Id, PreparedProgram? Prepared) RevisionOf(PrepareRequest request, string source, SplitOptions options, string outDir,
        IProgress<SplitProgress>? progress, CancellationToken cancellationToken)
    {
        var profile = request.Profile;
        try
        {
            using var store = Imported(() => ProgramStores.Open(Store), source);
            if (Imported(() => store.FindRevision(FileHash.Sha256Hex(source, cancellationToken), profile.Name), source) is { } known)
            {
                return (known.Id, null);
            }

            if (options.CheckProfile is null)
            {
                return (ImportAlone(store, source, profile, "the split does not check it", cancellationToken), null);
            }

            return SplitImporting(store, request, source, options, outDir, progress, cancellationToken);
        }
        catch (System.Data.Common.DbException e)
        {
            // Also while the split stores the revision in its pass: nothing of the import is kept, nothing published.
            throw StoreFailed(source, e);
        }
    }

    /// <summary>A store step of an import (opening, finding, importing): a store or file failure is the request's.</summary>
    private T Imported<T>(Func<T> step, string source)
    {
        try
        {
            return step();
        }
        catch (Exception e) when (e is System.Data.Common.DbException or IOException)
        {
            throw StoreFailed(source, e);
        }
    }

    private JobException StoreFailed(string source, Exception e) =>
        new($"store {Store.Display}: cannot import {source}: {StoreLocation.Redact(e.Message)}", JobErrorKind.BadRequest, e);

    /// <summary>One pass: the split checks, decodes and stores the revision as it cuts the chunks; the preparation is stored with it.</summary>
    private (long Id, PreparedProgram? Prepared) SplitImporting(IProgramRevisions store, PrepareRequest request, string source, SplitOptions options, string outDir,
        IProgress<SplitProgress>? progress, CancellationToken cancellationToken)
    {
        SplitResult? split = null;
        ProgramRefusedException? refused = null;
        ProgramImport? imported;
        using (var import = RevisionImport.Begin(store, source, new FileInfo(source).Length, request.Profile))
        {
            try
            {
                split = Splitter.SplitAndImport(source, options with { OutDir = outDir }, import, progress, cancellationToken);
            }
            catch (SplitException e)
            {
                refused = Refused(request, source, e);
            }

            imported = import.Result;
        }

        long id;
        if (imported is not null)
        {
            id = imported.Id;
            Interlocked.Increment(ref _importedInSplitPass);
            Log.Information("Imported {Source:l} into {Store:l} as program {Id} in the same pass as its split: {Summary:l}",
                source, Store.Display, id, imported.Summary.ToString());
        }
        else
        {
            // The split ended before the file was read whole (a block too large for a chunk), or gave the import up.
            id = ImportAlone(store, source, request.Profile, "the split could not store it in its pass", cancellationToken);
        }

        if (refused is not null)
        {
            throw refused;
        }

        if (split is null)
        {
            throw new InvalidOperationException("the split ended without a result");
        }

        var inputs = PreparationInputs.Of(split.Manifest.SourceSha256, options);
        if (GCode.Expansion.ProgramExpansion.Applies(source, request.Profile))
        {
            Log.Information("Program {Id}: its split reads subprogram files and persistent variables; prepared beside {Source:l}, not stored", id, source);
        }
        else if (store.FindPreparation(id, StoredPreparation.KeyOf(inputs)) is null)
        {
            var kept = store.StorePreparation(id, inputs, outDir);
            Interlocked.Increment(ref _preparationsStored);
            Log.Information("Prepared program {Id}: split and stored as its preparation {Preparation}", id, kept.Id);
        }

        return (id, new PreparedProgram(source, ChunkedProgram.FromManifest(split.Manifest, split.OutputDirectory), request.Profile, false, split.Warnings));
    }

    /// <summary>The import by itself (a pass of its own before the split), for what one pass cannot store.</summary>
    private long ImportAlone(IProgramRevisions store, string source, MachineProfile profile, string why, CancellationToken cancellationToken)
    {
        var imported = Imported(() => store.ImportRevision(source, profile, null, cancellationToken), source);
        Log.Information("Imported {Source:l} into {Store:l} as program {Id} ({Why:l}): {Summary:l}", source, Store.Display, imported.Id, why, imported.Summary.ToString());
        return imported.Id;
    }

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
