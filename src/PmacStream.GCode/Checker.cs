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
    /// <summary>The "exit" level: the program must not run when true.</summary>
    public bool HasErrors => Errors > 0;

    /// <summary>Errors counted in <see cref="Errors"/> but not listed: past <see cref="FindingLimits.PerLine"/> on their line.</summary>
    public int UnlistedErrors { get; init; }

    /// <summary>Warnings counted in <see cref="Warnings"/> but not listed.</summary>
    public int UnlistedWarnings { get; init; }

    /// <summary>
    /// The codes the program uses that the controller cannot run yet (<see cref="ControllerSupport.NotYet"/>), with
    /// the line of their first use: a job gate refuses such a program.
    /// </summary>
    public IReadOnlyDictionary<string, int> NotYetCodes { get; init; } = new Dictionary<string, int>();

    /// <summary>
    /// The summary in English, as logs and the program store keep it: <c>N errors, M warnings, B blocks</c>, and how
    /// many of them are not listed when a line had more than <see cref="FindingLimits.PerLine"/>.
    /// </summary>
    public override string ToString() => Format(System.Globalization.CultureInfo.InvariantCulture);

    /// <summary>The summary line in <see cref="DiagnosticText.Culture"/> (what <c>pmacstream check --lang</c> prints).</summary>
    public string ToLocalizedString() => Format(DiagnosticText.Culture);

    private string Format(System.Globalization.CultureInfo culture)
    {
        var line = DiagnosticText.Format(culture, DiagnosticText.SummaryKey, Errors, Warnings, Blocks);
        var unlisted = (long)UnlistedErrors + UnlistedWarnings;
        return unlisted == 0 ? line : $"{line}; {DiagnosticText.Format(culture, DiagnosticText.UnlistedKey, unlisted, FindingLimits.PerLine)}";
    }
}

/// <summary>
/// The one-pass program checker: reads the program once, streamed, and reports every diagnostic (not
/// only the first) through a callback, while interpreting each block so that the caller can store it. Memory does
/// not grow with the program. Never throws on content; I/O errors of the stream propagate.
/// </summary>
public sealed class Checker
{
    /// <summary>How many lines are held while waiting to see whether the program numbers any (W002).</summary>
    internal const int PendingSequenceLimit = 10000;

    // Findings are listed at most FindingLimits.PerLine a line and held at most FindingLimits.Held at a time, so a line
    // of junk, or a file of them, costs the same small memory as a clean program; the summary counts the rest.

    private readonly MachineProfile _profile;

    /// <summary>Creates a checker for a machine.</summary>
    public Checker(MachineProfile profile) => _profile = profile;

    /// <summary>The profile checked against.</summary>
    public MachineProfile Profile => _profile;

    /// <summary>Folders, limits and the variable file of the expansion of programs with subprograms or macros (null: the defaults).</summary>
    public Expansion.ExpansionOptions? MacroExpansion { get; init; }

    /// <summary>Off: straight moves are not measured, so the summary's estimated time covers arcs and dwells only (see <see cref="Interpreter.MeasureMoves"/>).</summary>
    internal bool MeasureMoves { get; init; } = true;

    /// <summary>
    /// Where the check's interpreter says what each line does as it decides it (<see cref="Interpreter.Canon"/>): the
    /// store takes each block's move, holes, corner and offsets from these calls.
    /// </summary>
    public ICanonicalMoves? Canon { get; init; }

    /// <summary>Checks a file. Throws <see cref="IOException"/>/<see cref="UnauthorizedAccessException"/> when it cannot be read.</summary>
    public CheckSummary CheckFile(string path, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock = null, CancellationToken cancellationToken = default)
    {
        if (Expansion.ProgramExpansion.Applies(path, _profile))
        {
            // Subprograms, macros or o-words: checked as the host will send them (GCode/Expansion).
            return Expansion.ProgramExpansion.Check(this, path, onDiagnostic, onBlock, MacroExpansion, cancellationToken);
        }

        using var stream = new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
        return Check(stream, path, onDiagnostic, onBlock, cancellationToken);
    }

    /// <summary>Checks a stream, calling <paramref name="onDiagnostic"/> in line order and <paramref name="onBlock"/> for each interpreted block.</summary>
    public CheckSummary Check(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock = null, CancellationToken cancellationToken = default) =>
        CheckCore(stream, fileName, onDiagnostic, onBlock, null, cancellationToken);

