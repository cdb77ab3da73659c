using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// What <c>stream</c> runs: a stored revision (<c>--program ID</c>), its exact source written from the store into the
/// station's program cache (<c>~/.pmacstream/programs/SHA/NAME</c>, content-addressed, so every station and store
/// agree and a resume finds it again); or a file, which the job service's preparation imports first (<c>PrepareRequest.Import</c>)
/// so its job names its revision.
/// </summary>
internal static class StoredPrograms
{
    /// <summary>The station's cache of revisions' sources.</summary>
    public static string CacheFolder => Path.Combine(Path.GetDirectoryName(StoreLocation.DefaultSqlitePath)!, "programs");

    /// <summary>The source file to prepare and the revision's id.</summary>
    public static (string Source, long? Revision) Source(StoreLocation location, string? file, long? programId)
    {
        if (file is not null && programId is not null)
        {
            throw new CliException("give a FILE or --program ID, not both");
        }

        if (programId is { } id)
        {
            using var store = ProgramsCommand.OpenStore(location);
            var info = store.GetProgram(id) ?? throw new CliException($"no program {id} in {location.Display}");
            return (Materialize(store, info), id);
        }

        if (file is null)
        {
            throw new CliException("say what to run: a FILE or --program ID");
        }

        // A file is found in the store, or imported into it, by the job service's preparation (PrepareRequest.Import).
        return (file, null);
    }

    /// <summary>
    /// The built-in profile a revision was imported with, or null (the default) when it was another (a profile file,
    /// which the store keeps by name only) or the revision is not there (<see cref="Source"/> says so).
    /// </summary>
    public static string? ProfileOf(StoreLocation location, long programId)
    {
        using var store = ProgramsCommand.OpenStore(location);
        return store.GetProgram(programId)?.Profile is { } name && MachineProfile.BuiltInNames.Contains(name, StringComparer.OrdinalIgnoreCase) ? name : null;
    }

    /// <summary>The revision's source in the station's cache (written from the store when missing or not its bytes).</summary>
    internal static string Materialize(IProgramRevisions store, ProgramInfo info)
    {
        var name = info.Name ?? Path.GetFileName(info.Path);
        var folder = Path.Combine(CacheFolder, info.Sha256);
        var path = Path.Combine(folder, name);
        if (File.Exists(path) && FileHash.SameDigest(FileHash.Sha256Hex(path, CancellationToken.None), info.Sha256))
        {
            return path;
        }

        Directory.CreateDirectory(folder);
        var temp = path + "." + Environment.ProcessId.ToString(CultureInfo.InvariantCulture) + ".exporting";
        try
        {
            using (var f = new FileStream(temp, FileMode.Create, FileAccess.Write))
            {
                if (!store.ExportSource(info.Id, f))
                {
                    throw new CliException($"program {info.Id} was stored by check --db, without its source: import it with pmacstream programs import");
                }
            }

            if (!FileHash.SameDigest(FileHash.Sha256Hex(temp, CancellationToken.None), info.Sha256))
            {
                throw new CliException($"program {info.Id}: the stored source does not match its SHA-256; the store is damaged");
            }

            File.Move(temp, path, overwrite: true);
        }
        finally
        {
            File.Delete(temp);
        }

        return path;
    }
}
