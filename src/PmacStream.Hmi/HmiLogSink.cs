using System.Collections.Concurrent;
using System.Globalization;
using Serilog;
using Serilog.Configuration;
using Serilog.Core;
using Serilog.Events;

namespace PmacStream.Hmi;

/// <summary>
/// A Serilog sink for the HMI's log pane. Events arrive on any thread (the streaming session, the connection);
/// they wait in a bounded queue until the presenter's tick, on the UI thread, moves them to the view. When the
/// queue is full the oldest lines go, so a flood of Debug events can never grow memory or stall the controller link.
/// </summary>
public sealed class HmiLogSink : ILogEventSink
{
    private readonly ConcurrentQueue<string> _queue = new();
    private readonly int _capacity;
    private readonly LogEventLevel _minimum;
    private int _count;
    private long _dropped;

    /// <summary>Creates a sink that keeps at most <paramref name="capacity"/> lines between drains.</summary>
    public HmiLogSink(int capacity = 5000, LogEventLevel minimum = LogEventLevel.Information)
    {
        _capacity = Math.Max(1, capacity);
        _minimum = minimum;
    }

    /// <summary>Lines dropped because the pane was not drained in time.</summary>
    public long Dropped => Interlocked.Read(ref _dropped);

    /// <inheritdoc />
    public void Emit(LogEvent logEvent)
    {
        if (logEvent.Level < _minimum)
        {
            return;
        }

        var text = Format(logEvent);
        _queue.Enqueue(text);
        if (Interlocked.Increment(ref _count) > _capacity && _queue.TryDequeue(out _))
        {
            Interlocked.Decrement(ref _count);
            Interlocked.Increment(ref _dropped);
        }
    }

    /// <summary>Takes up to <paramref name="max"/> waiting lines, oldest first.</summary>
    public IReadOnlyList<string> Drain(int max = 500)
    {
        var lines = new List<string>();
        while (lines.Count < max && _queue.TryDequeue(out var line))
        {
            Interlocked.Decrement(ref _count);
            lines.Add(line);
        }

        return lines;
    }

    /// <summary>Moves the waiting lines to the view's log pane (nothing is set when none waits).</summary>
    public void DrainTo(IMainView view)
    {
        ArgumentNullException.ThrowIfNull(view);
        var lines = Drain();
        if (lines.Count > 0)
        {
            view.AppendLog(lines);
        }
    }

    /// <summary>One pane line: time, level, source class and the rendered message (and the exception's message).</summary>
    internal static string Format(LogEvent e)
    {
        var source = e.Properties.TryGetValue(Constants.SourceContextPropertyName, out var ctx) && ctx is ScalarValue { Value: string s }
            ? s[(s.LastIndexOf('.') + 1)..]
            : "-";
        var level = e.Level switch
        {
            LogEventLevel.Verbose => "VRB",
            LogEventLevel.Debug => "DBG",
            LogEventLevel.Information => "INF",
            LogEventLevel.Warning => "WRN",
            LogEventLevel.Error => "ERR",
            _ => "FTL",
        };
        var text = $"{e.Timestamp.ToLocalTime().ToString("HH:mm:ss.fff", CultureInfo.InvariantCulture)} {level} {source}: {e.RenderMessage(CultureInfo.InvariantCulture)}";
        return e.Exception is null ? text : $"{text} ({e.Exception.Message})";
    }
}

/// <summary>Adds <see cref="HmiLogSink"/> to a Serilog configuration.</summary>
public static class HmiLogSinkExtensions
{
    /// <summary><c>.WriteTo.Hmi(sink)</c>: forwards events to the HMI's log pane.</summary>
    public static LoggerConfiguration Hmi(this LoggerSinkConfiguration writeTo, HmiLogSink sink) => writeTo.Sink(sink);
}
