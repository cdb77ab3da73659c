using System.Runtime.CompilerServices;
using System.Runtime.InteropServices;
using System.Text;
using PmacStream.GCode;
using Serilog;

namespace PmacStream.Program;

/// <summary>
/// Cuts a G-code program into rotary-buffer chunk files a Turbo PMAC accepts, streaming the
/// source (memory does not grow with its size). Each chunk is <c>CLOSE</c>, <c>OPEN ROT</c>, one line per source
/// block (plus a <c>P500=</c> line where the program sets F), and <c>CLOSE</c>; the last one carries the program
/// tail. Lines are ASCII with CR LF ends. Output goes to a temporary folder renamed into place at the end, so a
/// failure leaves no half-written set.
/// </summary>
public static class Splitter
{
    /// <summary>Chunk files' extension.</summary>
    public const string ChunkExtension = ".pmc";

    /// <summary>First lines of every chunk: close whatever buffer is open, open the rotary buffer.</summary>
    public static readonly string Header = "CLOSE\r\nOPEN ROT\r\n";

    /// <summary>Last line of every chunk, so online commands (M0 reads, P500 writes) never land in an open buffer.</summary>
    public static readonly string Footer = "CLOSE\r\n";

    private static readonly ILogger Logger = Log.ForContext(typeof(Splitter));

    /// <summary>The default output folder: <c>&lt;source dir&gt;/&lt;name&gt;_chunks</c>.</summary>
    public static string DefaultOutDir(string sourcePath)
    {
        var full = Path.GetFullPath(sourcePath);
        return Path.Combine(Path.GetDirectoryName(full)!, Path.GetFileNameWithoutExtension(full) + "_chunks");
    }

    /// <summary>Splits asynchronously on the thread pool (see <see cref="Split"/>).</summary>
    public static Task<SplitResult> SplitAsync(string sourcePath, SplitOptions? options = null,
        IProgress<SplitProgress>? progress = null, CancellationToken cancellationToken = default) =>
        Task.Run(() => Split(sourcePath, options, progress, cancellationToken), cancellationToken);

    /// <summary>
    /// Splits <paramref name="sourcePath"/> into chunk files plus <c>manifest.json</c>.
    /// </summary>
    /// <exception cref="SplitException">The program has errors (and <see cref="SplitOptions.AllowErrors"/> is off),
    /// a block cannot fit one chunk, or it holds no blocks. Nothing is written.</exception>
    /// <exception cref="IOException">The source cannot be read or the output folder cannot be written.</exception>
    /// <exception cref="ArgumentException">An option is invalid.</exception>
    /// <exception cref="OperationCanceledException">Cancelled; nothing is written.</exception>
    public static SplitResult Split(string sourcePath, SplitOptions? options = null,
        IProgress<SplitProgress>? progress = null, CancellationToken cancellationToken = default)
    {
        options ??= new SplitOptions();
        options.Validate();
        var source = Path.GetFullPath(sourcePath);
        if (!File.Exists(source))
        {
            throw new FileNotFoundException($"{sourcePath}: no such file", sourcePath);
        }

        var outDir = Path.GetFullPath(options.OutDir ?? DefaultOutDir(source));
        EnsureReplaceable(outDir);
        using var work = SplitWorkFolder.Create(outDir);
        var temp = work.Path;
        Logger.Information("Splitting {Source} into {OutDir} ({Lines} blocks, {Words} words, {Bytes} bytes per chunk)",
            source, outDir, options.LinesPerChunk, options.RotWords, options.MaxChunkBytes);
        try
        {
            var run = new SplitRun(source, temp, options, progress, cancellationToken);
            var (manifest, warnings) = run.Execute();
            manifest.Save(Path.Combine(temp, ChunkManifest.FileName));
            Publish(temp, outDir);
            Logger.Information("Split {Source}: {Chunks} chunks, {Blocks} blocks ({Motion} motion)",
                source, manifest.Chunks.Count, manifest.TotalBlocks, manifest.TotalMotionBlocks);
            return new SplitResult(manifest, outDir, warnings) { LaneLines = run.LaneLines, BufferLaneLines = run.BufferLaneLines, NotYetCodes = run.NotYetCodes };
        }
        catch
        {
            TryDelete(temp);
            throw;
        }
    }

