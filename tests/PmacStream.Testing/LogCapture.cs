using Serilog;
using Serilog.Core;
using Serilog.Events;
using Serilog.Formatting.Display;

namespace PmacStream.Testing;

/// <summary>
/// What a <c>pmacstream</c> process prints of its log, for a command run in the test's process: the CLI's console
/// sink shows warnings and worse on standard error, an exception with its stack trace, and in process nothing would.
/// <see cref="Install"/> makes the global logger do the same into the writer of whichever run
/// <see cref="Begin"/> named (per async flow, so a run's background work lands in its own capture).
/// </summary>
public static class LogCapture
{
    private static readonly AsyncLocal<TextWriter?> Target = new();
    private static readonly object Gate = new();
    private static bool _installed;

    /// <summary>
    /// Makes the global logger write warnings and worse, in the CLI's console format, to the capturing run. Call it
    /// before any logging type is used (a test project's module initializer): a logger taken from the silent default
    /// stays silent.
    /// </summary>
    public static void Install()
    {
        lock (Gate)
        {
            if (_installed)
            {
                return;
            }

            Log.Logger = new LoggerConfiguration().MinimumLevel.Warning().WriteTo.Sink(new Sink()).CreateLogger();
            _installed = true;
        }
    }

    /// <summary>Sends this flow's log to <paramref name="writer"/> until disposed.</summary>
    public static IDisposable Begin(TextWriter writer)
    {
        Target.Value = TextWriter.Synchronized(writer);
        return new End();
    }

    private sealed class End : IDisposable
    {
        public void Dispose() => Target.Value = null;
    }

    private sealed class Sink : ILogEventSink
    {
        // The CLI's console template (CliGlobals.ConfigureLogging).
        private readonly MessageTemplateTextFormatter _format = new("[{Timestamp:HH:mm:ss.fff} {Level:u3}] {Message:lj}{NewLine}{Exception}");

        public void Emit(LogEvent logEvent)
        {
            if (Target.Value is { } writer)
            {
                _format.Format(logEvent, writer);
            }
        }
    }
}
