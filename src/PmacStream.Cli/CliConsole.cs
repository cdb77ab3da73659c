namespace PmacStream.Cli;

/// <summary>
/// Where a command handler writes: the process's standard output and error, or a test's writers, so a command runs in
/// process with its options bound into a record.
/// </summary>
/// <param name="Out">Results and progress.</param>
/// <param name="Error">Warnings, refusals and findings.</param>
internal sealed record CliConsole(TextWriter Out, TextWriter Error)
{
    /// <summary>The process's standard output and error.</summary>
    public static CliConsole Standard => new(Console.Out, Console.Error);
}