    /// <summary>An existing output folder is replaced only when it is empty or holds a previous split.</summary>
    private static void EnsureReplaceable(string outDir)
    {
        if (File.Exists(outDir))
        {
            throw new IOException($"{outDir}: exists and is a file, not a folder");
        }

        if (!Directory.Exists(outDir))
        {
            return;
        }

        foreach (var f in Directory.EnumerateFileSystemEntries(outDir))
        {
            var name = Path.GetFileName(f);
            if (!(name == ChunkManifest.FileName || name.EndsWith(ChunkExtension, StringComparison.OrdinalIgnoreCase) || IsDownloadReport(f)) || Directory.Exists(f))
            {
                throw new IOException($"{outDir}: folder exists and holds other files ({name}); choose another --out");
            }
        }
    }

    /// <summary>The <c>.log</c> and <c>.map</c> a PComm-style download writes beside a chunk file are part of the split.</summary>
    private static bool IsDownloadReport(string path) =>
        (path.EndsWith(".log", StringComparison.OrdinalIgnoreCase) || path.EndsWith(".map", StringComparison.OrdinalIgnoreCase))
        && File.Exists(Path.ChangeExtension(path, ChunkExtension));

    private static void Publish(string temp, string outDir)
    {
        if (!Directory.Exists(outDir))
        {
            Directory.Move(temp, outDir);
            return;
        }

        // Swap: old set aside, new in place, old deleted; on failure the old set comes back.
        var old = temp + ".old";
        Directory.Move(outDir, old);
        try
        {
            Directory.Move(temp, outDir);
        }
        catch
        {
            Directory.Move(old, outDir);
            throw;
        }

        TryDelete(old);
    }

    private static void TryDelete(string folder)
    {
        try
        {
            if (Directory.Exists(folder))
            {
                Directory.Delete(folder, recursive: true);
            }
        }
        catch (IOException e)
        {
            Logger.Warning(e, "Could not delete {Folder}", folder);
        }
        catch (UnauthorizedAccessException e)
        {
            Logger.Warning(e, "Could not delete {Folder}", folder);
        }
    }

    /// <summary>
    /// One split in progress. Two threads share the work: the reading thread lexes the source (and runs the
    /// checker on the same blocks when <see cref="SplitOptions.CheckProfile"/> is set) and hands batches of lines
    /// over a bounded queue, in order, to the calling thread, which builds the chunks; a third writes and hashes
    /// the chunk files (<see cref="ChunkFileWriter"/>) and a fourth hashes the source. Most CAM lines are plain
    /// axis moves in the mode in force: those take the <see cref="AxisLine"/> lane (lexed in one scan of the read
    /// buffer, checked by <see cref="CheckRun.TryAxisLine"/>, handed over as their emitted text); every other line
    /// takes the general lexer, checker and emitter, with the same results (AxisLaneTests compare the two).
    /// </summary>
    private sealed class SplitRun
    {
        private const int QueueDepth = 2;

        private static readonly byte[] HeaderBytes = Encoding.ASCII.GetBytes(Header);
        private static readonly byte[] FooterBytes = Encoding.ASCII.GetBytes(Footer);
        private static readonly byte[] DwellZero = Encoding.ASCII.GetBytes("DWELL0");

        private readonly string _source;
        private readonly string _folder;
        private readonly string _name;
        private readonly SplitOptions _o;
        private readonly IProgress<SplitProgress>? _progress;
        private readonly CancellationToken _ct;
        private readonly byte[] _feedVar;
        private readonly byte[] _tail;
        private readonly int _tailWords;
        private readonly ByteLine _block = new(256); // the block set aside while its chunk is closed (once per chunk)
        private readonly AsciiCounter _trackDigits = new();
        private readonly byte[] _trackPrefix;     // "M0=="
        private readonly ulong _trackPrefixWord;
        private readonly byte[] _feedSuffix;      // " F(P500)"
        private readonly ulong _feedSuffixWord;
        private readonly ByteLine _chunk;
        private readonly ChunkTable _chunks;
        private long _totalBytes;
        // Options read for every block, held in fields.
        private readonly int _linesPerChunk;
        private readonly long _maxChunkBytes;
        private readonly int _rotWords;
        private readonly int _wordsPerBlock;
        private readonly int _limitReserve;   // tail and footer bytes every chunk keeps room for
        private readonly bool _exactTracking;
        private readonly bool _paperFeed;
        private readonly bool _toolChangeMoves; // M06's hook moves to the profile's tool change position
        private long _position;
        private ChunkFileWriter? _writer;

