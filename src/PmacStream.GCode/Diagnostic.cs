namespace PmacStream.GCode;

/// <summary>How serious a finding is: warnings let the program run, errors stop it.</summary>
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

    /// <summary>An unknown G code (not in the machine profile).</summary>
    public const string UnknownGCode = "E104";

    /// <summary>An unknown M code (not in the machine profile).</summary>
    public const string UnknownMCode = "E105";

    /// <summary>A value out of range: negative F, S, P, H or D.</summary>
    public const string NegativeValue = "E106";

    /// <summary>A T word that is not a whole number from 0 to the profile's tool count.</summary>
    public const string ToolOutOfRange = "E107";

    /// <summary>A G or M number with decimals that the profile does not know (<c>G1.5</c>).</summary>
    public const string DecimalCode = "E108";

    /// <summary>Two codes of one modal group in one block (<c>G00 G01</c>).</summary>
    public const string ModalGroupConflict = "E109";

    /// <summary>A block with no effective function code (only N, or words that do nothing alone).</summary>
    public const string NoFunction = "E110";

    /// <summary>The same word twice in a block (two X words).</summary>
    public const string DuplicateWord = "E111";

    /// <summary>Motion without axis words where the move needs an end point (an arc with neither axis words nor I/J/K).</summary>
    public const string MotionWithoutAxes = "E112";

    /// <summary>An arc without R or an I/J/K word of its plane.</summary>
    public const string ArcWithoutCenter = "E113";

    /// <summary>An arc whose end point is not on its circle (radii differ beyond tolerance, or R shorter than half the chord).</summary>
    public const string ArcRadiusMismatch = "E115";

    /// <summary>A feed move (G01/G02/G03) before any F word, or with F0.</summary>
    public const string FeedMoveWithoutFeed = "E116";

    /// <summary>An address letter the machine does not use (not in the profile's letters).</summary>
    public const string UnsupportedLetter = "E118";

    /// <summary>The file holds no blocks at all.</summary>
    public const string EmptyProgram = "E120";

    /// <summary>A NUL byte: the file is binary, not G-code.</summary>
    public const string NulByte = "E121";

    /// <summary>The file is UTF-16 (BOM found); G-code must be ASCII or UTF-8.</summary>
    public const string Utf16File = "E122";

    /// <summary>A <c>(</c> inside a comment: comments do not nest.</summary>
    public const string NestedComment = "E123";

    /// <summary>A code without a word it cannot go without (<c>G10</c> without L, a drilling cycle without Z).</summary>
    public const string RequiredWordMissing = "E124";

    /// <summary>A word whose value the code does not take (<c>G10 L5</c>, <c>G54.1 P0</c>, a peck depth Q of 0).</summary>
    public const string ValueNotAllowed = "E125";

    /// <summary>Axis words while no motion mode is in force (after G80 where G80 ends the motion mode).</summary>
    public const string NoMotionMode = "E126";

    /// <summary>More than <see cref="FindingLimits.WordsPerLine"/> words on one line: the rest of the line is not read.</summary>
    public const string TooManyWords = "E128";

    /// <summary>A move the programmable transformations in force (G51.1, G51, G68) cannot turn into a path the controller runs: an arc under unequal scaling, an arc out of the rotation's plane.</summary>
    public const string TransformNotRunnable = "E129";

    /// <summary>
    /// A canned cycle's holes in inverse time (G93): the cycle's feed moves have no F of their own, so no time to give
    /// them (LinuxCNC's rs274ngc refuses canned cycles in inverse time as well).
    /// </summary>
    public const string CycleInInverseTime = "E130";

    /// <summary>
    /// A work offset, G52 or G92 on a rotary axis (A, B, C) that would make its program value differ from its machine
    /// value: the library's offsets are on X, Y and Z, and the host does not track rotary positions.
    /// </summary>
    public const string RotaryOffset = "E131";

    /// <summary>G41/G42 without a cutter radius: the D number (or, under RS274/NGC, the tool) is not in the profile's <c>toolRadii</c>.</summary>
    public const string NoCutterRadius = "E132";

    /// <summary>
    /// A block cutter radius compensation cannot be computed for: compensation outside the XY plane (G18, G19) or under a
    /// programmable transformation, a start on an arc, a full circle, an arc too small for the cutter inside it, a canned cycle, a reference return, a G53 move or a rotary axis while it is
    /// on, G41/G42 while it is already on, a radius change while it is on.
    /// </summary>
    public const string CompensationNotRunnable = "E133";

    /// <summary>The first XY move after G41/G42 is not longer than the cutter radius (rs274ngc refuses the same).</summary>
    public const string CompensationEntryTooShort = "E134";

    /// <summary>An inside corner under cutter radius compensation: the end of the move before it would have to move back.</summary>
    public const string CompensationConcaveCorner = "E135";

    /// <summary>A code the profile knows but the controller cannot run yet (reported at its first use).</summary>
    public const string NotYetOnController = "W006";

    /// <summary>
    /// The job gate's refusal of a <see cref="NotYetOnController"/> code (its first use) in a program a job is asked to
    /// run: the PMAC would skip the code and run the rest of the block. Only the gate reports it, never <c>check</c>.
    /// </summary>
    public const string NotRunnableInJob = "E127";

    /// <summary>Text after the <c>%</c> that ends the tape: ignored.</summary>
    public const string TextAfterTapeEnd = "W007";

    /// <summary>
    /// A centre-format arc inside the profile's arc tolerance whose radii differ by more than rounding to the program's
    /// last decimal explains: it runs (as a spiral to the programmed end), but the post or the hand that wrote it erred.
    /// </summary>
    public const string ArcRoundedOffCircle = "W008";

    /// <summary>
    /// <c>G10 L20 P</c> under a profile with FANUC's extended offsets (it set <c>G54.1 P</c>), then a move before the
    /// program selected that offset: under grbl and LinuxCNC it set <c>G54</c>.. so that the position reads as the values.
    /// </summary>
    public const string DialectG10L20 = "W009";

    /// <summary><c>G04 P</c> whose value looks written for the other unit (a fraction of a millisecond, or 100 s and more).</summary>
    public const string DialectDwellUnits = "W010";

    /// <summary><c>G10 L2 P0</c>: FANUC's external work offset, or LinuxCNC's and grbl's offset in force.</summary>
    public const string DialectG10L2P0 = "W011";

    /// <summary><c>G28</c>/<c>G30</c> without axis words (grbl and LinuxCNC move every axis, FANUC none), or in G90 through an intermediate point that moves.</summary>
    public const string DialectReturn = "W012";

    /// <summary><c>M06</c> with no T word since the last tool change: the tool of the last T, not one written after it.</summary>
    public const string DialectToolChange = "W013";

    /// <summary>A <c>G92</c> shift still in force at program end: LinuxCNC keeps it for the next program; this host's next job starts without it.</summary>
    public const string DialectG92AtEnd = "W014";

    /// <summary>The program has no program number (O word).</summary>
    public const string NoProgramNumber = "W001";

    /// <summary>A block without a sequence number in a program that numbers other blocks.</summary>
    public const string NoSequenceNumber = "W002";

    /// <summary>A word that the block's codes do not use (ignored by the controller).</summary>
    public const string UnusedWord = "W003";

    /// <summary>A code missing a word it needs where the controller can still go on (G04 without P).</summary>
    public const string MissingWord = "W005";

    /// <summary>All codes, for tests and documentation.</summary>
    public static readonly IReadOnlyList<string> All =
    [
        IllegalCharacter, MalformedNumber, UnclosedComment, UnknownGCode, UnknownMCode, NegativeValue, ToolOutOfRange,
        DecimalCode, ModalGroupConflict, NoFunction, DuplicateWord, MotionWithoutAxes, ArcWithoutCenter, LineTooLong,
        ArcRadiusMismatch, FeedMoveWithoutFeed, UnsupportedLetter, EmptyProgram, NulByte, Utf16File,
        NoProgramNumber, NoSequenceNumber, UnusedWord, LowercaseLetter, MissingWord,
        NestedComment, RequiredWordMissing, ValueNotAllowed, NoMotionMode, NotYetOnController, TextAfterTapeEnd,
        NotRunnableInJob, TooManyWords, TransformNotRunnable, CycleInInverseTime, RotaryOffset,
        NoCutterRadius, CompensationNotRunnable, CompensationEntryTooShort, CompensationConcaveCorner,
        ArcRoundedOffCircle, DialectG10L20, DialectDwellUnits, DialectG10L2P0, DialectReturn, DialectToolChange, DialectG92AtEnd,
    ];

    /// <summary>Severity of a code: <c>E</c> codes are errors, <c>W</c> codes warnings.</summary>
    public static Severity SeverityOf(string code) => code.StartsWith('W') ? Severity.Warning : Severity.Error;
}
