using PmacStream.Streaming;

namespace PmacStream.Testing;

/// <summary>Checkpoints kept in memory (the last one, and how many durable writes).</summary>
public sealed class MemorySink : ICheckpointSink
{
    public Checkpoint? Last { get; private set; }

    public int Durable { get; private set; }

    public int Writes { get; private set; }

    public JobStart? Start { get; private set; }

    /// <summary>
    /// A power loss at the host: only checkpoints written durably (synchronous commit) survive, the others are lost.
    /// </summary>
    public bool DurableOnly { get; init; }

    public void RecordStart(JobStart start) => Start = start;

    /// <summary>The job record a host would read back after dying (what the job store keeps).</summary>
    public JobRecord Record() => new(1, "p.nc", string.Empty, "manifest.json", StrategyKind.Chunk, "in-process", Start?.FromLine, string.Empty, Last,
        DateTimeOffset.UnixEpoch, Start?.Preamble, Start is null ? "P501" : Start.LineProbeVariable);

    public void Save(Checkpoint checkpoint, bool durable)
    {
        if (durable || !DurableOnly)
        {
            Last = checkpoint;
        }

        Writes++;
        if (durable)
        {
            Durable++;
        }
    }
}
