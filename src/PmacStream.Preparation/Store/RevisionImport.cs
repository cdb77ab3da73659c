using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>
/// One program revision being stored while a check reads its file: the blocks, diagnostics, execution states and exact
/// source bytes of that one read go into one transaction, kept only by completing it (disposed before, nothing is
/// kept). <c>programs import</c> feeds one from its own check (<see cref="IProgramRevisions.ImportRevision"/>); a
/// split that imports in the same pass (<see cref="Splitter.SplitAndImport"/>) feeds one from the splitter's check,
/// so the rows are the same either way. Opened by <see cref="Begin"/> on either engine.
/// </summary>
public abstract class RevisionImport : IDisposable
{
    private bool _disposed;

    private protected RevisionImport(string file, MachineProfile profile)
    {
        File = Path.GetFullPath(file);
        Profile = profile;
    }

    /// <summary>The program file (full path), as the revision records it.</summary>
    public string File { get; }

    /// <summary>The profile the check runs under (the revision's).</summary>
    public MachineProfile Profile { get; }

    /// <summary>The revision kept, once the import completed; null before (or when it was given up).</summary>
    public ProgramImport? Result { get; private set; }

    /// <summary>The source bytes as the check reads them (<see cref="HashingReadStream"/> appends them), stored after each batch.</summary>
    internal SourcePieces Pieces { get; } = new();

    /// <summary>Where the storing side puts each batch (used on one thread at a time).</summary>
    internal abstract ImportPipeline.IBlockSink Blocks { get; }

    /// <summary>
    /// Opens an import into <paramref name="store"/> (a <see cref="ProgramStore"/> or a <see cref="PgProgramStore"/>)
    /// of <paramref name="file"/>, <paramref name="size"/> bytes, checked under <paramref name="profile"/>.
    /// </summary>
    /// <exception cref="NotSupportedException">Another implementation of <see cref="IProgramRevisions"/>.</exception>
    public static RevisionImport Begin(IProgramRevisions store, string file, long size, MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        return store switch
        {
            ProgramStore sqlite => sqlite.BeginRevision(file, size, profile),
            PgProgramStore pg => pg.BeginRevision(file, size, profile),
            _ => throw new NotSupportedException($"{store.GetType().Name} cannot take an import in the same pass as a split"),
        };
    }

    /// <summary>After each batch, on the storing thread: the source pieces read so far go in.</summary>
    internal abstract void AfterBatch();

    /// <summary>
    /// The check ended whole: the last source piece, the totals, and the commit (or, when the same content under the
    /// same profile is stored already, nothing kept and that revision's id). Call after the storing side finished.
    /// </summary>
    internal ProgramImport Complete(CheckSummary summary, string sha256)
    {
        ObjectDisposedException.ThrowIf(_disposed, this);
        Pieces.Finish();
        AfterBatch();
        return Result = CompleteCore(summary, sha256.ToLowerInvariant());
    }

    /// <summary>The engine's totals and commit, or the existing revision's id.</summary>
    private protected abstract ProgramImport CompleteCore(CheckSummary summary, string sha256);

    /// <summary>Reads <see cref="File"/> once through <paramref name="check"/> (a check feeding <see cref="Blocks"/>), hashing and keeping its bytes, and completes.</summary>
    internal ProgramImport Run(Func<Stream, CheckSummary> check)
    {
        using var fs = new FileStream(File, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        using var hashing = new HashingReadStream(fs, Pieces);
        var summary = check(hashing);
        hashing.CopyTo(Stream.Null); // the revision keeps the whole file, also what the check did not read (after a UTF-16 mark)
        return Complete(summary, hashing.HashHex());
    }

    /// <summary>Rolls back unless completed.</summary>
    public void Dispose()
    {
        if (_disposed)
        {
            return;
        }

        _disposed = true;
        DisposeCore();
        GC.SuppressFinalize(this);
    }

    /// <summary>The engine's rollback (unless committed) and release.</summary>
    private protected abstract void DisposeCore();
}
