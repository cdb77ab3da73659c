using System.Collections.Concurrent;
using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>
/// Check-and-store in two stages on two threads: a worker reads, checks and interprets the program into batches of
/// decoded blocks; the calling thread (which owns the SQLite connection) binds and inserts them. SQLite's insert is
/// the larger stage, so the reader and interpreter run for free beside it on a second core. A bounded queue keeps
/// memory flat whatever the program size. Either side failing stops the other; the first failure is rethrown and
/// the caller's transaction rolls back.
/// </summary>
internal static class ImportPipeline
{
    /// <summary>Where the pipeline's blocks and diagnostics go (one engine's writer), on the calling thread.</summary>
    internal interface IBlockSink
    {
        /// <summary>Adds a block (in program order).</summary>
        void Add(in Interpreter.LastBlock block, ModalState modal);

        /// <summary>Adds a diagnostic.</summary>
        void Add(Diagnostic diagnostic);

        /// <summary>Adds the execution state a start needs, each time it changed (line 0 first: the power-on state).</summary>
        void Add(StoredExecState state);

        /// <summary>Adds the holes of a cycle block (after that block).</summary>
        void Add(int line, CycleHoles holes);

        /// <summary>Adds piece <paramref name="seq"/> (0-based) of an expanded program's source map (<see cref="GCode.Expansion.ExpansionMap"/> text), after every block.</summary>
        void AddExpansionMap(int seq, string text);
    }

    /// <summary>Characters per stored piece of a source map.</summary>
    internal const int MapPiece = 1 << 20;

    /// <summary>Blocks per batch handed between the threads.</summary>
    internal const int BatchSize = 1024;

    /// <summary>Full batches that may wait for the inserting thread.</summary>
    internal const int QueueDepth = 4;

    /// <summary>Runs the check on a worker and stores every block and diagnostic through <paramref name="writer"/>.</summary>
    public static CheckSummary Run(Stream source, string file, MachineProfile profile, IBlockSink writer, Action<Diagnostic>? onDiagnostic,
        CancellationToken cancellationToken, Action? afterBatch = null)
    {
        // An expanded program's blocks are numbered by expanded line: its source map (file, line, calls, iteration of
        // each) is written beside the import into a temporary file, bounded in memory, and stored after the blocks.
        var mapPath = GCode.Expansion.ProgramExpansion.Applies(file, profile) ? Path.GetTempFileName() : null;
        try
        {
            CheckSummary summary;
            using (var mapText = mapPath is null ? null : new StreamWriter(mapPath, false, new System.Text.UTF8Encoding(false), 1 << 16))
            {
                summary = RunPipeline(source, file, profile, writer, onDiagnostic, cancellationToken, afterBatch, mapText);
            }

            if (mapPath is not null)
            {
                StoreMap(mapPath, writer);
            }

            return summary;
        }
        finally
        {
            if (mapPath is not null)
            {
                File.Delete(mapPath);
            }
        }
    }

    /// <summary>Stores an expansion's source map from its text file, in pieces of whole lines.</summary>
    internal static void StoreMap(string mapPath, IBlockSink writer)
    {
        // Whole lines per piece: a piece never ends inside a line (or a character).
        using var r = new StreamReader(mapPath, System.Text.Encoding.UTF8);
        var piece = new System.Text.StringBuilder(MapPiece + 256);
        var seq = 0;
        while (r.ReadLine() is { } line)
        {
            piece.Append(line).Append('\n');
            if (piece.Length >= MapPiece)
            {
                writer.AddExpansionMap(seq++, piece.ToString());
                piece.Clear();
            }
        }

        if (piece.Length > 0)
        {
            writer.AddExpansionMap(seq, piece.ToString());
        }
    }

