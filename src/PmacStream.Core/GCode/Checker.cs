using System.Diagnostics;

namespace PmacStream.GCode;

/// <summary>Totals of one check.</summary>
/// <param name="File">The file name as given.</param>
/// <param name="Lines">Source lines read.</param>
/// <param name="Blocks">Blocks interpreted (lines with words other than only O, not empty or comment-only).</param>
/// <param name="Errors">Error diagnostics.</param>
/// <param name="Warnings">Warning diagnostics.</param>
/// <param name="Bytes">Bytes read.</param>
/// <param name="EstimatedSeconds">Sum of the blocks' estimated durations (the program's run time at programmed feeds).</param>
/// <param name="Elapsed">Wall time the check took.</param>
public sealed record CheckSummary(string File, int Lines, long Blocks, int Errors, int Warnings, long Bytes, double EstimatedSeconds, TimeSpan Elapsed)
{
    /// <summary>Seed 002's "exit" level: the program must not run when true.</summary>
    public bool HasErrors => Errors > 0;

    /// <summary>The summary line the CLI prints: <c>N errors, M warnings, B blocks</c>.</summary>
    public override string ToString() => $"{Errors} errors, {Warnings} warnings, {Blocks} blocks";
}

/// <summary>
/// The one-pass program checker of seed 002: reads the program once, streamed, and reports every diagnostic (not
/// only the first) through a callback, while interpreting each block so that the caller can store it. Memory does
/// not grow with the program. Never throws on content; I/O errors of the stream propagate.
/// </summary>
public sealed class Checker
{
    /// <summary>How many lines are held while waiting to see whether the program numbers any (W002).</summary>
    internal const int PendingSequenceLimit = 10000;

    private readonly MachineProfile _profile;

    /// <summary>Creates a checker for a machine.</summary>
    public Checker(MachineProfile profile) => _profile = profile;

    /// <summary>The profile checked against.</summary>
    public MachineProfile Profile => _profile;

    /// <summary>Off: straight moves are not measured, so the summary's estimated time covers arcs and dwells only (see <see cref="Interpreter.MeasureMoves"/>).</summary>
    internal bool MeasureMoves { get; init; } = true;

    /// <summary>Checks a file. Throws <see cref="IOException"/>/<see cref="UnauthorizedAccessException"/> when it cannot be read.</summary>
    public CheckSummary CheckFile(string path, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock = null, CancellationToken cancellationToken = default)
    {
        using var stream = new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        return Check(stream, path, onDiagnostic, onBlock, cancellationToken);
    }

    /// <summary>Checks a stream, calling <paramref name="onDiagnostic"/> in line order and <paramref name="onBlock"/> for each interpreted block.</summary>
    public CheckSummary Check(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock = null, CancellationToken cancellationToken = default) =>
        CheckCore(stream, fileName, onDiagnostic, onBlock, null, null, cancellationToken);

    /// <summary>
    /// Checks a stream, handing the interpreter itself to <paramref name="onInterpreted"/> after each block (read
    /// <see cref="Interpreter.Last"/> and <see cref="Interpreter.State"/>): the store's path, without a record
    /// allocated per block.
    /// </summary>
    internal CheckSummary Check(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<Interpreter> onInterpreted, CancellationToken cancellationToken) =>
        CheckCore(stream, fileName, onDiagnostic, null, onInterpreted, null, cancellationToken);

    /// <summary>As the public overload; <paramref name="onLine"/> sees every line's lexed block after the checker took it (the splitter's single pass).</summary>
    internal CheckSummary Check(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock, Action<GBlock>? onLine, CancellationToken cancellationToken) =>
        CheckCore(stream, fileName, onDiagnostic, onBlock, null, onLine, cancellationToken);

