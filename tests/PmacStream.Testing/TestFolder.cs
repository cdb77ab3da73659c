namespace PmacStream.Testing;

/// <summary>
/// A fresh folder under the temporary directory for one test class (its programs, chunks and job database), removed
/// when the class is disposed.
/// </summary>
public sealed class TestFolder : IDisposable
{
    /// <summary>Creates <c>pmacstream-PREFIX-RANDOM</c> under the temporary directory.</summary>
    public TestFolder(string prefix) => Path = Directory.CreateTempSubdirectory($"pmacstream-{prefix}-").FullName;

    /// <summary>The folder.</summary>
    public string Path { get; }

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
