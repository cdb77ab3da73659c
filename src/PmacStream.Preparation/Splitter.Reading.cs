using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <content>The reading side of a split: the reader and checker lanes, host conversions, the line batches handed to the writer.</content>
public static partial class Splitter
{
    /// <summary>
    /// What the reading side found, handed to the writing side once it finished: its only other link to it is the
    /// bounded queue of line batches.
    /// </summary>
    private sealed record ReadOutcome(long Size, List<Diagnostic> Errors, int ErrorCount, List<Diagnostic> CheckErrors, int CheckErrorCount,
        int Warnings, Dictionary<string, int>? NotYet, int LaneLines, int BufferLaneLines)
    {
        /// <summary>The check's totals (an import in the same pass stores them), or null without a check.</summary>
        public CheckSummary? Summary { get; init; }

        /// <summary>The SHA-256 of the bytes read, when an import in the same pass hashed them.</summary>
        public string? Sha { get; init; }

        /// <summary>Why the import in the same pass was given up (nothing of it is kept), or null.</summary>
        public string? ImportGivenUp { get; init; }

        /// <summary>The split read the program's expansion (its map is beside the chunks).</summary>
        public bool Expanded { get; init; }
    }

    /// <summary>
    /// The reading side of a split, on its own thread: lexes the source (and checks it on the same blocks), converts
    /// the host blocks, and hands batches of lines to the writing side over <c>full</c>, taking empty ones back from
    /// <c>free</c>. Every field is this thread's; the writing side gets the <see cref="ReadOutcome"/> when it ends.
    /// </summary>
    private sealed partial class SourceReader(string source, string folder, long totalBytes, SplitOptions options, HandOff<LineBatch> full, HandOff<LineBatch> free,
        CancellationToken stop, ImportSide? import = null)
    {
        private readonly ImportSide? _import = import;
        private Store.ImportPipeline.Feed? _feed;  // the import's reading side, while it is fed
        private string? _importGivenUp;            // why it stopped being fed
        private bool _importSealed;                // the check's findings after this are not the stored check's (UTF-16)
        private FileStream? _file;                 // the file under the hashing stream of an import
        private Store.HashingReadStream? _hashing;
        private readonly string _source = source;
        private readonly string _folder = folder;     // the chunk folder: an expansion's map goes beside the manifest
        private readonly long _totalBytes = totalBytes; // the source file's size (an expanded source is longer than its file)
        private readonly SplitOptions _o = options;
        private readonly HandOff<LineBatch> _full = full;
        private readonly HandOff<LineBatch> _free = free;
        private readonly CancellationToken _stop = stop;
        private readonly List<Diagnostic> _errors = [];
        private readonly List<Diagnostic> _checkErrors = [];
        private int _errorCount;
        private int _checkErrorCount;
        private int _warnings;
        // Errors were found and the split will be refused: stop handing lines over, keep reading to list them.
        private bool _refusing;
        private LineBatch? _batch;
        private CheckRun? _check;
        private readonly List<int> _unused = new(2); // columns of the words the check found unused on the line being taken
        private Interpreter? _own;          // interprets for the host's conversions when the checker does not run (--force)
        private HostConversion? _host;
        // The batch lines of the compensated move held and the moves queued behind it, with the work offset each was
        // written in: an inside corner at the next XY move moves them to the crossing (the interpreter's decision).
        private HeldMoves<(int Index, Point3 Offset)>? _heldMoves;
        private readonly List<(int Index, Point3 Offset)> _heldNow = new(1), _final = new(4);
        private GBlock? _hostLine; // the host's converted lines are lexed into this one block (the batch copies them)
        private bool _started;              // the power-on call went before the first block
        private readonly Dictionary<string, int>? _notYet = options.CheckProfile != null ? new Dictionary<string, int>(StringComparer.Ordinal) : null; // codes the controller cannot run yet, first line
        private int _laneLines;        // lines the AxisLine lane took ...
        private int _bufferLaneLines;  // ... of them, straight from the read buffer

        private HeldMoves<(int Index, Point3 Offset)> HeldLines => _heldMoves ??= new(MoveLine);

        /// <summary>The checker runs in this pass whenever there is a profile (see <see cref="SplitRun"/>).</summary>
        private bool Checking => _o.CheckProfile != null;

        /// <summary>The reading thread: lexes (and checks) the source, hands lines over; returns what it found.</summary>
        public ReadOutcome Read()
        {
            var watch = System.Diagnostics.Stopwatch.StartNew();
            try
            {
                _batch = TakeFree();
                _feed = _import is { } import ? new Store.ImportPipeline.Feed(_o.CheckProfile!, import.Queue, null, _stop) : null;
                long size;
                CheckSummary? summary = null;
                string? sha = null;
                using (var stream = OpenSource())
                using (var reader = new GCodeReader(stream, leaveOpen: true, bufferSize: 1 << 16))
                {
                    // An import in the same pass stores each block's record and measured move: that check records and measures.
                    var check = _check = Checking ? new CheckRun(_o.CheckProfile!, measureMoves: _feed != null, OnChecked, null, _feed != null ? OnInterpreted : null) : null;
                    // The host's conversions (units, cycles, data blocks...) need the interpreter's state: the checker's, or
                    // without a check (--force) one of their own. Without a profile the program goes as it is written.
                    var own = _own = check == null && _o.CheckProfile != null ? new Interpreter(_o.CheckProfile) { MeasureMoves = false, RecordBlocks = false } : null;
                    if ((check?.Interpreter ?? own) is { } interpreter)
                    {
                        // The blocks block delete leaves out never run: positions the host computes (G92, cycles, G28,
                        // transformed moves) must not count them either.
                        interpreter.BlockDeleteEnabled = _o.BlockDelete;
                    }

                    var host = _host = check != null ? new HostConversion(check.Interpreter) : own != null ? new HostConversion(own) : null;
                    if (_feed != null && check != null && host != null)
                    {
                        // One interpreter's decisions, to both: the blocks the host sends and the store's records.
                        check.Interpreter.Canon = new CanonFanOut(host, _feed.Canon);
                    }

                    // With N kept, the lane's text (N dropped) is not the block; such splits take the full path.
                    // The lane takes G0/G1 lines without looking them up: only when the profile runs both on the controller.
                    // An import needs every line's record and measured move, which the lane does not make: each line is then
                    // interpreted in full, and a line the lane would have taken still goes as the lane's text (checkedLane).
                    var lane = _o.AxisLane && !_o.KeepN && LaneCodesRun(_o.CheckProfile) && _feed == null;
                    var checkedLane = _o.AxisLane && !_o.KeepN && LaneCodesRun(_o.CheckProfile) && _feed != null && check != null;
                    while (true)
                    {
                        // The lane first, straight on the read buffer: it finds the line's end itself.
                        // In a mode the checker's lane does not take (G91, arcs, no feed yet), no line is scanned for it.
                        var laneNow = lane && (check?.AxisLaneOpen ?? own?.AxisLaneOpen ?? true);
                        var peeked = false;
                        if (laneNow && reader.PeekBuffer(out var buffer, out var position, out var end))
                        {
                            peeked = true;
                            var batch = _batch!;
                            var length = AxisLine.TryParseNext(buffer, position, end, batch.Text, batch.TextLength, out var axes);
                            if (length >= 0 && TakeAxisLine(reader.LineNumber + 1, axes, reader.Position))
                            {
                                _bufferLaneLines++;
                                reader.TakeLine(length);
                                continue;
                            }
                        }

                        if (!reader.ReadRaw(out var data, out var start, out var rawLength))
                        {
                            break;
                        }

                        var number = reader.LineNumber;
                        if ((number & 0x3FFF) == 0)
                        {
                            _stop.ThrowIfCancellationRequested();
                        }

                        // The lane's other entry, for lines the buffer scan could not see whole (across two reads). A line
                        // it saw whole was already refused, by the scan or by the checker: no second try.
                        var tryLane = laneNow && !(peeked && reader.LineWasInBuffer);
                        var at = tryLane ? _batch!.AxisTextRoom(rawLength) : 0; // first: it may grow the text
                        if (tryLane && AxisLine.TryParse(data, start, rawLength, _batch!.Text, at, out var rawAxes) &&
                            TakeAxisLine(number, rawAxes, reader.Position))
                        {
                            continue;
                        }

                        if (checkedLane && TakeCheckedAxisLine(reader, data, start, rawLength, number))
                        {
                            continue;
                        }

                        var block = reader.LexRaw();
                        if (check != null)
                        {
                            if (number == 1 && reader.StartsWithUtf16Bom)
                            {
                                summary = check.Utf16(_source, reader.Position, watch.Elapsed);
                                _importSealed = true; // the check ends here: what the split adds after is not the check's
                                break;
                            }

                            if (_feed != null && _o.BlockDelete && (block.SkipFrom >= 0 || (block.BlockDelete && block.WordList.Count > 0)))
                            {
                                // The split skips this block (block delete on); the store decodes every block, as a separate
                                // import does: one interpreter cannot give both, so the import stops being fed here.
                                _importGivenUp = $"line {number} is skipped with block delete on, and the store decodes every block";
                                _feed = null;
                            }

                            check.Line(block);
                            _unused.Clear();
                            foreach (var d in check.LineDiagnostics)
                            {
                                if (d.Code == DiagnosticCodes.UnusedWord)
                                {
                                    _unused.Add(d.Column);
                                }
                            }
                        }
                        else
                        {
                            own?.Execute(block);
                        }

                        Take(block, host?.TakeLines());
                    }

                    EndExpansion();
                    if (check != null && reader.TextAfterTapeEnd)
                    {
                        check.TextAfterTapeEnd(reader.TapeEndLine);
                    }

                    if (check?.Finish(_source, reader.Position, watch.Elapsed, reader.LineNumber) is { } checkedAll)
                    {
                        if (_expansionError is { } refusal && !_importSealed)
                        {
                            // The expansion's refusal comes after the check's findings, as the import by itself reports it.
                            _feed?.OnDiagnostic(refusal);
                            checkedAll = checkedAll with { Errors = checkedAll.Errors + 1 };
                        }

                        summary ??= checkedAll;
                        if (checkedAll.UnlistedErrors > 0)
                        {
                            // Errors past the per-line listing limit were counted, not listed: the refusal counts them all.
                            _checkErrorCount += Math.Min(int.MaxValue - _checkErrorCount, checkedAll.UnlistedErrors);
                        }
                    }

                    size = SourceRead(reader);
                    if (_hashing != null)
                    {
                        // The revision keeps the whole file, also what the check did not read (after a UTF-16 mark).
                        stream.CopyTo(Stream.Null);
                        sha = _hashing.HashHex();
                    }
                    else if (_import != null && _expander != null)
                    {
                        // The split read the expansion: the revision's bytes and hash are the file's, read for them alone.
                        using var file = new FileStream(_source, FileMode.Open, FileAccess.Read, FileShare.Read, 1 << 16, FileOptions.SequentialScan);
                        using var hashing = new Store.HashingReadStream(file, _import.Revision.Pieces);
                        hashing.CopyTo(Stream.Null);
                        sha = hashing.HashHex();
                    }
                }

                _feed?.Finish();
                _batch!.EndPosition = size;
                _full.Add(_batch);
                _batch = null;
                return new ReadOutcome(size, _errors, _errorCount, _checkErrors, _checkErrorCount, _warnings, _notYet, _laneLines, _bufferLaneLines)
                {
                    Summary = summary,
                    Sha = sha,
                    ImportGivenUp = _import == null ? null : _importGivenUp,
                    Expanded = _expander != null,
                };
            }
            finally
            {
                _full.Complete();
                _import?.Queue.Complete();
                _file?.Dispose();
            }
        }

        /// <summary>A finding of the check: the import's (while it is the check's), then the split's.</summary>
        private void OnChecked(Diagnostic d)
        {
            if (!_importSealed)
            {
                // An expanded line's finding on the source line it came from, as the import by itself stores it.
                _feed?.OnDiagnostic(FromExpansion(d));
            }

            OnCheckDiagnostic(d);
        }

        /// <summary>A block the check interpreted, for the import while it is fed.</summary>
        private void OnInterpreted(Interpreter interp) => _feed?.OnInterpreted(interp);

        /// <summary>
        /// An <see cref="AxisLine"/> written at the end of the batch's text: checked (false: the checker wants the
        /// full path), then kept (unless the split is refused).
        /// </summary>
        private bool TakeAxisLine(int number, in AxisLine axes, long position)
        {
            var batch = _batch!;
            if (_check != null ? !_check.TryAxisLine(number, axes, batch.Text, batch.TextLength) :
                _own != null && !_own.TryStepAxisLine(axes, batch.Text, batch.TextLength))
            {
                return false;
            }

            if ((number & 0x3FFF) == 0)
            {
                _stop.ThrowIfCancellationRequested();
            }

            KeepAxisLine(number, axes, position);
            return true;
        }

        /// <summary>
        /// With an import in the same pass: a line the lane would have taken (<see cref="CheckRun.AxisLineOnlyMoves"/>) is
        /// interpreted in full, so the store gets its record and measured move, and goes as the lane's text, the bytes a
        /// plain split sends. False (nothing taken) for any other line.
        /// </summary>
        private bool TakeCheckedAxisLine(GCodeReader reader, byte[] data, int start, int rawLength, int number)
        {
            var batch = _batch!;
            var at = batch.AxisTextRoom(rawLength); // first: it may grow the text
            if (!AxisLine.TryParse(data, start, rawLength, batch.Text, at, out var axes) || !_check!.AxisLineOnlyMoves(axes))
            {
                return false;
            }

            _check.Line(reader.LexRaw());
            KeepAxisLine(number, axes, reader.Position);
            return true;
        }

        /// <summary>A lane line, checked: kept in the batch (unless the split is refused).</summary>
        private void KeepAxisLine(int number, in AxisLine axes, long position)
        {
            var batch = _batch!;
            _laneLines++;
            if (_refusing)
            {
                // The line is not kept, so its text is overwritten next: read the values it left there now.
                _check?.ReleaseText(batch.Text);
                _own?.ReleaseText(batch.Text);
                return;
            }

            batch.AddAxisLine(number, axes.TextLength, axes.Words);
            if (batch.IsFull)
            {
                Hand(position);
            }
        }

        /// <summary>Hands the full batch over and takes an empty one.</summary>
        private void Hand(long endPosition)
        {
            HeldLines.Clear();
            // The splitting thread reuses the batch's text once done with it: axis values still left there are read now.
            var batch = _batch!;
            _check?.ReleaseText(batch.Text);
            _own?.ReleaseText(batch.Text);
            batch.EndPosition = endPosition;
            _full.Add(batch);
            _batch = TakeFree();
        }

        private LineBatch TakeFree() =>
            _free.TryTake(out var batch) ? batch : throw new InvalidOperationException("batch pool closed");

        private void OnCheckDiagnostic(Diagnostic d)
        {
            d = FromExpansion(d);
            if (d.Severity == Severity.Error)
            {
                _checkErrorCount++;
                _refusing = !_o.AllowErrors;
                if (_checkErrors.Count < _o.MaxReportedErrors)
                {
                    _checkErrors.Add(d);
                }
            }
        }

        private static bool LaneCodesRun(MachineProfile? profile) =>
            profile == null || (profile.Find('G', 0)?.Controller != ControllerSupport.NotYet && profile.Find('G', 1)?.Controller != ControllerSupport.NotYet);

        /// <summary>One lexed line on the reading thread; <paramref name="converted"/>: the blocks the host sends instead (null: the line as it is).</summary>
        private void Take(GBlock b, IReadOnlyList<string>? converted)
        {
            if (b.DiagnosticList.Count > 0)
            {
                Collect(b);
            }

            if (_notYet != null)
            {
                NoteNotYet(b);
            }

            // Nothing for the controller in tape marks, skipped blocks and lines without words (Emit drops them too).
            if (_refusing || b.IsTapeMark || (b.BlockDelete && _o.BlockDelete) || b.WordList.Count == 0)
            {
                return;
            }

            var first = false;
            if (_host != null && !_started && converted is not { Count: 0 } && !OnlyNumbers(b))
            {
                // The library's state starts as the interpreter's does (power-on codes), whatever the last job left.
                _started = first = true;
                _batch!.Add(GCodeReader.LexLine(HostConversion.PowerOnState, b.LineNumber));
            }

            if (converted != null)
            {
                // One source block, several controller blocks: all carry its line, and they stay in one chunk.
                for (var i = 0; i < converted.Count; i++)
                {
                    if (_host!.TryWordsOf(i, out var words))
                    {
                        _batch!.Add(converted[i], words, b.LineNumber, continues: first || i > 0);
                    }
                    else
                    {
                        _batch!.Add(GCodeReader.LexLine(converted[i], b.LineNumber, _hostLine ??= new GBlock()), continues: first || i > 0);
                    }
                }
            }
            else
            {
                // With block delete on, the part of a block after a '/' inside it is skipped (FANUC's optional block skip).
                _batch!.Add(b, b.SkipFrom >= 0 && _o.BlockDelete ? b.SkipFrom : int.MaxValue, _unused, continues: first);
            }

            if (_host != null)
            {
                Hold(converted);
            }

            // A compensated move stays in the batch until the next XY move is known (bounded: the interpreter holds it
            // at most MaxHeldCompensationBlocks blocks).
            if (_batch!.IsFull && (HeldLines.Count == 0 || _batch.Count > 4 * LineBatch.MaxLines))
            {
                Hand(b.ByteOffset + b.Length);
            }
        }

        /// <summary>
        /// After a block's lines: the interpreter's decision for it (<see cref="CanonBlock.Hold"/>). An inside corner moves
        /// the compensated move held in the batch, and the plunges and retracts queued behind it, to where the offset
        /// paths cross (the interpreter already started this block's move there); the block's own move is held or
        /// queued in turn.
        /// </summary>
        private void Hold(IReadOnlyList<string>? converted)
        {
            var block = _host!.Block;
            if (block.AmendedEnd is not null && HeldLines.Count == 0)
            {
                throw new InvalidOperationException("an inside corner moves back the end of a move already handed over");
            }

            _heldNow.Clear();
            if (converted != null && _host.HeldMoveLine >= 0)
            {
                _heldNow.Add((_batch!.Count - converted.Count + _host.HeldMoveLine, block.Offset));
            }

            HeldLines.Take(block, _heldNow, _final);
            _final.Clear();
        }

        /// <summary>A held line moved on X and Y to the crossing of an inside corner, in place in the batch.</summary>
        private (int Index, Point3 Offset) MoveLine((int Index, Point3 Offset) held, Point3 crossing, bool _)
        {
            var moved = HostConversion.MovedLine(_batch!.TextAt(held.Index), crossing, held.Offset);
            _batch.Replace(held.Index, GCodeReader.LexLine(moved, _batch.Lines[held.Index].LineNumber, _hostLine ??= new GBlock()));
            return held;
        }

        /// <summary>A line of only O and N words (a program number, a label): nothing for the controller.</summary>
        private static bool OnlyNumbers(GBlock b)
        {
            foreach (var w in b.WordList)
            {
                if (w.Letter is not ('O' or 'N'))
                {
                    return false;
                }
            }

            return true;
        }

        /// <summary>Records the codes of a line that the controller cannot run yet (the manifest lists them for the job gate).</summary>
        private void NoteNotYet(GBlock b)
        {
            var profile = _o.CheckProfile!;
            foreach (var w in b.WordList)
            {
                if (w.Letter is 'G' or 'M' && profile.Find(w.Letter, w.Value) is { Controller: ControllerSupport.NotYet } def)
                {
                    _notYet!.TryAdd(def.Code, b.LineNumber);
                }
            }
        }

        private void Collect(GBlock b)
        {
            _errorCount += b.UnlistedErrors;
            _warnings += b.UnlistedWarnings;
            foreach (var d in b.DiagnosticList)
            {
                if (d.Severity == Severity.Error)
                {
                    _errorCount++;
                    _refusing = !_o.AllowErrors;
                    if (_errors.Count < _o.MaxReportedErrors)
                    {
                        _errors.Add(d);
                    }
                }
                else
                {
                    _warnings++;
                }
            }
        }
    }
}