    /// <summary>
    /// Checks a stream, handing the interpreter itself to <paramref name="onInterpreted"/> after each block (read
    /// <see cref="Interpreter.Last"/> and <see cref="Interpreter.State"/>): the store's path, without a record
    /// allocated per block.
    /// </summary>
    public CheckSummary Check(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<Interpreter> onInterpreted, CancellationToken cancellationToken) =>
        CheckCore(stream, fileName, onDiagnostic, null, onInterpreted, cancellationToken);

    private CheckSummary CheckCore(Stream stream, string fileName, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock,
        Action<Interpreter>? onInterpreted, CancellationToken cancellationToken)
    {
        var sw = Stopwatch.StartNew();
        var run = new CheckRun(_profile, MeasureMoves, onDiagnostic, onBlock, onInterpreted);
        run.Interpreter.Canon = Canon;
        using var reader = new GCodeReader(stream, leaveOpen: true);
        while (reader.Read())
        {
            cancellationToken.ThrowIfCancellationRequested();
            var block = reader.Current;
            if (block.LineNumber == 1 && reader.StartsWithUtf16Bom)
            {
                return run.Utf16(fileName, reader.Position, sw.Elapsed);
            }

            run.Line(block);
        }

        if (reader.TextAfterTapeEnd)
        {
            run.TextAfterTapeEnd(reader.TapeEndLine);
        }

        return run.Finish(fileName, reader.Position, sw.Elapsed, reader.LineNumber);
    }

    /// <summary>Checks program text held in memory (tests, the HMI editor) and returns the diagnostics with the summary.</summary>
    public (CheckSummary Summary, IReadOnlyList<Diagnostic> Diagnostics) CheckText(string text, string fileName = "<text>")
    {
        var list = new List<Diagnostic>();
        using var ms = new MemoryStream(System.Text.Encoding.UTF8.GetBytes(text));
        var summary = Check(ms, fileName, list.Add);
        return (summary, list);
    }
}

/// <summary>
/// One check in progress, a line at a time: <see cref="Checker"/> feeds it from its reader, the splitter from its
/// own (which takes simple lines through <see cref="TryAxisLine"/> without lexing them into a block).
/// </summary>
public sealed class CheckRun
{
    private readonly Action<Diagnostic> _onDiagnostic;
    private readonly Action<DecodedBlock>? _onBlock;
    private readonly Action<Interpreter>? _onInterpreted;
    private readonly Interpreter _interp;
    private readonly bool _programNumbers;
    // Until the first N is seen we cannot know whether un-numbered blocks deserve W002 ("only when the program
    // numbers some blocks"), so diagnostics are held (bounded) and released in line order once it is known.
    private readonly List<Diagnostic> _held = [];
    private readonly List<Diagnostic> _diags = new(8);
    private int _errors;
    private int _warnings;
    private long _unlistedErrors;
    private long _unlistedWarnings;
    private long _blocks;
    private double _seconds;
    private int _lines;
    private int _firstBlockLine;
    private bool _sawProgramNumber;
    private bool _sawSequence;
    private int _heldLines;
    private bool _undecidedOverflow;
    private bool _reportedNul;
    private int _tapeEnd;

    /// <summary>
    /// A check to <paramref name="profile"/>: findings go to <paramref name="onDiagnostic"/> in line order, each block to
    /// <paramref name="onBlock"/> as a record or the interpreter itself to <paramref name="onInterpreted"/> (either may be
    /// null); <paramref name="measureMoves"/> false leaves straight moves unmeasured (see <see cref="Checker.MeasureMoves"/>).
    /// </summary>
    public CheckRun(MachineProfile profile, bool measureMoves, Action<Diagnostic> onDiagnostic, Action<DecodedBlock>? onBlock,
        Action<Interpreter>? onInterpreted)
    {
        _onDiagnostic = onDiagnostic;
        _onBlock = onBlock;
        _onInterpreted = onInterpreted;
        _interp = new Interpreter(profile) { MeasureMoves = measureMoves, RecordBlocks = onBlock != null || onInterpreted != null };
        _programNumbers = profile.TakesProgramNumbers;
    }

    /// <summary>The interpreter the check runs (tests compare its state).</summary>
    public Interpreter Interpreter => _interp;

