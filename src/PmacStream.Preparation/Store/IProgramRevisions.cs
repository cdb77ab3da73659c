using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>
/// The program library of a store, whatever its engine (<see cref="ProgramStore"/> on SQLite, <see cref="PgProgramStore"/>
/// on PostgreSQL): revisions keyed by SHA-256 and profile, each with its decoded blocks, diagnostics and exact source.
/// </summary>
public interface IProgramRevisions : IDisposable
{
    /// <summary>Checks a file and stores it as a revision in the same pass (or returns the stored one with the same content and profile).</summary>
    ProgramImport ImportRevision(string file, MachineProfile profile, Action<Diagnostic>? onDiagnostic = null, CancellationToken cancellationToken = default);

    /// <summary>Program revisions, newest first.</summary>
    IReadOnlyList<ProgramInfo> ListRevisions();

    /// <summary>The revision with this content under this profile, or null (a file streamed again need not be imported again).</summary>
    ProgramInfo? FindRevision(string sha256, string profile) =>
        ListRevisions().FirstOrDefault(p => string.Equals(p.Sha256, sha256, StringComparison.OrdinalIgnoreCase) && p.Profile == profile);

    /// <summary>A stored program by id, or null.</summary>
    ProgramInfo? GetProgram(long id);

    /// <summary>The stored diagnostics of a program in line order.</summary>
    IReadOnlyList<Diagnostic> GetDiagnostics(long programId);

    /// <summary>Writes a revision's exact source bytes; false when it has none.</summary>
    bool ExportSource(long programId, Stream output);

    /// <summary>Deletes a program with its blocks, diagnostics and source.</summary>
    void DeleteProgram(long programId);

    /// <summary>The first block at or after a source line, with its modal state as the interpreter had it, or null.</summary>
    DecodedBlock? GetBlockAtOrAfterLine(long programId, int line);

    /// <summary>
    /// Where a start at <paramref name="line"/> begins (the first motion block at or after it), the block before that
    /// one, and the stored execution state in force there (null when the revision was stored without one); null when
    /// no motion block follows the line.
    /// </summary>
    StoredStart? GetStart(long programId, int line);

    /// <summary>Whether a block starting with <c>/</c> (block delete) is stored at or before <paramref name="line"/>.</summary>
    bool HasBlockDeleteBlock(long programId, int line);

    /// <summary>
    /// The stored blocks of source lines <paramref name="fromLine"/>..<paramref name="toLine"/> in program order, each
    /// with its cycle holes (null for other blocks, and for cycle blocks of revisions stored before schema 9): the
    /// preview and selected-block execution read these instead of the file. Streams rows; enumerate it to the end
    /// (or dispose the enumerator) before the next call on this store.
    /// </summary>
    IEnumerable<StoredBlock> ReadStoredBlocks(long programId, int fromLine = 0, int toLine = int.MaxValue);

    /// <summary>
    /// The stored moves (blocks with a motion: moves, dwells, cycles) of source lines <paramref name="fromLine"/>..<paramref name="toLine"/>
    /// in program order, with the seconds the import's interpreter gave each (an inside corner's shortening applied) and
    /// the feed in force: a range's ETA without interpreting the source again. Streams rows, as <see cref="ReadStoredBlocks"/>.
    /// </summary>
    IEnumerable<StoredMoveTime> ReadMoveTimes(long programId, int fromLine = 0, int toLine = int.MaxValue);

    /// <summary>
    /// The source map of a revision whose program was expanded (subprograms, macros, o-words: its blocks are numbered by
    /// expanded line, as <c>M0==</c> numbers them): file, line, call stack and iteration of every expanded line. Null for a
    /// program that was not expanded, and for one imported before schema 10 (import it again).
    /// </summary>
    GCode.Expansion.ExpansionMap? ReadExpansionMap(long programId);

    /// <summary>The revision's preparation made from the inputs <paramref name="inputsKey"/> names, or null.</summary>
    StoredPreparation? FindPreparation(long programId, string inputsKey);

    /// <summary>A stored preparation's chunk files (name and bytes), in order, one row at a time.</summary>
    IEnumerable<(string Name, byte[] Data)> ReadPreparationFiles(long preparationId);

    /// <summary>
    /// Stores a split (its manifest and every chunk file of <paramref name="folder"/>) as a preparation of the revision,
    /// in one transaction; when another station stored the same inputs first, that one is kept and returned.
    /// </summary>
    StoredPreparation StorePreparation(long programId, string inputs, string folder);

    /// <summary>The revision's stored preparations, oldest first.</summary>
    IReadOnlyList<StoredPreparation> ListPreparations(long programId);
}

/// <summary>A block as stored: its decoded record, and the holes it drills when it is a cycle block.</summary>
/// <param name="Block">The block with its modal state, as the interpreter had it.</param>
/// <param name="Holes">A cycle block's holes (null for other blocks, and for cycles stored before schema 9).</param>
public readonly record struct StoredBlock(DecodedBlock Block, CycleHoles? Holes);

/// <summary>A stored move's time: what the ETA reads of a block.</summary>
/// <param name="Line">The block's source line.</param>
/// <param name="Kind">What it moves (never <see cref="MotionKind.None"/>).</param>
/// <param name="Seconds">Its time at the programmed feed (a dwell's, a cycle's holes'), as the import's interpreter decided it.</param>
/// <param name="Feed">The feed in force after the block, in program units; null when none was programmed yet.</param>
public readonly record struct StoredMoveTime(int Line, MotionKind Kind, double Seconds, double? Feed);

/// <summary>Opens a store's program library by its location.</summary>
public static class ProgramStores
{
    /// <summary>Opens (creating and migrating when needed) the program library at <paramref name="location"/>.</summary>
    public static IProgramRevisions Open(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        if (location.Engine == StoreEngine.Postgres)
        {
            return PgProgramStore.Open(location);
        }

        StoreFiles.PrepareSqlite(location.Target);
        return ProgramStore.Open(location.Target);
    }
}