    private static CheckSummary RunPipeline(Stream source, string file, MachineProfile profile, IBlockSink writer, Action<Diagnostic>? onDiagnostic,
        CancellationToken cancellationToken, Action? afterBatch, TextWriter? mapText)
    {
        using var stop = CancellationTokenSource.CreateLinkedTokenSource(cancellationToken);
        using var queue = new Queue(stop.Token);
        var producer = Task.Factory.StartNew(
            () =>
            {
                try
                {
                    return Produce(source, file, profile, onDiagnostic, queue, mapText, stop.Token);
                }
                finally
                {
                    queue.Complete();
                }
            },
            CancellationToken.None,
            TaskCreationOptions.LongRunning,
            TaskScheduler.Default);

        try
        {
            Consume(queue, writer, afterBatch);
        }
        catch
        {
            // The store failed: stop the reader (it may be waiting for room in the queue), then report the store's error.
            stop.Cancel();
            try
            {
                producer.Wait();
            }
            catch (AggregateException)
            {
            }

            throw;
        }

        // The reader's own failure (I/O, cancellation, a throwing callback) surfaces here, unwrapped.
        return producer.GetAwaiter().GetResult();
    }

    /// <summary>
    /// The storing side: every batch the reading side hands over, in order, into <paramref name="writer"/>, until the
    /// reading side completes the queue. Runs on the thread that may use the store's connection.
    /// </summary>
    internal static void Consume(Queue queue, IBlockSink writer, Action? afterBatch)
    {
        foreach (var batch in queue.Full.GetConsumingEnumerable())
        {
            for (var i = 0; i < batch.Count; i++)
            {
                writer.Add(in batch.Blocks[i], batch.Modals[i]!);
            }

            foreach (var d in batch.Diagnostics)
            {
                writer.Add(d);
            }

            foreach (var s in batch.States)
            {
                writer.Add(s);
            }

            foreach (var (line, holes) in batch.Holes)
            {
                writer.Add(line, holes);
            }

            batch.Clear();
            queue.Free.Add(batch);
            afterBatch?.Invoke();
        }
    }

    /// <summary>The reading side: checks the program (through its expansion when it has one) and hands full batches on.</summary>
    private static CheckSummary Produce(Stream source, string file, MachineProfile profile, Action<Diagnostic>? onDiagnostic,
        Queue queue, TextWriter? mapText, CancellationToken token)
    {
        var feed = new Feed(profile, queue, onDiagnostic, token);
        var checker = new Checker(profile) { Canon = feed.Canon };
        CheckSummary summary;
        if (GCode.Expansion.ProgramExpansion.Applies(file, profile))
        {
            // Subprograms, macros or o-words: the blocks stored are the expansion's, as the controller gets
            // them (M0== numbers those); the source bytes are still the file's, read here for their hash.
            source.CopyTo(Stream.Null);
            var map = new GCode.Expansion.ExpansionMap(1 << 16);
            if (mapText is not null)
            {
                map.WriteTo(mapText);
            }

            summary = GCode.Expansion.ProgramExpansion.Check(checker, file, feed.OnDiagnostic, feed.OnInterpreted, null, token, map);
        }
        else
        {
            summary = checker.Check(source, file, feed.OnDiagnostic, feed.OnInterpreted, token);
        }

        feed.Finish();
        return summary;
    }

    /// <summary>The bounded hand-over between the reading side and the storing side: full batches one way, emptied ones back.</summary>
    internal sealed class Queue : IDisposable
    {
        /// <summary>A queue of <see cref="QueueDepth"/> full batches, its waits ended by <paramref name="token"/>.</summary>
        public Queue(CancellationToken token)
        {
            Token = token;
            for (var i = 0; i < QueueDepth + 2; i++)
            {
                Free.Add(new Batch());
            }
        }

        /// <summary>Ends the reading side's waits (the storing side failed, or the caller cancelled).</summary>
        public CancellationToken Token { get; }

        /// <summary>Batches for the storing side, in program order.</summary>
        public BlockingCollection<Batch> Full { get; } = new(QueueDepth);

        /// <summary>Batches the storing side emptied.</summary>
        public BlockingCollection<Batch> Free { get; } = new();

        /// <summary>The reading side ended (whole or not): the storing side ends after what was handed over.</summary>
        public void Complete() => Full.CompleteAdding();

        /// <inheritdoc />
        public void Dispose()
        {
            Full.Dispose();
            Free.Dispose();
        }
    }

