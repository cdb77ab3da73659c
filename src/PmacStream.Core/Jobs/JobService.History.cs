using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>A job of the store's history, as <c>pmacstream jobs --json</c> prints it.</summary>
/// <param name="Id">The job's id.</param>
/// <param name="ProgramId">The program revision it ran, or null (a job of an older version, or a file not stored).</param>
/// <param name="Program">The program file it ran.</param>
/// <param name="Station">The station that ran it, or null.</param>
/// <param name="Machine">The machine (its name, else its connection).</param>
/// <param name="Started">When it started.</param>
/// <param name="Ended">When it ended, or null.</param>
/// <param name="Outcome"><c>running</c>, <c>completed</c>, <c>aborted</c>, <c>interrupted</c> or <c>alarm</c>.</param>
/// <param name="BlocksExecuted">Blocks executed.</param>
/// <param name="BlocksTotal">Blocks in the program, or null when not recorded.</param>
public sealed record JobHistoryView(long Id, long? ProgramId, string Program, string? Station, string Machine, DateTimeOffset Started, DateTimeOffset? Ended, string Outcome, long BlocksExecuted, long? BlocksTotal);

/// <summary>A program revision of the store, as <c>pmacstream programs list --json</c> prints it.</summary>
/// <param name="Id">The revision's id (what <c>stream --program ID</c> takes).</param>
/// <param name="Name">Its name (the file it was imported from).</param>
/// <param name="Sha256">The SHA-256 of its source.</param>
/// <param name="Profile">The machine profile it was checked under.</param>
/// <param name="Blocks">Blocks.</param>
/// <param name="Errors">Errors the check found.</param>
/// <param name="Warnings">Warnings the check found.</param>
/// <param name="Imported">When it was imported.</param>
public sealed record StoredProgramView(long Id, string Name, string Sha256, string Profile, long Blocks, int Errors, int Warnings, DateTimeOffset Imported);

/// <summary>The job history and the program library of the store, for a screen (the HMI): views, never SQL.</summary>
public sealed partial class JobService
{
    /// <summary>Where the store is, for a screen (never its password).</summary>
    public string StoreDisplay => Store.Display;

    /// <summary>Every job of the store, newest first (what <c>jobs --json</c> lists).</summary>
    public IReadOnlyList<JobHistoryView> JobHistory() =>
        ListJobs().Select(j => new JobHistoryView(j.Id, j.History.ProgramId, j.ProgramPath, j.History.Station, j.History.Machine ?? j.Connection, j.Created, j.History.Ended,
            j.Outcome, j.History.BlocksExecuted ?? 0, j.History.BlocksTotal)).ToList();

    /// <summary>The store's program revisions, newest first (what <c>programs list --json</c> lists); empty before the store exists.</summary>
    public IReadOnlyList<StoredProgramView> StoredPrograms()
    {
        if (!JobStores.Exists(Store))
        {
            return [];
        }

        using var store = ProgramStores.Open(Store);
        return store.ListRevisions().Select(p => new StoredProgramView(p.Id, p.Name ?? Path.GetFileName(p.Path), p.Sha256, p.Profile, p.Blocks, p.Errors, p.Warnings, p.Created)).ToList();
    }

    /// <summary>
    /// A stored revision's exact source as a file a screen opens and runs (as <c>stream --program ID</c> does): written
    /// from the store into the station's program cache (<c>~/.pmacstream/programs/SHA256/NAME</c>, checked against its
    /// SHA-256), and the built-in profile it was imported under (null for another, kept by name only).
    /// </summary>
    /// <exception cref="JobException">No such revision, or it has no source (stored by <c>check --db</c>), or the stored source does not match its SHA-256.</exception>
    public (string Path, string? Profile) StoredProgramFile(long id)
    {
        using var store = ProgramStores.Open(Store);
        var info = store.GetProgram(id) ?? throw new JobException($"no program {id} in {Store.Display}", JobErrorKind.BadRequest);
        var profile = MachineProfile.BuiltInNames.Contains(info.Profile, StringComparer.OrdinalIgnoreCase) ? info.Profile : null;
        var name = info.Name ?? Path.GetFileName(info.Path);
        var folder = Path.Combine(Path.GetDirectoryName(StoreLocation.DefaultSqlitePath)!, "programs", info.Sha256);
        var path = Path.Combine(folder, name);
        if (File.Exists(path) && FileHash.SameDigest(FileHash.Sha256Hex(path, CancellationToken.None), info.Sha256))
        {
            return (path, profile);
        }

        Directory.CreateDirectory(folder);
        var temp = path + "." + Environment.ProcessId.ToString(CultureInfo.InvariantCulture) + ".exporting";
        try
        {
            using (var f = new FileStream(temp, FileMode.Create, FileAccess.Write))
            {
                if (!store.ExportSource(info.Id, f))
                {
                    throw new JobException($"program {id} was stored by check --db, without its source: import it with pmacstream programs import", JobErrorKind.BadRequest);
                }
            }

            if (!FileHash.SameDigest(FileHash.Sha256Hex(temp, CancellationToken.None), info.Sha256))
            {
                throw new JobException($"program {id}: the stored source does not match its SHA-256; the store is damaged", JobErrorKind.Failed);
            }

            File.Move(temp, path, overwrite: true);
        }
        finally
        {
            File.Delete(temp);
        }

        return (path, profile);
    }
}
