using Serilog;

namespace PmacStream.Streaming;

/// <summary>
/// A session's job log: its events, logged at Information (a download in its window is logged once, by its own line)
/// and raised to the HMI and CLI, and the status message: the last notable event (fault, late download, underrun,
/// recovery, completion) or note, with what to do.
/// </summary>
internal sealed class JobLog
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StreamingSession>();

    private readonly object _source;

    /// <summary>Raises events with <paramref name="source"/> (the session) as their sender.</summary>
    public JobLog(object source) => _source = source;

    /// <summary>Raised for every event.</summary>
    public event EventHandler<StreamingEvent>? Raised;

    /// <summary>The status message.</summary>
    public string Message { get; set; } = string.Empty;

    /// <summary>Logs and raises an event of chunk <paramref name="chunk"/> while the tracking variable reads <paramref name="trackedLine"/>.</summary>
    public void Raise(StreamingEventKind kind, string message, int chunk, int trackedLine)
    {
        if (kind is StreamingEventKind.Fault or StreamingEventKind.ChunkDownloadedLate or StreamingEventKind.Underrun or StreamingEventKind.Completed
            or StreamingEventKind.Recovered or StreamingEventKind.ProgramStop)
        {
            Message = message;
        }

        if (kind != StreamingEventKind.ChunkDownloaded)
        {
            Log.Information("{Kind}: {Message}", kind, message);
        }

        Raised?.Invoke(_source, new StreamingEvent(kind, message, chunk, trackedLine));
    }

    /// <summary>A download: in its window, late (the window was missed), or the rest of a chunk that broke off; <paramref name="at"/> says where execution was.</summary>
    public void Downloaded(ChunkSent sent, bool late, string at, int trackedLine)
    {
        if (!sent.Whole)
        {
            Raise(StreamingEventKind.ChunkDownloaded, $"rest of chunk {sent.Chunk} sent ({sent.Lines} lines)", sent.Chunk, trackedLine);
            return;
        }

        Log.Information("{Kind} chunk {Chunk} ({Lines} lines) at {At}", late ? "late download of" : "downloaded", sent.Chunk, sent.Lines, at);
        Raise(late ? StreamingEventKind.ChunkDownloadedLate : StreamingEventKind.ChunkDownloaded,
            late ? $"chunk {sent.Chunk} downloaded late (window missed) at {at}" : $"chunk {sent.Chunk} downloaded at {at}", sent.Chunk, trackedLine);
    }

    /// <summary>A note for the status message (logged at Information, not raised).</summary>
    public void Note(string message)
    {
        Message = message;
        Log.Information("{Message}", message);
    }
}
