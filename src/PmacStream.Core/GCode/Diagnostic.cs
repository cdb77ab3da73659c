namespace PmacStream.GCode;

/// <summary>How serious a finding is. Seed 002: warnings let the program run, errors stop it.</summary>
public enum Severity
{
    /// <summary>The controller can still go on; the programmer should look.</summary>
    Warning,

    /// <summary>The block cannot be run as written.</summary>
    Error,
}

/// <summary>One finding about a program: where it is, how serious, and a stable code.</summary>
/// <param name="Severity">Warning or error.</param>
/// <param name="Code">Stable code such as <c>E101</c>; see <see cref="DiagnosticCodes"/>.</param>
/// <param name="Line">1-based source line.</param>
/// <param name="Column">1-based column (bytes from the start of the line).</param>
/// <param name="Message">Human text in the chosen language.</param>
public sealed record Diagnostic(Severity Severity, string Code, int Line, int Column, string Message)
{
    /// <summary>Formats as the compilers do: <c>FILE:LINE:COL: error E104: message</c>.</summary>
    public string Format(string file) =>
        $"{file}:{Line}:{Column}: {(Severity == Severity.Error ? "error" : "warning")} {Code}: {Message}";
}

/// <summary>
/// Lexical diagnostic codes raised by <see cref="GCodeReader"/>. The checker adds the semantic ones; codes are
/// never renumbered because users grep logs and suppress by code.
/// </summary>
public static class DiagnosticCodes
{
    /// <summary>A character that cannot start a word.</summary>
    public const string IllegalCharacter = "E101";

    /// <summary>A number that does not parse (a letter with no digits, two points, ...).</summary>
    public const string MalformedNumber = "E102";

    /// <summary>A <c>(</c> comment not closed on its line.</summary>
    public const string UnclosedComment = "E103";

    /// <summary>A line longer than the reader accepts.</summary>
    public const string LineTooLong = "E114";

    /// <summary>A lowercase letter (accepted, but shop standards want upper case).</summary>
    public const string LowercaseLetter = "W004";
}