        // Reading thread only (read by the splitting thread after it finished).
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
        private readonly ProgramStopCodes _stops;
        private readonly Dictionary<string, int> _stopCodes = new(StringComparer.Ordinal); // stop codes used, first line
        private Interpreter? _own;          // interprets for the host's conversions when the checker does not run (--force)
        private HostConversion? _host;
        private bool _started;              // the power-on call went before the first block
        private readonly Dictionary<string, int>? _notYet; // codes the controller cannot run yet, first line (with a profile)
        private double _feedSet = double.NaN; // the feed the last P500= line set (paper feed mode)
        private int _laneLines;        // lines the AxisLine lane took ...
        private int _bufferLaneLines;  // ... of them, straight from the read buffer
        private HandOff<LineBatch>? _full;
        private HandOff<LineBatch>? _free;
        private CancellationToken _stop;

        // Current chunk (splitting thread).
        private int _chunkBlocks;
        private int _chunkMotion;
        private int _chunkWords;
        private int _chunkFirst;
        private int _chunkLast;
        private int _totalBlocks;
        private int _totalMotion;
        private int _lastBlockStart;
        private bool _lastBlockEndsProgram;

        public SplitRun(string source, string folder, SplitOptions options, IProgress<SplitProgress>? progress, CancellationToken ct)
        {
            _source = source;
            _folder = folder;
            _name = Path.GetFileNameWithoutExtension(source);
            _chunks = new ChunkTable(_name);
            _o = options;
            _progress = progress;
            _ct = ct;
            _feedVar = Encoding.ASCII.GetBytes(options.FeedVariable);
            var sync = SyncAssignment.Of(options);
            _trackPrefix = sync.PrefixBytes();
            _trackPrefixWord = Word8(_trackPrefix);
            _feedSuffix = Encoding.ASCII.GetBytes($" F({options.FeedVariable})");
            _feedSuffixWord = Word8(_feedSuffix);
            var tail = new StringBuilder();
            foreach (var line in options.ProgramTail.Split('\n'))
            {
                var t = line.Trim();
                if (t.Length > 0)
                {
                    tail.Append(t).Append("\r\n");
                    _tailWords += Math.Max(1, t.Split(' ', StringSplitOptions.RemoveEmptyEntries).Length);
                }
            }

            _tail = Encoding.ASCII.GetBytes(tail.ToString());
            _linesPerChunk = options.LinesPerChunk;
            _maxChunkBytes = options.MaxChunkBytes;
            _rotWords = options.RotWords;
            _wordsPerBlock = options.WordsPerBlock;
            _limitReserve = _tail.Length + FooterBytes.Length;
            _exactTracking = sync.Placement == TrackingPlacement.Exact;
            _paperFeed = options.Feed == FeedMode.Paper;
            _toolChangeMoves = options.CheckProfile?.ToolChangePosition != null;
            _chunk = new ByteLine((int)Math.Min(options.MaxChunkBytes + 256, 1 << 20));
            _chunk.Append(HeaderBytes);
            _notYet = options.CheckProfile != null ? new Dictionary<string, int>(StringComparer.Ordinal) : null;
            _stops = ProgramStopCodes.Of(options.CheckProfile ?? MachineProfile.Default);
        }

        /// <summary>The codes the program uses that the controller cannot run yet, with their first line (null without a profile).</summary>
        public IReadOnlyDictionary<string, int>? NotYetCodes => _notYet;

        /// <summary>Lines the <see cref="AxisLine"/> lane took (read after <see cref="Execute"/>).</summary>
        public int LaneLines => _laneLines;

        /// <summary>Of <see cref="LaneLines"/>, those scanned straight in the read buffer.</summary>
        public int BufferLaneLines => _bufferLaneLines;

        /// <summary>
        /// The checker runs in this pass whenever there is a profile: it decides refusal (unless forced) and, forced or
        /// not, which words the controller must not get (W003: a word the block does not use is not ignored by a PMAC).
        /// </summary>
        private bool Checking => _o.CheckProfile != null;

