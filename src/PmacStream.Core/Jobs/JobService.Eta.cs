using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>The ETA's move times: a stored revision's range reads the seconds its import stored for each block.</summary>
public sealed partial class JobService
{
    /// <summary>
    /// The move times of lines <paramref name="fromLine"/>..<paramref name="toLine"/> of the stored revision
    /// <paramref name="programId"/>, read from its stored blocks (the seconds the import's interpreter gave each move,
    /// inside corners applied): the same table <see cref="MoveTimeTable.FromProgram"/> builds for those lines, without
    /// interpreting the source from the top. Null (the caller interprets the file) when the revision is not the
    /// program of <paramref name="sourceSha256"/>, was interpreted under another profile identity than
    /// <paramref name="profile"/> (another tool table changes compensated moves), holds no move there, or the store
    /// cannot be read (a warning says why).
    /// </summary>
    public MoveTimeTable? MoveTimesFromStore(long programId, string sourceSha256, int fromLine, int toLine, MachineProfile profile)
    {
        ArgumentNullException.ThrowIfNull(profile);
        try
        {
            using var store = ProgramStores.Open(Store);
            if (store.GetProgram(programId) is not { } info || !FileHash.SameDigest(info.Sha256, sourceSha256) || info.ProfileIdentity != profile.Identity)
            {
                Log.Information("Program {Id}: its stored move times are not the job's (another program or profile); the ETA interprets the file", programId);
                return null;
            }

            var table = MoveTimeTable.FromMoves(store.ReadMoveTimes(programId, fromLine, toLine).Select(m => (m.Line, m.Kind, m.Seconds, m.Feed)));
            return table.BlockCount == 0 ? null : table;
        }
        catch (System.Data.Common.DbException e)
        {
            Log.Warning("The store {Store:l} cannot be read ({Message:l}): the ETA of program {Id} interprets the file", Store.Display, StoreLocation.Redact(e.Message), programId);
            return null;
        }
    }

    /// <summary>
    /// A job's move times: a stored revision started from a line or run as a range reads them from the store (lines
    /// A..B, or A to the end); anything else, or when the store cannot serve them, interprets the source (kept per file).
    /// An expanded program's lines are expanded lines: it interprets its file as before.
    /// </summary>
    private async Task<IMoveTimes?> JobMoveTimesAsync(long? programId, ChunkedProgram program, int? fromLine, int? toLine, MachineProfile profile, CancellationToken cancellationToken)
    {
        if (programId is { } id && (fromLine is not null || toLine is not null) && SourceLocations.MapOf(program.Folder) is null
            && await Task.Run(() => MoveTimesFromStore(id, program.Manifest.SourceSha256, fromLine ?? 0, toLine ?? int.MaxValue, profile), cancellationToken).ConfigureAwait(false) is { } stored)
        {
            Log.Information("Program {Id}: the ETA of lines {From}..{To} reads {Blocks} stored move times", id, fromLine ?? 1, toLine?.ToString(System.Globalization.CultureInfo.InvariantCulture) ?? "end", stored.BlockCount);
            return stored;
        }

        return await MoveTimesAsync(program.Manifest.SourcePath, profile, cancellationToken).ConfigureAwait(false);
    }
}
