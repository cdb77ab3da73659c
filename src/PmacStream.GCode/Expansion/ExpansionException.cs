namespace PmacStream.GCode.Expansion;

/// <summary>The codes of the expansion's refusals (each one stops the expansion: nothing after it is produced).</summary>
public static class ExpansionCodes
{
    /// <summary>A macro or o-word statement the expander cannot read.</summary>
    public const string Syntax = "E150";

    /// <summary>A called subprogram or macro that is in no file searched.</summary>
    public const string NotFound = "E151";

    /// <summary>A loop that goes round more often than the limit (an endless loop).</summary>
    public const string LoopLimit = "E152";

    /// <summary>Calls nested deeper than the limit (recursion without an end).</summary>
    public const string DepthLimit = "E153";

    /// <summary>The expansion would be longer than the limit.</summary>
    public const string SizeLimit = "E154";

    /// <summary>A variable only the machine knows at run time (probe results, inputs, clocks), or one the host cannot set.</summary>
    public const string MachineOnly = "E155";

    /// <summary><c>#3000</c>: the program raises an alarm.</summary>
    public const string Alarm = "E156";

    /// <summary>Flow that does not match (END without DO, ENDSUB outside a call, a subprogram without M99 ...).</summary>
    public const string Flow = "E157";

    /// <summary>A value that cannot be computed (division by zero, an undefined named parameter ...).</summary>
    public const string Value = "E158";

    /// <summary>All of them.</summary>
    public static readonly IReadOnlyList<string> All = [Syntax, NotFound, LoopLimit, DepthLimit, SizeLimit, MachineOnly, Alarm, Flow, Value];
}

/// <summary>The expansion refused the program at a source location (which may be in a subprogram file).</summary>
public sealed class ExpansionException(string code, string file, int line, int column, string message, string? context = null)
    : Exception(message)
{
    /// <summary>The refusal's code (<see cref="ExpansionCodes"/>).</summary>
    public string Code { get; } = code;

    /// <summary>The file holding the line.</summary>
    public string File { get; } = file;

    /// <summary>1-based line in <see cref="File"/>.</summary>
    public int Line { get; } = line;

    /// <summary>1-based column.</summary>
    public int Column { get; } = column;

    /// <summary>The main program's line the refused line runs for (its outermost call), 0 when it is in the main program.</summary>
    public int MainLine { get; init; }

    /// <summary>How the line was reached (the calls and iterations), empty in the main program outside loops.</summary>
    public string Context { get; } = context ?? string.Empty;

    /// <summary><c>FILE:LINE:COL: error CODE: message</c>.</summary>
    public string Format() => $"{File}:{Line}:{Column}: error {Code}: {Message}{(Context.Length > 0 ? $" ({Context})" : string.Empty)}";
}