    /// <summary>
    /// The findings of the last line given to <see cref="Line"/>, whether already reported or held while the program's
    /// numbering is undecided: the splitter reads which words the controller would be sent to no purpose (W003).
    /// </summary>
    public IReadOnlyList<Diagnostic> LineDiagnostics => _diags;

    /// <summary>The file starts with a UTF-16 byte-order mark: one error, and the check ends there.</summary>
    public CheckSummary Utf16(string fileName, long bytes, TimeSpan elapsed)
    {
        _lines = 1;
        Make(DiagnosticCodes.Utf16File, 1, 1);
        _held.Clear();
        return new CheckSummary(fileName, _lines, 0, _errors, _warnings, bytes, 0, elapsed);
    }

    /// <summary>
    /// Takes a line of only an N number, the motion code in force (G00/G01) and X/Y/Z words, already lexed by
    /// <see cref="AxisLine"/> into <paramref name="text"/> at <paramref name="textStart"/>, when it is sure to leave
    /// no diagnostic: it then moves the interpreter exactly as <see cref="Line"/> would. False (nothing changed) when
    /// the line needs the full path.
    /// </summary>
    public bool TryAxisLine(int lineNumber, in AxisLine line, byte[] text, int textStart)
    {
        // An N-less block is told W002 once the program numbers blocks, and held while that is undecided.
        if (line.HasN ? !_sawSequence : (_sawSequence || !_undecidedOverflow))
        {
            return false;
        }

        if (!_interp.TryStepAxisLine(line, text, textStart))
        {
            return false;
        }

        _lines = lineNumber;
        _blocks++;
        if (_firstBlockLine == 0)
        {
            _firstBlockLine = lineNumber;
        }

        return true;
    }

    /// <summary>
    /// Whether <see cref="TryAxisLine"/> would take <paramref name="line"/> now were the interpreter neither recording nor
    /// measuring (<see cref="Interpreter.AxisLineOnlyMoves"/>): it then leaves no diagnostic, and its full check
    /// (<see cref="Line"/>) changes what <see cref="TryAxisLine"/> would, besides recording and measuring it.
    /// </summary>
    public bool AxisLineOnlyMoves(in AxisLine line) =>
        !(line.HasN ? !_sawSequence : (_sawSequence || !_undecidedOverflow)) && _interp.AxisLineOnlyMoves(line);

    /// <summary>Whether <see cref="TryAxisLine"/> can take any line now: when not, a caller need not even scan for one.</summary>
    public bool AxisLaneOpen => _interp.AxisLaneOpen;

    /// <summary>The caller is about to reuse a text array it gave <see cref="TryAxisLine"/> (see <see cref="Interpreter.ReleaseText"/>).</summary>
    public void ReleaseText(byte[] text) => _interp.ReleaseText(text);

