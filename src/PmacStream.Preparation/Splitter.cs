using PmacStream.GCode;
using PmacStream.Preparation.Store;
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
        IProgress<SplitProgress>? progress = null, CancellationToken cancellationToken = default) =>
        SplitCore(sourcePath, options ?? new SplitOptions(), null, progress, cancellationToken);

    /// <summary>
    /// Splits <paramref name="sourcePath"/> as <see cref="Split"/> does and stores it as a program revision in the same
    /// pass: the splitter's check, which decides the chunks, also feeds <paramref name="import"/> (every block's words,
    /// modal state and measured move, the diagnostics, the execution states, the exact source bytes and their SHA-256
    /// from the one read), and the import is completed as soon as the file was read whole, before a refusal is thrown,
    /// so a program with errors is stored with its diagnostics. The rows are those a separate
    /// <see cref="Store.IProgramRevisions.ImportRevision"/> writes. Where one check cannot give both (block delete on
    /// and a block-delete block in the program: the store decodes every block, the split skips those), the import is
    /// given up at that line, nothing of it kept, and <see cref="RevisionImport.Result"/> stays null (the caller
    /// imports separately). A program with subprograms or macros stores the blocks of its expansion, as the split cuts
    /// them (and its source map); its file's bytes are hashed and kept by a read of their own. Needs
    /// <see cref="SplitOptions.CheckProfile"/> (the import's profile).
    /// </summary>
    /// <exception cref="ArgumentException">No check profile, or another profile than the import's.</exception>
    /// <exception cref="System.Data.Common.DbException">The store failed; nothing of the import is kept and nothing is split.</exception>
    public static SplitResult SplitAndImport(string sourcePath, SplitOptions options, RevisionImport import,
        IProgress<SplitProgress>? progress = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(options);
        ArgumentNullException.ThrowIfNull(import);
        if (options.CheckProfile is not { } profile || !ReferenceEquals(profile, import.Profile) && profile.Identity != import.Profile.Identity)
        {
            throw new ArgumentException("a split that imports checks under the import's profile (SplitOptions.CheckProfile)", nameof(options));
        }

        return SplitCore(sourcePath, options, import, progress, cancellationToken);
    }

    private static SplitResult SplitCore(string sourcePath, SplitOptions options, RevisionImport? import,
        IProgress<SplitProgress>? progress, CancellationToken cancellationToken)
    {
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
            var run = new SplitRun(source, temp, options, import, progress, cancellationToken);
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
        private readonly RevisionImport? _import; // the revision stored in the same pass, or null

        public SplitRun(string source, string folder, SplitOptions options, RevisionImport? import, IProgress<SplitProgress>? progress, CancellationToken ct)
        {
            _source = source;
            _import = import;
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
            // The source hash runs on its own thread over a second (page-cached) read, overlapping the split; an import
            // in the same pass hashes (and keeps) the bytes of the one read instead.
            var sourceHash = _import == null ? Task.Run(() => (Sha: FileHash.Sha256Hex(_source, out var hashed), Size: hashed), _ct) : null;
            using var stop = CancellationTokenSource.CreateLinkedTokenSource(_ct);
            using var importQueue = _import != null ? new ImportPipeline.Queue(stop.Token) : null;
            // The store's inserts run on a thread of their own, behind the bounded queue: the slowest stage of the pass.
            var storing = importQueue == null ? null : Task.Factory.StartNew(() => StoreBatches(importQueue, stop), CancellationToken.None, TaskCreationOptions.LongRunning, TaskScheduler.Default);
            ReadOutcome read;
            try
            {
                read = Run(totalBytes, importQueue, storing, stop);
            }
            catch (Exception e) when (storing != null)
            {
                // The storing thread uses the store's connection: it has ended before the caller may dispose it, and its
                // failure (which stopped the reading side) is the one reported.
                importQueue!.Complete();
                if (Ended(storing) is { } failure && e is OperationCanceledException && !_ct.IsCancellationRequested)
                {
                    System.Runtime.ExceptionServices.ExceptionDispatchInfo.Capture(failure).Throw();
                }

                throw;
            }

            string sha;
            if (sourceHash != null)
            {
                (sha, var hashedSize) = sourceHash.GetAwaiter().GetResult();
                if (hashedSize != read.Size)
                {
                    throw new IOException($"{_source}: changed while it was being split ({read.Size} bytes read, {hashedSize} hashed)");
                }
            }
            else
            {
                sha = read.Sha!;
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

        /// <summary>The reading side on its thread, the chunks on this one; the import completed before the split may be refused.</summary>
        private ReadOutcome Run(long totalBytes, ImportPipeline.Queue? importQueue, Task? storing, CancellationTokenSource stop)
        {
            using var full = new HandOff<LineBatch>(QueueDepth, stop.Token);
            using var free = new HandOff<LineBatch>(QueueDepth + 2, stop.Token);
            for (var i = 0; i < QueueDepth + 2; i++)
            {
                free.Add(new LineBatch());
            }

            var importing = importQueue == null ? null : new ImportSide(_import!, importQueue);
            var source = new SourceReader(_source, _folder, totalBytes, _o, full, free, stop.Token, importing);
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
                CompleteImport(read, storing);
                Finish(read);
                writer.Complete();
            }

            return read;
        }

        /// <summary>The storing thread: every batch of the import into the store; a failure stops the reading side.</summary>
        private void StoreBatches(ImportPipeline.Queue queue, CancellationTokenSource stop)
        {
            try
            {
                ImportPipeline.Consume(queue, _import!.Blocks, _import.AfterBatch);
            }
            catch
            {
                stop.Cancel();
                throw;
            }
        }

        /// <summary>The file was read whole: once every batch is stored, the import is completed (kept), unless it was given up.</summary>
        private void CompleteImport(ReadOutcome read, Task? storing)
        {
            if (storing == null)
            {
                return;
            }

            storing.GetAwaiter().GetResult(); // the reading side completed the queue; a store failure surfaces here
            if (read.ImportGivenUp is { } why)
            {
                Logger.Information("{Source}: not stored in the same pass as its split: {Why}", _source, why);
                return;
            }

            if (read.Expanded)
            {
                // The expansion's source map, as the split wrote it beside the chunks, goes with the revision.
                ImportPipeline.StoreMap(Path.Combine(_folder, GCode.Expansion.ExpansionMap.FileName), _import!.Blocks);
            }

            _import!.Complete(read.Summary!, read.Sha!);
        }

        /// <summary>Waits for a task that may have failed; its failure, or null.</summary>
        private static Exception? Ended(Task task)
        {
            try
            {
                task.Wait(CancellationToken.None);
                return null;
            }
            catch (AggregateException e)
            {
                return e.InnerException;
            }
        }
    }

    /// <summary>The import a split feeds in the same pass: the revision and the queue to its storing thread.</summary>
    private sealed record ImportSide(RevisionImport Revision, ImportPipeline.Queue Queue);
}

/// <summary>Codes of the splitter's own findings (the G-code checker owns the E1xx/E2xx codes).</summary>
public static class SplitDiagnosticCodes
{
    /// <summary>A single block larger than a whole chunk's budget.</summary>
    public const string BlockTooBig = "S001";
}