    /// <summary>
    /// The reading side of an import, fed by a check as it interprets: each block's record (its words and modal state
    /// from the interpreter's record of the line; its move, holes, corner and offsets from the canonical calls, which
    /// <see cref="Canon"/> must receive), the diagnostics and the execution states, in batches handed to the storing
    /// side. <see cref="ImportPipeline"/>'s own check feeds one; so does the splitter's reading side when a split
    /// stores the revision in the same pass.
    /// </summary>
    internal sealed class Feed
    {
        private readonly Queue _queue;
        private readonly Action<Diagnostic>? _onDiagnostic;
        private readonly CornerHold _corners;
        private readonly ExecStateTracker _states;
        private readonly Decisions _decided = new();
        private Batch _batch;

        /// <summary>A feed into <paramref name="queue"/> under <paramref name="profile"/>; <paramref name="onDiagnostic"/> also sees each diagnostic.</summary>
        public Feed(MachineProfile profile, Queue queue, Action<Diagnostic>? onDiagnostic, CancellationToken token)
        {
            _queue = queue;
            _onDiagnostic = onDiagnostic;
            _corners = new CornerHold(queue.Full, token);
            _states = new ExecStateTracker(profile);
            _batch = queue.Free.Take(token);
            _batch.States.Add(_states.Initial);
        }

        /// <summary>Where the check's interpreter must make its canonical calls (alone, or beside other consumers).</summary>
        public ICanonicalMoves Canon => _decided;

        /// <summary>A diagnostic of the check, in line order.</summary>
        public void OnDiagnostic(Diagnostic d)
        {
            _batch.Diagnostics.Add(d);
            _onDiagnostic?.Invoke(d);
        }

        /// <summary>After each block: its record, holes, corner and the execution state when it changed.</summary>
        public void OnInterpreted(Interpreter interp)
        {
            var batch = _batch;
            var decided = _decided;
            batch.Add(in interp.Last, interp.State, decided);
            if (decided.Holes is { } holes)
            {
                batch.Holes.Add((interp.Last.Line, holes));
            }

            _corners.Added(batch, decided);

            if (_states.After(interp.Last.Line, decided, interp.State) is { } changed)
            {
                batch.States.Add(changed);
            }

            if (batch.Count == BatchSize)
            {
                _corners.Full(batch);
                _batch = _queue.Free.Take(_queue.Token);
            }
        }

        /// <summary>The check ended whole: the last batch (and one held for an inside corner) goes to the storing side.</summary>
        public void Finish()
        {
            _corners.Release();
            _queue.Full.Add(_batch, _queue.Token);
        }
    }

    /// <summary>
    /// What the interpreter decided for the line it took last, from its canonical calls: the move (when it moved), a
    /// cycle's holes, the inside corner, the offset in force and the tables it left (read at once, before the next step).
    /// </summary>
    internal sealed class Decisions : ICanonicalMoves
    {
        private CanonMotion _motion;

        /// <summary>The line moved (or dwelt): <see cref="Move"/> holds its motion.</summary>
        public bool Moved { get; private set; }

        /// <summary>The line's motion, when <see cref="Moved"/>.</summary>
        public ref readonly CanonMotion Move => ref _motion;

        /// <summary>A cycle block's holes, else null.</summary>
        public CycleHoles? Holes { get; private set; }

        /// <summary>At a G41/G42 inside corner: where the move held (and the moves queued behind it) end instead, on X and Y.</summary>
        public Point3? AmendedEnd { get; private set; }

        /// <summary>The line's part in the moves held under G41/G42 (<see cref="CanonBlock.Hold"/>).</summary>
        public CompensationHold Hold { get; private set; }

        /// <summary>The offset from program to machine coordinates in force after the line.</summary>
        public Point3 Offset { get; private set; }

        /// <summary>The work offset and tool tables and the shifts as the line left them (live).</summary>
        public WorkCoordinates? Tables { get; private set; }

        public void StartBlock(in CanonStart start) => Moved = false;

        public void Step(in HostMove step)
        {
        }

        public void Motion(in CanonMotion motion) => (_motion, Moved) = (motion, true);

