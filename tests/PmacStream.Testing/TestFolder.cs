namespace PmacStream.Testing;

/// <summary>
/// A fresh folder under the temporary directory for one test or test class (its programs, chunks and job database),
/// removed when disposed: the one temp-folder helper of the tests (<c>using var folder = new TestFolder("tag")</c> in a
/// test, a field disposed with the class when helpers write several programs).
/// </summary>
public sealed class TestFolder : IDisposable
{
    private int _folders;

    /// <summary>Creates <c>pmacstream-PREFIX-RANDOM</c> under the temporary directory.</summary>
    public TestFolder(string prefix) => Path = Directory.CreateTempSubdirectory($"pmacstream-{prefix}-").FullName;

    /// <summary>The folder.</summary>
    public string Path { get; }

    /// <summary>Creates a new, empty folder inside this one (<c>NAME-N</c>), for one more program of the same test.</summary>
    public string NewFolder(string name) =>
        Directory.CreateDirectory(System.IO.Path.Combine(Path, $"{name}-{Interlocked.Increment(ref _folders)}")).FullName;

    /// <inheritdoc />
    public void Dispose()
    {
        try
        {
            Directory.Delete(Path, true);
        }
        catch (IOException)
        {
            // A child process of the test may still hold a file open: the temporary directory is the system's to clean.
        }
    }
}
