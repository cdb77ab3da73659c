namespace PmacStream.Core.Tests.GCode;

/// <summary>The repository root (the folder holding PmacStream.sln), found by walking up from the test binaries.</summary>
internal static class RepoRoot
{
    public static string Path { get; } = Find();

    /// <summary>The shared CAM corpus next to the repository, or null when it is absent.</summary>
    public static string? Corpus
    {
        get
        {
            var dir = System.IO.Path.GetFullPath(System.IO.Path.Combine(Path, "..", "shared", "gcode-corpus"));
            return Directory.Exists(dir) ? dir : null;
        }
    }

    /// <summary>The corpus's programs (not its README or source list), in name order; null when the corpus is absent.</summary>
    public static IReadOnlyList<string>? CorpusPrograms =>
        Corpus is { } dir
            ? Directory.GetFiles(dir)
                .Where(f => !f.EndsWith(".md", StringComparison.Ordinal) && !f.EndsWith(".tsv", StringComparison.Ordinal))
                .OrderBy(f => f, StringComparer.Ordinal)
                .ToList()
            : null;

    private static string Find()
    {
        var dir = new DirectoryInfo(AppContext.BaseDirectory);
        while (dir != null && !File.Exists(System.IO.Path.Combine(dir.FullName, "PmacStream.sln")))
        {
            dir = dir.Parent;
        }

        return dir?.FullName ?? throw new InvalidOperationException("PmacStream.sln not found above " + AppContext.BaseDirectory);
    }
}
