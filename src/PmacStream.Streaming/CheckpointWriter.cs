namespace PmacStream.Streaming;

/// <summary>
/// Writes a session's checkpoints to its sink (the job store), deciding which are durable: those the caller asks for
/// (start, faults, a chunk sent, the end) and the first one in every chunk execution enters, so a crash never resumes
/// from a checkpoint of a chunk the controller has already left. A checkpoint that says what the last one written
/// said (a tick on which the tracking variable, the next line to send and the state all stood still) is not written
/// again unless asked to be durable: the record already holds it, so a resume finds the same. Without a sink
/// nothing is taken.
/// </summary>
internal sealed class CheckpointWriter
{
    private readonly ICheckpointSink? _sink;
    private readonly Func<Checkpoint> _take;
    private int _lastDurableChunk;
    private Checkpoint? _written;

    /// <summary>Writes to <paramref name="sink"/> (null: nowhere) what <paramref name="take"/> returns when asked.</summary>
    public CheckpointWriter(ICheckpointSink? sink, Func<Checkpoint> take)
    {
        _sink = sink;
        _take = take;
    }

    /// <summary>Records how the job starts, before the start sends anything (durable in the job store).</summary>
    public void RecordStart(JobStart start) => _sink?.RecordStart(start);

    /// <summary>Takes a checkpoint and writes it; <paramref name="durable"/> asks for a synchronous commit.</summary>
    public void Save(bool durable)
    {
        if (_sink is null)
        {
            return;
        }

        var checkpoint = _take();
        if (checkpoint.CurrentChunk != _lastDurableChunk)
        {
            durable = true;
            _lastDurableChunk = checkpoint.CurrentChunk;
        }

        if (!durable && _written is { } last && SamePosition(last, checkpoint))
        {
            return;
        }

        _sink.Save(checkpoint, durable);
        _written = checkpoint;
    }

    /// <summary>True when two checkpoints differ at most in when they were taken.</summary>
    internal static bool SamePosition(Checkpoint a, Checkpoint b) => a with { TimeUtc = b.TimeUtc } == b;
}
