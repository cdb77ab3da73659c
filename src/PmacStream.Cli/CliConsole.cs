using System.CommandLine;
using System.Runtime.CompilerServices;

namespace PmacStream.Cli;

/// <summary>
/// Where a command handler writes and reads: the process's standard streams, or a test's writers and input, so a
/// command runs in process with its options bound into a record.
/// </summary>
/// <param name="Out">Results and progress.</param>
/// <param name="Error">Warnings, refusals and findings.</param>
/// <param name="Input">The operator's input (a confirmation, Enter at a stop); null for the process's standard input.</param>
internal sealed record CliConsole(TextWriter Out, TextWriter Error, TextReader? Input = null)
{
    // The input of an in-process run, found from its invocation (System.CommandLine's configuration carries only writers).
    private static readonly ConditionalWeakTable<InvocationConfiguration, TextReader> Inputs = new();

    /// <summary>The process's standard output and error.</summary>
    public static CliConsole Standard => new(Console.Out, Console.Error);

    /// <summary>The operator's input.</summary>
    public TextReader In => Input ?? Console.In;

    /// <summary>Whether the input is not a terminal (a test's input never is), so nobody can answer a question.</summary>
    public bool InputRedirected => Input is not null || Console.IsInputRedirected;

    /// <summary>Whether results go to the process's own standard output (which a command may buffer).</summary>
    public bool IsProcessOutput => ReferenceEquals(Out, Console.Out);

    /// <summary>Whether output goes to the process's own terminal, where a progress bar may redraw itself.</summary>
    public bool IsTerminal => IsProcessOutput && !Console.IsOutputRedirected;

    /// <summary>The invocation settings that make a parsed command write to this console.</summary>
    public InvocationConfiguration Configure(InvocationConfiguration configuration)
    {
        configuration.Output = Out;
        configuration.Error = Error;
        if (Input is not null)
        {
            Inputs.AddOrUpdate(configuration, Input);
        }

        return configuration;
    }

    /// <summary>The console a parsed command was invoked with (<see cref="Configure"/>): the process's own by default.</summary>
    public static CliConsole Of(ParseResult parse)
    {
        var c = parse.InvocationConfiguration;
        return new(c.Output, c.Error, Inputs.TryGetValue(c, out var input) ? input : null);
    }
}
