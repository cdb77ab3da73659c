namespace PmacStream.Plc;

/// <summary>What a ladder name is bound to.</summary>
public enum LadderSymbolKind
{
    /// <summary>A bit of the input image (a button, a limit switch, a relay contact wired to an input).</summary>
    Input,

    /// <summary>A bit of the output image (a contactor coil, a lamp, a valve).</summary>
    Output,

    /// <summary>An internal relay: a bit in controller memory that no terminal sees.</summary>
    Internal,
}

/// <summary>One declared name of a ladder program and the M-variable the generator gives it.</summary>
/// <param name="Name">The name as written (case-insensitive for lookup), e.g. <c>SB1</c>.</param>
/// <param name="Kind">Input, output or internal.</param>
/// <param name="Bit">Bit number in its image word (inputs/outputs) or running index (internals).</param>
/// <param name="MVariable">The M-variable number that holds the bit, e.g. 800 for <c>M800</c>.</param>
/// <param name="Comment">The trailing comment of the declaration, if any (copied into the generated program).</param>
/// <param name="Line">1-based source line of the declaration.</param>
public sealed record LadderSymbol(string Name, LadderSymbolKind Kind, int Bit, int MVariable, string? Comment, int Line);

/// <summary>
/// Where an I/O word and its image live. The physical word is refreshed by the controller, the image is a
/// copy in open memory (cleared at power-up/reset) that the logic reads and writes; each bit of the image gets its own
/// M-variable.
/// </summary>
/// <param name="WordAddress">Physical word address, e.g. <c>$078800</c> (without memory prefix).</param>
/// <param name="Memory">Memory space of the physical word: <c>X</c> or <c>Y</c>.</param>
/// <param name="Offset">First bit of the group within the physical word.</param>
/// <param name="Width">Number of bits in the group (1..24).</param>
/// <param name="ImageAddress">Address of the image word in Y memory, e.g. <c>$0010F0</c>.</param>
/// <param name="WordVariable">M-variable number for the physical group (seed: 1000 for inputs, 1002 for outputs).</param>
/// <param name="ImageVariable">M-variable number for the whole image (seed: 1001 / 1003).</param>
/// <param name="BitBase">M-variable number of image bit 0 (seed: 800 for inputs, 900 for outputs).</param>
public sealed record IoWordConfig(
    int WordAddress, char Memory, int Offset, int Width, int ImageAddress, int WordVariable, int ImageVariable, int BitBase)
{
    /// <summary>The default input side: physical inputs M1000, image M1001, bits M800...</summary>
    public static IoWordConfig DefaultInputs { get; } = new(0x078800, 'Y', 0, 8, 0x0010F0, 1000, 1001, 800);

    /// <summary>The default output side: physical outputs M1002, image M1003, bits M900...</summary>
    public static IoWordConfig DefaultOutputs { get; } = new(0x078801, 'Y', 0, 8, 0x0010F1, 1002, 1003, 900);
}

/// <summary>Where internal relays live: consecutive bits of open-memory words, one M-variable each.</summary>
/// <param name="Address">Y address of the first word (24 internal bits per word).</param>
/// <param name="BitBase">M-variable number of internal relay 0.</param>
public sealed record InternalConfig(int Address, int BitBase)
{
    /// <summary>Default: Y:$0010F2 onwards (after the two images), M1100 onwards.</summary>
    public static InternalConfig Default { get; } = new(0x0010F2, 1100);
}

/// <summary>
/// One rung: a coil and the contact network that drives it. Contacts in series are an AND, parallel branches an OR,
/// a normally-closed contact is a NOT.
/// </summary>
/// <param name="Coil">The coil's symbol (an output or internal relay).</param>
/// <param name="Network">The contact network.</param>
/// <param name="Line">1-based source line of the rung.</param>
public sealed record LadderRung(LadderSymbol Coil, LadderExpr Network, int Line);

/// <summary>A node of a rung's contact network.</summary>
public abstract record LadderExpr;

/// <summary>One contact: normally open (passes when the bit is 1) or normally closed (passes when it is 0).</summary>
/// <param name="Symbol">The bit the contact looks at.</param>
/// <param name="NormallyClosed">True for a normally-closed contact (<c>!NAME</c>).</param>
public sealed record LadderContact(LadderSymbol Symbol, bool NormallyClosed) : LadderExpr;

/// <summary>Contacts or groups in series: passes when all pass.</summary>
/// <param name="Items">At least two items.</param>
public sealed record LadderSeries(IReadOnlyList<LadderExpr> Items) : LadderExpr;

/// <summary>Parallel branches: passes when any branch passes.</summary>
/// <param name="Items">At least two branches.</param>
public sealed record LadderParallel(IReadOnlyList<LadderExpr> Items) : LadderExpr;

/// <summary>The inverse of a whole group (<c>!(A | B)</c>), what a normally-closed contact of an internal relay gives.</summary>
/// <param name="Inner">The negated group.</param>
public sealed record LadderNot(LadderExpr Inner) : LadderExpr;

/// <summary>A parsed, validated ladder program.</summary>
/// <param name="PlcNumber">The PLC number from a <c>plc N</c> line, or null.</param>
/// <param name="Inputs">Input word and image placement.</param>
/// <param name="Outputs">Output word and image placement.</param>
/// <param name="Internals">Internal relay placement.</param>
/// <param name="Symbols">All declared names in declaration order.</param>
/// <param name="Rungs">Rungs in source order (the scan order).</param>
public sealed record LadderProgram(
    int? PlcNumber,
    IoWordConfig Inputs,
    IoWordConfig Outputs,
    InternalConfig Internals,
    IReadOnlyList<LadderSymbol> Symbols,
    IReadOnlyList<LadderRung> Rungs)
{
    /// <summary>Finds a declared name (case-insensitive), or null.</summary>
    public LadderSymbol? Find(string name) =>
        Symbols.FirstOrDefault(s => string.Equals(s.Name, name, StringComparison.OrdinalIgnoreCase));

    /// <summary>Declared names of one kind, in declaration order.</summary>
    public IEnumerable<LadderSymbol> OfKind(LadderSymbolKind kind) => Symbols.Where(s => s.Kind == kind);
}

/// <summary>One problem found in a ladder file, with its position.</summary>
/// <param name="Line">1-based line.</param>
/// <param name="Column">1-based column.</param>
/// <param name="Message">What is wrong and what was expected.</param>
public sealed record LadderDiagnostic(int Line, int Column, string Message)
{
    /// <summary>Formats as compilers do: <c>FILE:LINE:COL: error: message</c>.</summary>
    public string Format(string file) => $"{file}:{Line}:{Column}: error: {Message}";
}

/// <summary>Thrown when a ladder file has errors; carries every error found, not just the first.</summary>
public sealed class LadderParseException : Exception
{
    /// <summary>Creates the exception from the parser's findings.</summary>
    public LadderParseException(string file, IReadOnlyList<LadderDiagnostic> diagnostics)
        : base(string.Join(Environment.NewLine, diagnostics.Select(d => d.Format(file))))
    {
        File = file;
        Diagnostics = diagnostics;
    }

    /// <summary>The file name used in messages.</summary>
    public string File { get; }

    /// <summary>All errors, in source order.</summary>
    public IReadOnlyList<LadderDiagnostic> Diagnostics { get; }
}
