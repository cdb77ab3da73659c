using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Jobs;

/// <summary>A stored revision's decoded blocks, for a face that draws them (the HMI's preview of a program opened from the store).</summary>
/// <param name="ProgramId">The revision.</param>
/// <param name="Name">Its name (the file it was imported from).</param>
/// <param name="Profile">The profile its blocks were interpreted under.</param>
/// <param name="Blocks">How many blocks a pass yields.</param>
/// <param name="Errors">Its stored error diagnostics (the first <see cref="JobService.StoredErrorsKept"/>).</param>
/// <param name="ErrorCount">How many errors its check found.</param>
/// <param name="Read">A fresh pass over its blocks in program order, each with a cycle block's holes (the store is opened for the pass and closed after it).</param>
public sealed record StoredBlocksView(long ProgramId, string Name, string Profile, long Blocks, IReadOnlyList<Diagnostic> Errors, long ErrorCount,
    Func<IEnumerable<(DecodedBlock Block, CycleHoles? Holes)>> Read);

/// <summary>The stored blocks of a revision: what <c>preview --program ID</c> draws, for the HMI.</summary>
public sealed partial class JobService
{
    /// <summary>Error diagnostics a <see cref="StoredBlocksView"/> carries (the count is exact).</summary>
    public const int StoredErrorsKept = 100;

    /// <summary>
    /// The stored decoded blocks of revision <paramref name="programId"/> (<see cref="IProgramRevisions.ReadStoredBlocks"/>,
    /// the reader of <c>preview --program ID</c>): nothing of the file is read. Null when the store has no such revision
    /// or cannot be read (the caller draws the file instead; a warning says why).
    /// </summary>
    public StoredBlocksView? StoredBlocksOf(long programId)
    {
        try
        {
            using var store = ProgramStores.Open(Store);
            if (store.GetProgram(programId) is not { } info)
            {
                Log.Warning("Program {Id} is not in the store {Store:l}: its preview reads the file", programId, Store.Display);
                return null;
            }

            var errors = store.GetDiagnostics(programId).Where(d => d.Severity == Severity.Error).ToList();
            return new StoredBlocksView(programId, info.Name ?? Path.GetFileName(info.Path), info.Profile, info.Blocks,
                errors.Take(StoredErrorsKept).ToList(), Math.Max(info.Errors, errors.Count), () => ReadStored(programId));
        }
        catch (System.Data.Common.DbException e)
        {
            Log.Warning("The store {Store:l} cannot be read ({Message:l}): the preview of program {Id} reads the file", Store.Display, StoreLocation.Redact(e.Message), programId);
            return null;
        }
    }

    private IEnumerable<(DecodedBlock Block, CycleHoles? Holes)> ReadStored(long programId)
    {
        using var store = ProgramStores.Open(Store);
        foreach (var b in store.ReadStoredBlocks(programId))
        {
            yield return (b.Block, b.Holes);
        }
    }
}
