using PmacStream.GCode.Expansion;

namespace PmacStream.Cli;

/// <summary>
/// The source locations of an expanded program's tracked lines on the console: <c>M0==</c> counts expanded lines,
/// and the split's <see cref="ExpansionMap.FileName"/> says where each came from (<c>O1002 line 7, call 3 of 4 from line 12</c>).
/// </summary>
internal static class CliExpansion
{
    /// <summary>The split's map, null when the program was not expanded (its lines are its source lines).</summary>
    public static ExpansionMap? Map(string chunkFolder)
    {
        var path = Path.Combine(chunkFolder, ExpansionMap.FileName);
        return File.Exists(path) ? ExpansionMap.Load(path) : null;
    }

    /// <summary>The progress text with the tracked line's source location, when the program was expanded.</summary>
    public static string Describe(string progress, long line, ExpansionMap? map) => map == null || line <= 0 ? progress : $"{progress} [{map.Describe(line)}]";

    /// <summary>" (O1002 line 7, ...)" for an expanded program's line, empty otherwise.</summary>
    public static string Where(long line, ExpansionMap? map) => map == null || line <= 0 ? string.Empty : $" ({map.Describe(line)})";
}
