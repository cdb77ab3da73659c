using PmacStream.GCode;
using Serilog;

namespace PmacStream.Preparation;

/// <summary>
/// Cuts a G-code program into rotary-buffer chunk files a Turbo PMAC accepts, streaming the
/// source (memory does not grow with its size). Each chunk is <c>CLOSE</c>, <c>OPEN ROT</c>, one line per source
/// block (plus a <c>P500=</c> line where the program sets F), and <c>CLOSE</c>; the last one carries the program
/// tail. Lines are ASCII with CR LF ends. Output goes to a temporary folder renamed into place at the end, so a
/// failure leaves no half-written set.
/// </summary>
public static partial class Splitter
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
            source, outDir, options.BlocksPerChunk, options.RotWords, options.MaxChunkBytes);
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
            if (!(name == ChunkManifest.FileName || name == GCode.Expansion.ExpansionMap.FileName || name.EndsWith(ChunkExtension, StringComparison.OrdinalIgnoreCase) || IsDownloadReport(f)) || Directory.Exists(f))
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
    /// One split in progress, and its writing side. Two threads share the work and nothing else: the reading thread
    /// (<see cref="SourceReader"/>, which owns its state) lexes the source (and runs the checker on the same blocks
    /// when <see cref="SplitOptions.CheckProfile"/> is set) and hands batches of lines over a bounded queue, in order,
    /// to the calling thread, which builds the chunks; a third writes and hashes
    /// the chunk files (<see cref="ChunkFileWriter"/>) and a fourth hashes the source. Most CAM lines are plain
    /// axis moves in the mode in force: those take the <see cref="AxisLine"/> lane (lexed in one scan of the read
    /// buffer, checked by <see cref="CheckRun.TryAxisLine"/>, handed over as their emitted text); every other line
    /// takes the general lexer, checker and emitter, with the same results (AxisLaneTests compare the two).
    /// </summary>
    private sealed partial class SplitRun
    {
        private const int QueueDepth = 2;

        private readonly string _source;
        private readonly string _folder;
        private readonly SplitOptions _o;
        private readonly CancellationToken _ct;
        private readonly int _wordsPerBlock;       // read for every block, held in a field
        private readonly ChunkLineWriter _lines;   // a block's chunk text
        private readonly ChunkPacker _packer;      // the chunks, under the budgets
        private ReadOutcome? _read;                // the reading side's findings, once it finished

        public SplitRun(string source, string folder, SplitOptions options, IProgress<SplitProgress>? progress, CancellationToken ct)
        {
            _source = source;
            _folder = folder;
            _o = options;
            _ct = ct;
            _wordsPerBlock = options.WordsPerBlock;
            _lines = new ChunkLineWriter(options);
            _packer = new ChunkPacker(source, folder, options, progress, ct);
        }

        /// <summary>The codes the program uses that the controller cannot run yet, with their first line (null without a profile).</summary>
        public IReadOnlyDictionary<string, int>? NotYetCodes => _read?.NotYet;

        /// <summary>Lines the <see cref="AxisLine"/> lane took (read after <see cref="Execute"/>).</summary>
        public int LaneLines => _read?.LaneLines ?? 0;

        /// <summary>Of <see cref="LaneLines"/>, those scanned straight in the read buffer.</summary>
        public int BufferLaneLines => _read?.BufferLaneLines ?? 0;

        /// <summary>
        /// The checker runs in this pass whenever there is a profile: it decides refusal (unless forced) and, forced or
        /// not, which words the controller must not get (W003: a word the block does not use is not ignored by a PMAC).
        /// </summary>
        private bool Checking => _o.CheckProfile != null;

        public (ChunkManifest Manifest, int Warnings) Execute()
        {
            var totalBytes = _packer.TotalBytes = new FileInfo(_source).Length;
            // The source hash runs on its own thread over a second (page-cached) read, overlapping the split.
            var sourceHash = Task.Run(() => (Sha: FileHash.Sha256Hex(_source, out var hashed), Size: hashed), _ct);
            using var stop = CancellationTokenSource.CreateLinkedTokenSource(_ct);
            using var full = new HandOff<LineBatch>(QueueDepth, stop.Token);
            using var free = new HandOff<LineBatch>(QueueDepth + 2, stop.Token);
            for (var i = 0; i < QueueDepth + 2; i++)
            {
                free.Add(new LineBatch());
            }

            var source = new SourceReader(_source, _folder, totalBytes, _o, full, free, stop.Token);
            ReadOutcome read;
            using (var writer = new ChunkFileWriter(_packer.Chunks, _o.AfterChunkWritten, _ct, (int)Math.Min(_o.MaxChunkBytes + 256, 1 << 20)))
            {
                _packer.WriteTo(writer);
                var reading = Task.Factory.StartNew(source.Read, CancellationToken.None, TaskCreationOptions.LongRunning, TaskScheduler.Default);
                try
                {
                    // Batches arrive in source order (one producer, one FIFO queue), so chunks keep the source order.
                    while (full.TryTake(out var batch))
                    {
                        Consume(batch);
                        batch.Clear();
                        free.Add(batch);
                    }

                    read = reading.GetAwaiter().GetResult(); // rethrows what stopped the reading thread
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

                _read = read;
                Finish(read);
                writer.Complete();
            }

            var (sha, hashedSize) = sourceHash.GetAwaiter().GetResult();
            if (hashedSize != read.Size)
            {
                throw new IOException($"{_source}: changed while it was being split ({read.Size} bytes read, {hashedSize} hashed)");
            }

            var manifest = new ChunkManifest(_source, read.Size, sha, _packer.TotalBlocks, _packer.TotalMotion, _o.TrackVariable,
                _o.Tracking, _o.Feed, _o.FeedVariable, _packer.Chunks)
            {
                Shape = _o.ResolvedShape,
                CheckedProfile = _o.CheckedProfile,
                NotYetCodes = read.NotYet,
                StopCodes = _lines.StopCodes,
            };
            return (manifest, read.Warnings);
        }
    }
}

/// <summary>Codes of the splitter's own findings (the G-code checker owns the E1xx/E2xx codes).</summary>
public static class SplitDiagnosticCodes
{
    /// <summary>A single block larger than a whole chunk's budget.</summary>
    public const string BlockTooBig = "S001";
}
