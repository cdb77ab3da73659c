namespace PmacStream.Streaming;

/// <summary>What is wrong with a job database.</summary>
public enum JobStoreProblem
{
    /// <summary>The file cannot be opened, read or written (permissions, a full disk, locked): nothing was changed.</summary>
    Unavailable,

    /// <summary>The file (or its write-ahead log) is damaged; it was moved aside, kept for inspection.</summary>
    Damaged,

    /// <summary>A job's record holds a value it cannot hold; that job cannot be resumed from the record.</summary>
    BadRecord,
}

/// <summary>
/// A job database that cannot be used as it is, with a one-line message naming the file, what is wrong and what to
/// do (never a stack trace for damaged input).
/// </summary>
public sealed class JobStoreException : Exception
{
    /// <summary>Creates the exception.</summary>
    public JobStoreException(string path, JobStoreProblem problem, string message, Exception? innerException = null)
        : base(message, innerException)
    {
        Path = path;
        Problem = problem;
    }

    /// <summary>The job database.</summary>
    public string Path { get; }

    /// <summary>What is wrong.</summary>
    public JobStoreProblem Problem { get; }

    /// <summary>Where the damaged files were moved (the database's new name), when <see cref="Problem"/> is <see cref="JobStoreProblem.Damaged"/>.</summary>
    public string? KeptAs { get; init; }
}
