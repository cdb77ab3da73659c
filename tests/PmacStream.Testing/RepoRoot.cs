namespace PmacStream.Testing;

/// <summary>
/// The repository root (the folder holding PmacStream.sln), found by walking up from the test binaries, and the
/// places the tests read from it: the samples and the shared CAM corpus beside the repository.
/// </summary>
public static class RepoRoot
{
    /// <summary>The repository root; a test run outside a checkout fails here, plainly.</summary>
    public static string Path { get; } = Find();

    /// <summary>The sample program every demo and many tests use: <c>samples/demo.nc</c>.</summary>
    public static string DemoProgram => Sample("demo.nc");

    /// <summary>The shared CAM corpus folder (<c>../shared/gcode-corpus</c>), or null when it is absent.</summary>
    public static string? Corpus
    {
        get
        {
            var dir = System.IO.Path.GetFullPath(System.IO.Path.Combine(Path, "..", "shared", "gcode-corpus"));
            return Directory.Exists(dir) ? dir : null;
        }
    }

    /// <summary>
    /// The corpus's programs (not its README or source list), in name order; null when the corpus is absent.
    /// Tests that need them call <see cref="Requires.Corpus"/>, which reports SKIPPED instead.
    /// </summary>
    public static IReadOnlyList<string>? CorpusPrograms =>
        Corpus is { } dir
            ? Directory.GetFiles(dir)
                .Where(f => !f.EndsWith(".md", StringComparison.Ordinal) && !f.EndsWith(".tsv", StringComparison.Ordinal))
                .OrderBy(f => f, StringComparer.Ordinal)
                .ToList()
            : null;

    /// <summary>A file under <c>samples/</c>, e.g. <c>Sample("plc", "motor-fwd-rev.ladder")</c>.</summary>
    public static string Sample(params string[] parts) => System.IO.Path.Combine([Path, "samples", .. parts]);

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
