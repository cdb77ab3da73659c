using PmacStream.GCode;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>
/// The interpreter's move times of the programs this host ran (for the ETA and the adaptive lead), kept per file
/// while its size and write time stay the same, so a second start or a resume does not interpret the program again.
/// </summary>
internal sealed class MoveTimeCache
{
    private readonly Dictionary<string, (long Length, DateTime Written, MoveTimeTable Table)> _tables = new(StringComparer.Ordinal);

    /// <summary>The table of <paramref name="path"/> (built now when not kept, or when the file changed).</summary>
    public MoveTimeTable Get(string path, MachineProfile profile)
    {
        var full = Path.GetFullPath(path);
        var info = new FileInfo(full);
        lock (_tables)
        {
            if (_tables.TryGetValue(full, out var kept) && kept.Length == info.Length && kept.Written == info.LastWriteTimeUtc)
            {
                return kept.Table;
            }
        }

        var table = MoveTimeTable.FromProgram(full, profile: profile);
        lock (_tables)
        {
            _tables[full] = (info.Length, info.LastWriteTimeUtc, table);
        }

        return table;
    }
}