        public (ChunkManifest Manifest, int Warnings) Execute()
        {
            long size;
            _totalBytes = new FileInfo(_source).Length;
            // The source hash runs on its own thread over a second (page-cached) read, overlapping the split.
            var sourceHash = Task.Run(() => (Sha: FileHash.Sha256Hex(_source, out var hashed), Size: hashed), _ct);
            using var stop = CancellationTokenSource.CreateLinkedTokenSource(_ct);
            using var full = new HandOff<LineBatch>(QueueDepth, stop.Token);
            using var free = new HandOff<LineBatch>(QueueDepth + 2, stop.Token);
            for (var i = 0; i < QueueDepth + 2; i++)
            {
                free.Add(new LineBatch());
            }

            _full = full;
            _free = free;
            _stop = stop.Token;
            using (var writer = new ChunkFileWriter(_chunks, _o.AfterChunkWritten, _ct, (int)Math.Min(_o.MaxChunkBytes + 256, 1 << 20)))
            {
                _writer = writer;
                var reading = Task.Factory.StartNew(Produce, CancellationToken.None, TaskCreationOptions.LongRunning, TaskScheduler.Default);
                try
                {
                    // Batches arrive in source order (one producer, one FIFO queue), so chunks keep the source order.
                    while (full.TryTake(out var batch))
                    {
                        Consume(batch);
                        batch.Clear();
                        free.Add(batch);
                    }

                    size = reading.GetAwaiter().GetResult(); // rethrows what stopped the reading thread
                }
                catch
                {
                    stop.Cancel();
                    try
                    {
                        reading.Wait(CancellationToken.None);
                    }
                    catch (AggregateException)
                    {
                        // The splitting thread's own failure is the one reported.
                    }

                    throw;
                }

                Finish();
                writer.Complete();
            }

            var (sha, hashedSize) = sourceHash.GetAwaiter().GetResult();
            if (hashedSize != size)
            {
                throw new IOException($"{_source}: changed while it was being split ({size} bytes read, {hashedSize} hashed)");
            }

            var manifest = new ChunkManifest(_source, size, sha, _totalBlocks, _totalMotion, _o.TrackVariable,
                _o.Tracking, _o.Feed, _o.FeedVariable, _chunks)
            {
                LinesPerChunk = _o.LinesPerChunk,
                RotWords = _o.RotWords,
                WordsPerBlock = _o.WordsPerBlock,
                MaxChunkBytes = _o.MaxChunkBytes,
                ProgramTail = _o.ProgramTail,
                KeepN = _o.KeepN,
                BlockDelete = _o.BlockDelete,
                CheckedProfile = _o.CheckedProfile,
                NotYetCodes = _notYet,
                StopCodes = _stopCodes,
            };
            return (manifest, _warnings);
        }

        /// <summary>The reading thread: lexes (and checks) the source, hands lines over; returns the bytes read.</summary>
        private long Produce()
        {
            try
            {
                _batch = TakeFree();
                long size;
                using (var stream = new FileStream(_source, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan))
                using (var reader = new GCodeReader(stream, leaveOpen: true, bufferSize: 1 << 16))
                {
                    var check = _check = Checking ? new CheckRun(_o.CheckProfile!, measureMoves: false, OnCheckDiagnostic, null, null) : null;
                    // The host's conversions (units, cycles, data blocks...) need the interpreter's state: the checker's, or
                    // without a check (--force) one of their own. Without a profile the program goes as it is written.
                    var own = _own = check == null && _o.CheckProfile != null ? new Interpreter(_o.CheckProfile) { MeasureMoves = false, RecordBlocks = false } : null;
                    var host = _host = check != null ? new HostConversion(check.Interpreter) : own != null ? new HostConversion(own) : null;
                    // With N kept, the lane's text (N dropped) is not the block; such splits take the full path.
                    // The lane takes G0/G1 lines without looking them up: only when the profile runs both on the controller.
                    var lane = _o.AxisLane && !_o.KeepN && LaneCodesRun(_o.CheckProfile);
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

                        var block = reader.LexRaw();
                        host?.Before();
                        if (check != null)
                        {
                            if (number == 1 && reader.StartsWithUtf16Bom)
                            {
                                check.Utf16(_source, reader.Position, TimeSpan.Zero);
                                break;
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
                            own?.StepCore(block, null);
                        }

                        Take(block, host?.Convert(block));
                    }

                    if (check != null && reader.TextAfterTapeEnd)
                    {
                        check.TextAfterTapeEnd(reader.TapeEndLine);
                    }

                    if (check?.Finish(_source, reader.Position, TimeSpan.Zero, reader.LineNumber) is { UnlistedErrors: > 0 } checkedAll)
                    {
                        // Errors past the per-line listing limit were counted, not listed: the refusal counts them all.
                        _checkErrorCount += Math.Min(int.MaxValue - _checkErrorCount, checkedAll.UnlistedErrors);
                    }
                    size = reader.Position;
                }

                _batch!.EndPosition = size;
                _full!.Add(_batch);
                _batch = null;
                return size;
            }
            finally
            {
                _full!.Complete();
            }
        }

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

