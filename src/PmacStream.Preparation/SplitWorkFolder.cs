using Serilog;

namespace PmacStream.Preparation;

/// <summary>
/// The hidden folder a split is written in (<c>.NAME.tmp-GUID</c> beside the output folder) before it is renamed into
/// place, with a lock file (<c>.NAME.tmp-GUID.lock</c>, held open exclusively) that says a live split owns it. A split
/// that is killed (SIGKILL, a crash, power loss) cannot delete its folder; the next split of the same output folder
/// removes every such folder whose lock no live process holds, and the old split a killed swap left aside.
/// </summary>
internal sealed class SplitWorkFolder : IDisposable
{
    // A folder without a lock file was left by a version without locks; one this old is no one's work any more.
    private static readonly TimeSpan UnlockedAge = TimeSpan.FromMinutes(1);
    private static readonly ILogger Log = Serilog.Log.ForContext<SplitWorkFolder>();
    private readonly FileStream _lock;

    private SplitWorkFolder(string path, FileStream lockFile)
    {
        Path = path;
        _lock = lockFile;
    }

    /// <summary>The folder to write the split in.</summary>
    public string Path { get; }

    /// <summary>Removes what killed splits of <paramref name="outDir"/> left, then makes a new locked work folder beside it.</summary>
    public static SplitWorkFolder Create(string outDir)
    {
        var parent = System.IO.Path.GetDirectoryName(outDir) ?? throw new IOException($"{outDir}: cannot write to a root folder");
        Directory.CreateDirectory(parent);
        RemoveStale(outDir);
        var path = System.IO.Path.Combine(parent, $"{Prefix(outDir)}{Guid.NewGuid():N}");
        var lockFile = new FileStream(path + ".lock", FileMode.CreateNew, FileAccess.ReadWrite, FileShare.None, 1, FileOptions.DeleteOnClose);
        try
        {
            Directory.CreateDirectory(path);
        }
        catch
        {
            lockFile.Dispose();
            throw;
        }

        return new SplitWorkFolder(path, lockFile);
    }

    /// <summary>
    /// Deletes the work folders of <paramref name="outDir"/> no live split owns (their lock file is not held, or they
    /// have none and are old); returns how many. Folders of a split running now are left alone.
    /// </summary>
    public static int RemoveStale(string outDir)
    {
        var parent = System.IO.Path.GetDirectoryName(outDir);
        if (parent is null || !Directory.Exists(parent))
        {
            return 0;
        }

        // One owner per work folder: the folder, the old split a killed swap set aside (.old) and the lock file.
        var owners = Directory.EnumerateFileSystemEntries(parent, Prefix(outDir) + "*")
            .Select(e => e.EndsWith(".old", StringComparison.Ordinal) ? e[..^4] : e.EndsWith(".lock", StringComparison.Ordinal) ? e[..^5] : e)
            .Distinct(StringComparer.Ordinal)
            .ToList();
        var removed = 0;
        foreach (var owner in owners)
        {
            if (!Abandoned(owner))
            {
                continue;
            }

            try
            {
                foreach (var folder in new[] { owner, owner + ".old" })
                {
                    if (Directory.Exists(folder))
                    {
                        Directory.Delete(folder, recursive: true);
                        removed++;
                        Log.Information("Removed {Folder}, left by an interrupted split", folder);
                    }
                }

                File.Delete(owner + ".lock");
            }
            catch (Exception e) when (e is IOException or UnauthorizedAccessException)
            {
                Log.Warning("Could not remove {Folder}, left by an interrupted split: {Error}", owner, e.Message);
            }
        }

        return removed;
    }

    /// <summary>Releases the lock (its file is deleted with it).</summary>
    public void Dispose() => _lock.Dispose();

    private static string Prefix(string outDir) => $".{System.IO.Path.GetFileName(outDir)}.tmp-";

    private static bool Abandoned(string owner)
    {
        var lockPath = owner + ".lock";
        if (!File.Exists(lockPath))
        {
            var written = Directory.Exists(owner) ? Directory.GetLastWriteTimeUtc(owner) : Directory.GetLastWriteTimeUtc(owner + ".old");
            return DateTime.UtcNow - written > UnlockedAge;
        }

        try
        {
            // Opens only when no live process holds it (an exclusive open is an advisory lock on Linux, a share
            // lock on Windows; either way the kernel drops it when its owner dies).
            using var probe = new FileStream(lockPath, FileMode.Open, FileAccess.ReadWrite, FileShare.None);
            return true;
        }
        catch (IOException)
        {
            return false;
        }
        catch (UnauthorizedAccessException)
        {
            return false;
        }
    }
}