        public void EndBlock(in CanonBlock block) =>
            (Holes, AmendedEnd, Hold, Offset, Tables) = (block.Holes, block.AmendedEnd, block.Hold, block.Offset, block.Tables);
    }

    /// <summary>
    /// The records of the moves held under G41/G42 (the interpreter's decision, <see cref="CanonBlock.Hold"/>): an
    /// inside corner at the next XY move moves the held move's end, and the plunges and retracts queued behind it, to
    /// the crossing (<see cref="CanonBlock.AmendedEnd"/>), so a full batch holding one of them waits until that move is
    /// known. The hold spans at most <see cref="Interpreter.MaxHeldCompensationBlocks"/> blocks after the move, fewer
    /// than a batch, so at most one batch waits.
    /// </summary>
    private sealed class CornerHold(BlockingCollection<Batch> full, CancellationToken token)
    {
        private readonly HeldMoves<(Batch Batch, int Index)> _held = new(Move);
        private readonly List<(Batch Batch, int Index)> _moves = new(1), _final = new(2);
        private Batch? _pending;

        /// <summary>After a block was added to <paramref name="batch"/>: the interpreter's decision for it; a batch waiting goes on once nothing in it is held.</summary>
        public void Added(Batch batch, Decisions decided)
        {
            _moves.Clear();
            if (decided.Moved)
            {
                _moves.Add((batch, batch.Count - 1));
            }

            _held.Take(decided.Hold, decided.AmendedEnd, _moves, _final);
            _final.Clear();
            if (_held.Count == 0)
            {
                Release();
            }
        }

        /// <summary>A full batch goes on, unless it holds a move still held.</summary>
        public void Full(Batch batch)
        {
            Release();
            if (_held.Count > 0)
            {
                _pending = batch;
            }
            else
            {
                full.Add(batch, token);
            }
        }

        /// <summary>Hands the batch waiting for the next XY move on.</summary>
        public void Release()
        {
            if (_pending is { } p)
            {
                full.Add(p, token);
                _pending = null;
            }
        }

        /// <summary>
        /// The record of a move an inside corner moved: the held move ends at the crossing, its length and time what is
        /// left; a move queued behind it runs at the crossing (both ends), its length and time its own.
        /// </summary>
        private static (Batch Batch, int Index) Move((Batch Batch, int Index) at, Point3 crossing, bool held)
        {
            ref var block = ref at.Batch.Blocks[at.Index];
            if (held)
            {
                var end = AmendedMove.MovedTo(block.End, crossing);
                var part = AmendedMove.Fraction(block.Motion, block.Start, block.End, block.Center, end);
                (block.End, block.Length, block.DurationSeconds) = (end, block.Length * part, block.DurationSeconds * part);
            }
            else
            {
                (block.Start, block.End) = (AmendedMove.MovedTo(block.Start, crossing), AmendedMove.MovedTo(block.End, crossing));
            }

            return at;
        }
    }

    /// <summary>Decoded blocks (interpreter fields plus the shared, immutable modal state) and diagnostics.</summary>
    internal sealed class Batch
    {
        public readonly Interpreter.LastBlock[] Blocks = new Interpreter.LastBlock[BatchSize];
        public readonly ModalState?[] Modals = new ModalState?[BatchSize];
        public readonly List<Diagnostic> Diagnostics = [];
        public readonly List<StoredExecState> States = [];
        public readonly List<(int Line, CycleHoles Holes)> Holes = [];

        public int Count { get; private set; }

        /// <summary>A block: the line's words from <paramref name="line"/>, its move from the canonical <paramref name="decided"/>.</summary>
        public void Add(in Interpreter.LastBlock line, ModalState modal, Decisions decided)
        {
            ref var b = ref Blocks[Count];
            b = line;
            if (decided.Moved)
            {
                ref readonly var m = ref decided.Move;
                (b.Motion, b.Start, b.End, b.Center, b.Length, b.DurationSeconds) = (m.Kind, m.Start, m.End, m.Centre, m.Length, m.Seconds);
            }

            Modals[Count] = modal;
            Count++;
        }

        public void Clear()
        {
            Count = 0;
            Diagnostics.Clear();
            States.Clear();
            Holes.Clear();
        }
    }
}