            _laneLines++;
            if (_refusing)
            {
                // The line is not kept, so its text is overwritten next: read the values it left there now.
                _check?.ReleaseText(batch.Text);
                _own?.ReleaseText(batch.Text);
                return true;
            }

            batch.AddAxisLine(number, axes.TextLength, axes.Words);
            if (batch.IsFull)
            {
                Hand(position);
            }

            return true;
        }

        /// <summary>Hands the full batch over and takes an empty one.</summary>
        private void Hand(long endPosition)
        {
            // The splitting thread reuses the batch's text once done with it: axis values still left there are read now.
            var batch = _batch!;
            _check?.ReleaseText(batch.Text);
            _own?.ReleaseText(batch.Text);
            batch.EndPosition = endPosition;
            _full!.Add(batch);
            _batch = TakeFree();
        }

        private LineBatch TakeFree() =>
            _free!.TryTake(out var batch) ? batch : throw new InvalidOperationException("batch pool closed");

        private void OnCheckDiagnostic(Diagnostic d)
        {
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
                    _batch!.Add(GCodeReader.LexLine(converted[i], b.LineNumber), continues: first || i > 0);
                }
            }
            else
            {
                // With block delete on, the part of a block after a '/' inside it is skipped (FANUC's optional block skip).
                _batch!.Add(b, b.SkipFrom >= 0 && _o.BlockDelete ? b.SkipFrom : int.MaxValue, _unused, continues: first);
            }

            if (_batch!.IsFull)
            {
                Hand(b.ByteOffset + b.Length);
            }
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

        /// <summary>The splitting thread's work on one batch.</summary>
        private void Consume(LineBatch batch)
        {
            var text = batch.Text;
            var lines = batch.Lines;
            var n = 0;
            while (n < lines.Length)
            {
                ref readonly var line = ref lines[n];
                if ((n & 0x3FF) == 0x3FF)
                {
                    _ct.ThrowIfCancellationRequested();
                }

                if (line.IsAxisLine)
                {
                    EmitAxisLine(text.AsSpan(line.TextStart, line.TextLength), line.WordCount, line.LineNumber);
                    n++;
                }
                else if (n + 1 < lines.Length && lines[n + 1].Continues)
                {
                    // A host block of several lines: emitted together (they stay in one chunk).
                    n = EmitGroup(batch, n);
                }
                else
                {
                    Emit(text.AsSpan(line.TextStart, line.TextLength), batch.WordsOf(line), line.LineNumber);
                    n++;
                }
            }

            _position = batch.EndPosition;
        }

        private void Finish()
        {
            if (Checking && !_o.AllowErrors && _checkErrorCount > 0)
            {
                throw new SplitException(
                    $"{_source}: {_checkErrorCount} error(s); not split (force splits anyway)", _checkErrors, _checkErrorCount)
                {
                    FromChecker = true,
                };
            }

            // Also when checking: lines stopped flowing at the first lexical error, so never publish what came before.
            if (_errorCount > 0 && !_o.AllowErrors)
            {
                throw new SplitException(
                    $"{_source}: {_errorCount} error(s); not split (force splits anyway, dropping what is not G-code)",
                    _errors, _errorCount);
            }

            if (_chunkBlocks == 0)
            {
                throw new SplitException($"{_source}: no program blocks to split", [], 1);
            }

            Flush(last: true);
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

        /// <summary>The lines of one host block from <paramref name="first"/> on, as one block of the chunk; returns the index after them.</summary>
        private int EmitGroup(LineBatch batch, int first)
        {
            var lines = batch.Lines;
            var end = first + 1;
            var room = 0;
            while (end < lines.Length && lines[end].Continues)
            {
                end++;
            }

            for (var i = first; i < end; i++)
            {
                room += (2 * lines[i].TextLength) + (2 * lines[i].WordCount) + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length));
            }

            var space = _chunk.Reserve(room);
            var o = space;
            var moves = 0;
            var endsProgram = false;
            var words = 0;
            for (var i = first; i < end; i++)
            {
                var written = Write(o, batch.Text.AsSpan(lines[i].TextStart, lines[i].TextLength), batch.WordsOf(lines[i]), lines[i].LineNumber,
                    out var motion, out var ends, out var values);
                if (written == 0)
                {
                    continue;
                }

                o = o[written..];
                moves |= motion != BlockMotion.None ? 1 : 0; // one source block, however many moves the host made of it
                endsProgram |= ends;
                words += Math.Max(_o.WordsPerBlock, values);
            }

            if (space.Length != o.Length)
            {
                Add(space.Length - o.Length, lines[first].LineNumber, moves, endsProgram, words);
            }

            return end;
        }

        private void Emit(ReadOnlySpan<byte> src, ReadOnlySpan<GWord> words, int lineNumber)
        {
            var space = _chunk.Reserve((2 * src.Length) + (2 * words.Length) + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length)));
            var written = Write(space, src, words, lineNumber, out var motion, out var endsProgram, out var values);
            if (written > 0)
            {
                Add(written, lineNumber, motion != BlockMotion.None ? 1 : 0, endsProgram, Math.Max(_o.WordsPerBlock, values));
            }
        }

        /// <summary>Writes one block's chunk text at <paramref name="space"/>; returns its length (0: nothing for the controller).</summary>
        private int Write(Span<byte> space, ReadOnlySpan<byte> src, ReadOnlySpan<GWord> words, int lineNumber, out BlockMotion motion, out bool endsProgram, out int values)
        {
            // Hot path: spans over the batch's word list and line bytes, written straight into the chunk being
            // built; no allocation and no intermediate copy per block.
            var paperFeed = _o.Feed == FeedMode.Paper;
            var feedIndex = -1;
            var nIndex = -1;
            var any = false;
            var scan = default(MotionScan);
            for (var i = 0; i < words.Length; i++)
            {
                switch (words[i].Letter)
                {
                    case 'N':
                        nIndex = nIndex < 0 ? i : nIndex;
                        break;
                    case 'O':
                        break;
                    case 'F' when paperFeed:
                        feedIndex = i;
                        break;
                    default:
                        any = true;
                        scan.Add(words[i], _stops);
                        break;
                }
            }

            if (feedIndex >= 0 && words[feedIndex].Value.Equals(_feedSet))
            {
                // The feed variable already holds this feed: a P500= line would only repeat it.
                feedIndex = -1;
            }

            motion = scan.Result;
            if (motion == BlockMotion.None && scan.ToolChange && _toolChangeMoves)
            {
                // The tool change hook moves the machine: tracked like a dwell (its marker, no feed suffix).
                motion = BlockMotion.Dwell;
            }

            endsProgram = scan.EndsProgram && motion == BlockMotion.None;
            values = 0;
            if (!any && feedIndex < 0)
            {
                return 0; // empty, comment-only, N-only, O-only or an unchanged F: nothing for the controller
            }

            // The room (reserved by the caller) is an upper bound: every word's text plus a separator, the source line
            // once more (for P500=F), markers.
            var o = space;
            if (feedIndex >= 0)
            {
                // Where the program changes F, the value goes into the feed variable so F(P500) keeps it.
                _feedSet = words[feedIndex].Value;
                o = Put(o, _feedVar);
                o[0] = (byte)'=';
                o = Number(o[1..], src, words[feedIndex]);
                o[0] = (byte)'\r';
                o[1] = (byte)'\n';
                o = o[2..];
                values++;
            }

            if (any)
            {
                var sep = false;
                if (_o.KeepN && nIndex >= 0)
                {
                    o[0] = (byte)'N';
                    o = Number(o[1..], src, words[nIndex]);
                    sep = true;
                    values++;
                }

                var tracked = motion != BlockMotion.None;
                if (tracked && _exactTracking)
                {
                    if (sep)
                    {
                        o[0] = (byte)' ';
                        o = o[1..];
                    }

                    o = Track(o, lineNumber);
                    sep = true;
                    values++;
                }

                if (motion == BlockMotion.Stop)
                {
                    // The dwell ends lookahead and carries the marker: M0 names the stop's line while the controller
                    // waits there, whatever the stop code's routine does.
                    _stopCodes.TryAdd(scan.StopCode!, lineNumber);
                    if (sep)
                    {
                        o[0] = (byte)' ';
                        o = o[1..];
                    }

                    o = Put(o, DwellZero);
                    sep = true;
                    values++;
                }

                foreach (ref readonly var w in words)
                {
                    if (w.Letter is 'N' or 'O' || (w.Letter == 'F' && paperFeed))
                    {
                        continue;
                    }

                    if (sep)
                    {
                        o[0] = (byte)' ';
                        o = o[1..];
                    }

                    o[0] = (byte)w.Letter;
                    o = Number(o[1..], src, w);
                    sep = true;
                    values++;
                }

                if (motion == BlockMotion.Move && paperFeed)
                {
                    o = Put(o, _feedSuffix, _feedSuffixWord); // " F(P500)"
                    values++;
                }

                if (tracked && !_exactTracking)
                {
                    o[0] = (byte)' ';
                    o = Track(o[1..], lineNumber);
                    values++;
                }

                o[0] = (byte)'\r';
                o[1] = (byte)'\n';
                o = o[2..];
            }

            return space.Length - o.Length;
        }

        /// <summary>
        /// <see cref="Emit"/> for an <see cref="AxisLine"/>: its text is already the words as emitted, so only the
        /// markers go around it. A move, so it is tracked and (paper feed) gets the feed suffix.
        /// </summary>
        private void EmitAxisLine(ReadOnlySpan<byte> text, int words, int lineNumber)
        {
            // The same bytes as Emit, written through one reference into the reserved space instead of span slices
            // (this runs for nearly every line): the room covers the markers' 8- and 16-byte stores.
            var space = _chunk.Reserve(text.Length + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length)));
            ref var o = ref MemoryMarshal.GetReference(space);
            var at = 0;
            var values = words + 1;
            if (_exactTracking)
            {
                at = TrackAt(ref o, lineNumber);
                Unsafe.Add(ref o, at++) = (byte)' ';
            }

            text.CopyTo(MemoryMarshal.CreateSpan(ref Unsafe.Add(ref o, at), text.Length));
            at += text.Length;
            if (_paperFeed)
            {
                at += PutAt(ref Unsafe.Add(ref o, at), _feedSuffix, _feedSuffixWord); // " F(P500)"
                values++;
            }

            if (!_exactTracking)
            {
                Unsafe.Add(ref o, at++) = (byte)' ';
                at += TrackAt(ref Unsafe.Add(ref o, at), lineNumber);
            }

            Unsafe.WriteUnaligned(ref Unsafe.Add(ref o, at), (ushort)('\r' | ('\n' << 8)));
            Add(at + 2, lineNumber, motions: 1, endsProgram: false, Math.Max(_wordsPerBlock, values));
        }

        /// <summary>Writes a fixed marker at <paramref name="o"/> (one 8-byte store when it fits in 8); returns its length.</summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private static int PutAt(ref byte o, byte[] bytes, ulong word)
        {
            if (bytes.Length <= 8)
            {
                Unsafe.WriteUnaligned(ref o, word);
            }
            else
            {
                bytes.CopyTo(MemoryMarshal.CreateSpan(ref o, bytes.Length));
            }

            return bytes.Length;
        }

        /// <summary>Writes <c>M0==</c> and the line's digits at <paramref name="o"/> (16 bytes of room after the marker); returns the length.</summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private int TrackAt(ref byte o, int sourceLine)
        {
            var at = PutAt(ref o, _trackPrefix, _trackPrefixWord);
            return at + _trackDigits.Write(MemoryMarshal.CreateSpan(ref Unsafe.Add(ref o, at), 16), sourceLine);
        }

        private static Span<byte> Put(Span<byte> o, byte[] bytes)
        {
            bytes.CopyTo(o);
            return o[bytes.Length..];
        }

        /// <summary>
        /// Writes a fixed marker of at most 8 bytes (<paramref name="word"/> holds it, zero-padded) with one 8-byte
        /// store; longer markers, or too little room, take the general copy.
        /// </summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private static Span<byte> Put(Span<byte> o, byte[] bytes, ulong word)
        {
            if (bytes.Length <= 8 && o.Length >= 8)
            {
                MemoryMarshal.Write(o, word);
            }
            else
            {
                bytes.CopyTo(o);
            }

            return o[bytes.Length..];
        }

        private static ulong Word8(byte[] bytes)
        {
            Span<byte> padded = stackalloc byte[8];
            padded.Clear();
            bytes.AsSpan(0, Math.Min(8, bytes.Length)).CopyTo(padded);
            return MemoryMarshal.Read<ulong>(padded);
        }

        /// <summary>A number as written in the source, minus a leading <c>+</c> (the PMAC reads it as an operator).</summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private static Span<byte> Number(Span<byte> o, ReadOnlySpan<byte> src, in GWord w)
        {
            var text = src.Slice(w.NumberStart, w.NumberLength);
            if (text.Length > 1 && text[0] == (byte)'+')
            {
                text = text[1..];
            }

            // Most numbers are under 8 bytes and more line follows them: one 8-byte load and store (the bytes past the
            // number land in reserved space and are overwritten next) instead of a general copy per word.
            var start = w.NumberStart + (w.NumberLength - text.Length);
            if (text.Length <= 8 && src.Length - start >= 8 && o.Length >= 8)
            {
                MemoryMarshal.Write(o, MemoryMarshal.Read<ulong>(src[start..]));
            }
            else
            {
                text.CopyTo(o);
            }

            return o[text.Length..];
        }

        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private Span<byte> Track(Span<byte> o, int sourceLine)
        {
            o = Put(o, _trackPrefix, _trackPrefixWord);
            return o[_trackDigits.Write(o, sourceLine)..];
        }

        /// <summary>
        /// Takes the block just written after the chunk's content (<paramref name="bytes"/> long), starting a new
        /// chunk first when it would break a limit.
        /// </summary>
        private void Add(int bytes, int sourceLine, int motions, bool endsProgram, int words)
        {
            var reserve = _limitReserve;
            if (_chunkBlocks > 0 &&
                (_chunkBlocks >= _linesPerChunk ||
                 _chunk.Length + bytes + reserve > _maxChunkBytes ||
                 _chunkWords + words + _tailWords > _rotWords))
            {
                // Once per chunk: the block waits aside while the full chunk is closed and handed to the writer.
                _block.Clear();
                _block.Append(_chunk.Pending(bytes));
                Flush(last: false);
                _chunk.Append(_block.Span);
            }
            else
            {
                _chunk.Commit(bytes);
            }

            if (_chunkBlocks == 0 &&
                (HeaderBytes.Length + bytes + reserve > _o.MaxChunkBytes || words + _tailWords > _o.RotWords))
            {
                var message = $"block of {bytes} bytes, ~{words} words does not fit one chunk " +
                              $"({_o.MaxChunkBytes} bytes, {_o.RotWords} words, {HeaderBytes.Length + reserve} bytes and {_tailWords} words taken by header and tail); raise --rot-words";
                var d = new Diagnostic(Severity.Error, SplitDiagnosticCodes.BlockTooBig, sourceLine, 1, message);
                throw new SplitException($"{_source}:{sourceLine}: {message}", [d], 1);
            }

            if (_chunkBlocks == 0)
            {
                _chunkFirst = sourceLine;
            }

            _lastBlockStart = _chunk.Length - bytes;
            _lastBlockEndsProgram = endsProgram;
            _chunkBlocks++;
            _chunkWords += words;
            _chunkLast = sourceLine;
            _totalBlocks++;
            _chunkMotion += motions;
            _totalMotion += motions;
        }

        private void Flush(bool last)
        {
            _ct.ThrowIfCancellationRequested();
            var words = _chunkWords;
            if (last)
            {
                // The tail goes before the program's own end code (M02/M30) when that is the last block, so the
                // end code still ends the program; otherwise after the last block.
                if (_lastBlockEndsProgram)
                {
                    _chunk.Insert(_lastBlockStart, _tail);
                }
                else
                {
                    _chunk.Append(_tail);
                }

                words += _tailWords;
            }

            _chunk.Append(FooterBytes);
            var length = _chunk.Length;
            var index = _chunks.Add(_chunkFirst, _chunkLast, _chunkBlocks, _chunkMotion, length, words);
            // The full buffer goes to the writer as it is; an empty one comes back for the next chunk.
            _chunk.Swap(_writer!.Submit(index, _chunks.FilePath(_folder, index), _chunk.Buffer, length));
            _chunk.Append(HeaderBytes);
            _chunkBlocks = 0;
            _chunkMotion = 0;
            _chunkWords = 0;
            _progress?.Report(new SplitProgress(_position, _totalBytes, _chunks.Count, _totalBlocks));
        }
    }
}

/// <summary>Codes of the splitter's own findings (the G-code checker owns the E1xx/E2xx codes).</summary>
public static class SplitDiagnosticCodes
{
    /// <summary>A single block larger than a whole chunk's budget.</summary>
    public const string BlockTooBig = "S001";
}