    /// <summary>Checks one lexed line.</summary>
    // Hot loop of a million-line program: compile optimized at once instead of spending the first
    // hundreds of milliseconds in unoptimized tier-0 code waiting for tiering.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveOptimization)]
    public void Line(GBlock block)
    {
        _lines = block.LineNumber;
        var diags = _diags;
        diags.Clear();
        var lexical = block.DiagnosticList;
        for (var di = 0; di < lexical.Count; di++)
        {
            var d = lexical[di];
            if (d.Code == DiagnosticCodes.NulByte)
            {
                // One report per file is enough to say "binary"; the rest would bury everything else.
                if (_reportedNul)
                {
                    continue;
                }

                _reportedNul = true;
            }

            diags.Add(d);
        }

        var interp = _interp;
        var isBlock = interp.StepCore(block, diags);
        if (diags.Count > FindingLimits.PerLine || lexical.Count == FindingLimits.PerLine)
        {
            // Only a line with that many findings can have more that are counted, not listed.
            CountUnlisted(diags, block);
        }

        if (isBlock)
        {
            ref readonly var decoded = ref interp.Last;
            _blocks++;
            _seconds += decoded.DurationSeconds;
            if (_firstBlockLine == 0)
            {
                _firstBlockLine = block.LineNumber;
            }

            if (decoded.N.HasValue)
            {
                if (!_sawSequence)
                {
                    // The program numbers blocks: the held un-numbered ones get their W002, in line order.
                    _sawSequence = true;
                    foreach (var d in _held)
                    {
                        Emit(d);
                    }

                    _held.Clear();
                }
            }
            else if (_sawSequence)
            {
                diags.Insert(0, NoSequence(block.LineNumber));
            }
            else if (!_undecidedOverflow)
            {
                diags.Insert(0, NoSequence(block.LineNumber));
            }
        }

        if (interp.LastHadProgramNumber)
        {
            _sawProgramNumber = true;
        }

        if (!_sawSequence && !_undecidedOverflow)
        {
            _held.AddRange(diags);
            if (++_heldLines > Checker.PendingSequenceLimit || _held.Count > FindingLimits.Held)
            {
                // A long un-numbered start, or one full of findings: take the program as un-numbered rather than hold
                // unbounded memory.
                _undecidedOverflow = true;
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
            if (_onBlock != null)
            {
                _onBlock(interp.Materialize());
            }
            else
            {
                _onInterpreted?.Invoke(interp);
            }
        }
    }

    /// <summary>The reader ended the tape at a <c>%</c> on <paramref name="line"/> with text after it: that text is ignored (W007).</summary>
    public void TextAfterTapeEnd(int line)
    {
        _tapeEnd = line;
    }

    /// <summary>The end of the program: the whole-program findings, and the totals.</summary>
    public CheckSummary Finish(string fileName, long bytes, TimeSpan elapsed, int linesRead = 0)
    {
        // Lines after the end of the tape were read, not checked: they still count as the file's lines.
        _lines = Math.Max(_lines, linesRead);
        if (!_sawSequence)
        {
            ReleaseWithoutW002();
        }

        if (_tapeEnd > 0)
        {
            Make(DiagnosticCodes.TextAfterTapeEnd, _tapeEnd, 1);
        }

        if (_blocks == 0)
        {
            Make(DiagnosticCodes.EmptyProgram, Math.Max(1, _lines), 1);
        }
        else if (!_sawProgramNumber && _programNumbers)
        {
            Make(DiagnosticCodes.NoProgramNumber, _firstBlockLine, 1);
        }

        return new CheckSummary(fileName, _lines, _blocks, Clamp(_errors + _unlistedErrors), Clamp(_warnings + _unlistedWarnings), bytes, _seconds, elapsed)
        {
            NotYetCodes = new Dictionary<string, int>(_interp.NotYetCodes),
            UnlistedErrors = Clamp(_unlistedErrors),
            UnlistedWarnings = Clamp(_unlistedWarnings),
        };
    }

    private void Emit(Diagnostic d)
    {
        if (d.Severity == Severity.Error)
        {
            _errors++;
        }
        else
        {
            _warnings++;
        }

        _onDiagnostic(d);
    }

    private static int Clamp(long count) => (int)Math.Min(int.MaxValue, count);

    /// <summary>
    /// Keeps the first <see cref="FindingLimits.PerLine"/> findings of a line and counts the rest, with the lexer's
    /// findings of <paramref name="block"/> that it counted and did not list.
    /// </summary>
    private void CountUnlisted(List<Diagnostic> diags, GBlock block)
    {
        _unlistedErrors += block.UnlistedErrors;
        _unlistedWarnings += block.UnlistedWarnings;
        for (var i = FindingLimits.PerLine; i < diags.Count; i++)
        {
            if (diags[i].Severity == Severity.Error)
            {
                _unlistedErrors++;
            }
            else
            {
                _unlistedWarnings++;
            }
        }

        if (diags.Count > FindingLimits.PerLine)
        {
            diags.RemoveRange(FindingLimits.PerLine, diags.Count - FindingLimits.PerLine);
        }
    }

    private void ReleaseWithoutW002()
    {
        foreach (var d in _held)
        {
            if (d.Code != DiagnosticCodes.NoSequenceNumber)
            {
                Emit(d);
            }
        }

        _held.Clear();
    }

    private void Make(string code, int line, int column, params object[] args) =>
        Emit(new Diagnostic(DiagnosticCodes.SeverityOf(code), code, line, column, DiagnosticText.Format(code, args)));

    private static Diagnostic NoSequence(int line) =>
        new(Severity.Warning, DiagnosticCodes.NoSequenceNumber, line, 1, DiagnosticText.Format(DiagnosticCodes.NoSequenceNumber));
}
