namespace PmacStream.GCode.Expansion;

/// <summary>How a program's subprograms, macros and loops are expanded on the host, and the bounds of the expansion.</summary>
public sealed record ExpansionOptions
{
    /// <summary>The language of the program's subprograms and macros.</summary>
    public MacroDialect Dialect { get; init; } = MacroDialect.Fanuc;

    /// <summary>
    /// Folders searched for a subprogram the program's own file does not hold (FANUC <c>M98 P1002</c>: a file named
    /// by <see cref="ProgramFileNames"/>; RS274/NGC <c>o&lt;name&gt; call</c>: <c>name.ngc</c>). Empty: the program's own folder.
    /// </summary>
    public IReadOnlyList<string> ProgramFolders { get; init; } = [];

    /// <summary>File names a FANUC program number is looked for under (<c>{0}</c> is the number; <c>{0:D4}</c> four digits).</summary>
    public IReadOnlyList<string> ProgramFileNames { get; init; } = ["O{0:D4}.nc", "O{0}.nc", "{0:D4}.nc", "{0}.nc"];

    /// <summary>Most lines the expansion may produce (a program that would produce more is refused, E154).</summary>
    public long MaxExpandedLines { get; init; } = 200_000_000;

    /// <summary>Most times one loop (WHILE, DO, repeat, a GOTO backwards) may go round (E152): an endless loop is refused, not run.</summary>
    public long MaxLoopIterations { get; init; } = 10_000_000;

    /// <summary>Deepest nesting of calls (E153): recursion without an end is refused.</summary>
    public int MaxCallDepth { get; init; } = 32;

    /// <summary>Largest program file held for the expansion.</summary>
    public long MaxSourceBytes { get; init; } = 512L << 20;

    /// <summary>The machine (its work offsets and tool table are the system variables the host reads); null: the default profile.</summary>
    public MachineProfile? Profile { get; init; }

    /// <summary>
    /// The file keeping this machine's persistent variables (FANUC <c>#500</c>-<c>#999</c>) on the host; null: none
    /// (they start vacant and are not kept).
    /// </summary>
    public string? PersistentVariablesFile { get; init; }
}