    // Hot loop of a million-line program: compile optimized at once instead of spending the first
    // hundreds of milliseconds in unoptimized tier-0 code waiting for tiering.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveOptimization)]
    private CheckSummary CheckCore(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock,
        Action<Interpreter>? onInterpreted, Action<GBlock>? onLine, CancellationToken cancellationToken)
    {
        var sw = Stopwatch.StartNew();
        var errors = 0;
        var warnings = 0;
        long blocks = 0;
        double seconds = 0;
        var lines = 0;
        var firstBlockLine = 0;
        var sawProgramNumber = false;
        var sawSequence = false;
        // Until the first N is seen we cannot know whether un-numbered blocks deserve W002 ("only when the program
        // numbers some blocks"), so diagnostics are held (bounded) and released in line order once it is known.
        var held = new List<Diagnostic>();
        var heldLines = 0;
        var undecidedOverflow = false;
        var reportedNul = false;
        var diags = new List<Diagnostic>(8);
        var interp = new Interpreter(_profile) { MeasureMoves = MeasureMoves, RecordBlocks = onBlock != null || onInterpreted != null };

        void Emit(Diagnostic d)
        {
            if (d.Severity == Severity.Error)
            {
                errors++;
            }
            else
            {
                warnings++;
            }

            onDiagnostic(d);
        }

        void ReleaseWithoutW002()
        {
            foreach (var d in held)
            {
                if (d.Code != DiagnosticCodes.NoSequenceNumber)
                {
                    Emit(d);
                }
            }

            held.Clear();
        }

        void Make(string code, int line, int column, params object[] args) =>
            Emit(new Diagnostic(DiagnosticCodes.SeverityOf(code), code, line, column, DiagnosticText.Format(code, args)));

        using var reader = new GCodeReader(stream, leaveOpen: true);
        while (reader.Read())
        {
            cancellationToken.ThrowIfCancellationRequested();
            var block = reader.Current;
            lines = block.LineNumber;
            if (lines == 1 && reader.StartsWithUtf16Bom)
            {
                Make(DiagnosticCodes.Utf16File, 1, 1);
                held.Clear();
                return new CheckSummary(fileName, lines, 0, errors, warnings, reader.Position, 0, sw.Elapsed);
            }

            diags.Clear();
            var lexical = block.DiagnosticList;
            for (var di = 0; di < lexical.Count; di++)
            {
                var d = lexical[di];
                if (d.Code == DiagnosticCodes.NulByte)
                {
                    // One report per file is enough to say "binary"; the rest would bury everything else.
                    if (reportedNul)
                    {
                        continue;
                    }

                    reportedNul = true;
                }

                diags.Add(d);
            }

            var isBlock = interp.StepCore(block, diags);
            if (isBlock)
            {
                ref readonly var decoded = ref interp.Last;
                blocks++;
                seconds += decoded.DurationSeconds;
                if (firstBlockLine == 0)
                {
                    firstBlockLine = block.LineNumber;
                }

                if (decoded.N.HasValue)
                {
                    if (!sawSequence)
                    {
                        // The program numbers blocks: the held un-numbered ones get their W002, in line order.
                        sawSequence = true;
                        foreach (var d in held)
                        {
                            Emit(d);
                        }

                        held.Clear();
                    }
                }
                else if (sawSequence)
                {
                    diags.Insert(0, NoSequence(block.LineNumber));
                }
                else if (!undecidedOverflow)
                {
                    diags.Insert(0, NoSequence(block.LineNumber));
                }
            }

            if (interp.LastHadProgramNumber)
            {
                sawProgramNumber = true;
            }

            if (!sawSequence && !undecidedOverflow)
            {
                held.AddRange(diags);
                if (++heldLines > PendingSequenceLimit)
                {
                    // A long un-numbered start: treat the program as un-numbered rather than hold unbounded memory.
                    undecidedOverflow = true;
                    ReleaseWithoutW002();
                }
            }
            else
            {
                for (var di = 0; di < diags.Count; di++)
                {
                    Emit(diags[di]);
                }
            }

            if (isBlock)
            {
                if (onBlock != null)
                {
                    onBlock(interp.Materialize());
                }
                else
                {
                    onInterpreted?.Invoke(interp);
                }
            }

            onLine?.Invoke(block);
        }

        if (!sawSequence)
        {
            ReleaseWithoutW002();
        }

        if (blocks == 0)
        {
            Make(DiagnosticCodes.EmptyProgram, Math.Max(1, lines), 1);
        }
        else if (!sawProgramNumber)
        {
            Make(DiagnosticCodes.NoProgramNumber, firstBlockLine, 1);
        }

        return new CheckSummary(fileName, lines, blocks, errors, warnings, reader.Position, seconds, sw.Elapsed);
    }

    private static Diagnostic NoSequence(int line) =>
        new(Severity.Warning, DiagnosticCodes.NoSequenceNumber, line, 1, DiagnosticText.Format(DiagnosticCodes.NoSequenceNumber));

    /// <summary>Checks program text held in memory (tests, the HMI editor) and returns the diagnostics with the summary.</summary>
    public (CheckSummary Summary, IReadOnlyList<Diagnostic> Diagnostics) CheckText(string text, string fileName = "<text>")
    {
        var list = new List<Diagnostic>();
        using var ms = new MemoryStream(System.Text.Encoding.UTF8.GetBytes(text));
        var summary = Check(ms, fileName, list.Add);
        return (summary, list);
    }
}
