using PmacStream.Cli;

namespace PmacStream.IntegrationTests;

/// <summary>
/// Runs <c>pmacstream ARGS</c> in the test's process: the same root command, parser, handlers and exit-code
/// convention as the binary, writing to captured writers instead of the process's standard streams. A test that
/// needs the real process (its exit code, a signal, a terminal, two stations) uses <see cref="Streaming.CliProcess"/>.
/// </summary>
internal static class CliRun
{
    /// <summary>As long as a process run may take before it is stopped (the command is cancelled, as by Ctrl-C).</summary>
    private static readonly TimeSpan Limit = TimeSpan.FromSeconds(120);

    /// <summary>Runs the command line with <paramref name="stdin"/> as its input (empty by default, never a terminal).</summary>
    public static async Task<(int Code, string Out, string Err)> InProcessAsync(string[] args, string? stdin = null)
    {
        // Synchronized: a job's events write from the streaming thread while the handler writes from its own.
        using var output = new StringWriter();
        using var error = new StringWriter();
        using var timeout = new CancellationTokenSource(Limit);
        var console = new CliConsole(TextWriter.Synchronized(output), TextWriter.Synchronized(error), new StringReader(stdin ?? string.Empty));
        var code = await CliApp.InvokeAsync(args, console, timeout.Token).ConfigureAwait(false);
        return (code, output.ToString(), error.ToString());
    }

    /// <summary>Runs the command line in process with empty input; for tests written as synchronous methods.</summary>
    public static (int Code, string Out, string Err) InProcess(params string[] args) => InProcessAsync(args).GetAwaiter().GetResult();
}
