using PmacStream.Preparation.Store;

namespace PmacStream.Streaming;

/// <summary>
/// Jobs, their checkpoints and their history, whatever the store's engine: <see cref="JobStore"/> (one SQLite file,
/// crash-safe checkpoints in its write-ahead log) or <see cref="PgJobStore"/> (a shop's PostgreSQL). Further records
/// (an alarm history) are further tables and methods beside these, in both engines' migrations.
/// </summary>
public interface IJobStore : IDisposable
{
    /// <summary>Where it is, for messages (the SQLite file, or the PostgreSQL URI without its password).</summary>
    string Path { get; }

    /// <summary>Records a new job and returns its id (see <see cref="JobStore.CreateJob"/>).</summary>
    long CreateJob(string programPath, string programSha256, string manifestPath, StrategyKind strategy, string connection, int? fromLine, string? lineProbe = "P501", string? settings = null,
        (string Source, string Identity)? profile = null, JobHistoryStart? history = null);

    /// <summary>Writes a job's checkpoint; durable ones survive a power loss.</summary>
    void SaveCheckpoint(long jobId, Checkpoint cp, bool durable, long? executed);

    /// <summary>Records how the job (re)starts.</summary>
    void RecordStart(long jobId, JobStart start);

    /// <summary>Sets the job's message.</summary>
    void SetMessage(long jobId, string message);

    /// <summary>
    /// Where the job's current line came from in an expanded program (<c>O1002 line 7, call 3 of 4 from line 12</c>);
    /// null for a program without subprograms or macros, whose lines are its source lines.
    /// </summary>
    void SetSourceLocation(long jobId, string? location);

    /// <summary>Records how a job ended.</summary>
    void RecordEnd(long jobId, string outcome, long executed, long total, int stops, int alarms);

    /// <summary>Records a resume by this process.</summary>
    void RecordResume(long jobId, string? station);

    /// <summary>A job by id, or null.</summary>
    JobRecord? Get(long id);

    /// <summary>The most recent job that has not completed, or null.</summary>
    JobRecord? LatestUnfinished();

    /// <summary>The newest job recorded for a connection, or null.</summary>
    JobRecord? Latest(string connection);

    /// <summary>All jobs, newest first.</summary>
    IReadOnlyList<JobRecord> List();

    /// <summary>A sink that writes one job's checkpoints (with the blocks executed, for the history).</summary>
    ICheckpointSink SinkFor(long jobId, Func<long?>? executed = null) => new StoreSink(this, jobId, executed);

    private sealed class StoreSink(IJobStore store, long jobId, Func<long?>? executed) : ICheckpointSink
    {
        public void Save(Checkpoint checkpoint, bool durable) => store.SaveCheckpoint(jobId, checkpoint, durable, executed?.Invoke());

        public void RecordStart(JobStart start) => store.RecordStart(jobId, start);
    }
}

/// <summary>Opens a store's jobs by its location.</summary>
public static class JobStores
{
    /// <summary>Opens (creating and migrating when needed) the jobs of the store at <paramref name="location"/>.</summary>
    /// <exception cref="JobStoreException">It cannot be opened (damaged, unreachable, no rights).</exception>
    public static IJobStore Open(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        return location.Engine == StoreEngine.Postgres ? PgJobStore.Open(location) : JobStore.Open(location.Target);
    }

    /// <summary>True when the store holds anything to read (an SQLite file that exists; a PostgreSQL database always).</summary>
    public static bool Exists(StoreLocation location)
    {
        ArgumentNullException.ThrowIfNull(location);
        return location.Engine == StoreEngine.Postgres || File.Exists(location.Target) || Directory.Exists(location.Target);
    }
}
