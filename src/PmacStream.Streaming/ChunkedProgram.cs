using System.Security.Cryptography;
using System.Text;
using System.Text.RegularExpressions;
using PmacStream.Preparation;

namespace PmacStream.Streaming;

/// <summary>Where the next program line to send lies: chunk (1-based) and 0-based line within the chunk's body.</summary>
/// <param name="Chunk">1-based chunk index; <c>TotalChunks + 1</c> means everything was sent.</param>
/// <param name="Line">0-based index into the chunk's body lines (the lines between <c>OPEN ROT</c> and <c>CLOSE</c>).</param>
public readonly record struct StreamPosition(int Chunk, int Line)
{
    /// <inheritdoc />
    public override string ToString() => $"chunk {Chunk} line {Line}";
}

/// <summary>One rotary-buffer program line of a chunk body.</summary>
/// <param name="Text">The line as it is sent.</param>
/// <param name="TrackedLine">The source line of its <c>M0==n</c> marker, 0 when it carries none.</param>
/// <param name="IsMotion">True when the line commands a move or dwell.</param>
/// <param name="Words">Estimated rotary-buffer words the line takes.</param>
/// <param name="FileLine">1-based line number in the chunk file.</param>
public readonly record struct ProgramLine(string Text, int TrackedLine, bool IsMotion, int Words, int FileLine);

/// <summary>
/// A split program as the streamer sees it: the manifest and its chunk files, read lazily (a chunk at a time, the
/// last few cached) so a program of any size streams in bounded memory.
/// </summary>
public sealed class ChunkedProgram
{
    private static readonly Regex MotionWords = new(
        @"(?<![A-Z])(?:[XYZABCUVWIJK]\s*[-+]?[\d.(]|DWELL|DELAY|G0?4(?!\d))",
        RegexOptions.Compiled | RegexOptions.CultureInvariant | RegexOptions.IgnoreCase);

    private static readonly Regex Values = new(@"[A-Z]+\s*(?:==|=)?\s*[-+]?[\d.(]", RegexOptions.Compiled | RegexOptions.CultureInvariant | RegexOptions.IgnoreCase);

    private readonly Regex _feedExpression;
    private readonly Dictionary<int, IReadOnlyList<ProgramLine>> _cache = new();
    private readonly Queue<int> _cacheOrder = new();
    private int _finalTrackedLine = -1;
    private string? _lineProbe;

    /// <summary>Program lines per chunk a line-probe value can address (<see cref="ProbeValue"/>).</summary>
    internal const long ProbeLinesPerChunk = 100_000;

    private ChunkedProgram(ChunkManifest manifest, string folder)
    {
        Manifest = manifest;
        Folder = folder;
        Sync = SyncAssignment.Of(manifest);
        var f = Regex.Escape(string.IsNullOrWhiteSpace(manifest.FeedVariable) ? "P500" : manifest.FeedVariable.Trim());
        _feedExpression = new Regex($@"F\s*\(\s*{f}\s*\)", RegexOptions.Compiled | RegexOptions.CultureInvariant | RegexOptions.IgnoreCase);
    }

    /// <summary>The manifest.</summary>
    public ChunkManifest Manifest { get; }

    /// <summary>The tracking assignment (<c>M0==n</c>) the chunk lines carry.</summary>
    public SyncAssignment Sync { get; }

    /// <summary>The folder holding the manifest and chunk files.</summary>
    public string Folder { get; }

    /// <summary>Number of chunks.</summary>
    public int TotalChunks => Manifest.Chunks.Count;

    /// <summary>
    /// The line-probe variable (e.g. <c>P501</c>), or null. When set, every non-motion body line (every line with
    /// paper placement, <see cref="ProbesEveryLine"/>) is sent with a plain
    /// (calculation-time) assignment <c>P501=n</c> in front, <c>n</c> = <see cref="ProbeValue"/> of its position.
    /// A non-motion line carries no <c>M0==</c> (and a synchronous assignment would only show with the next move),
    /// so after a download broke off and the buffer drained, the probe is what tells whether the controller got it.
    /// </summary>
    public string? LineProbeVariable => _lineProbe;

    /// <summary>
    /// True when the probe goes on every line, moves too: with paper placement (<c>... M0==n</c> last) a move's
    /// marker is only written when the next move starts, so after a drain M0 names the move before the last one
    /// that arrived, and only the probe tells that the last one arrived.
    /// </summary>
    public bool ProbesEveryLine => _lineProbe is not null && Sync.LagsOneMove;

    /// <summary>Sets <see cref="LineProbeVariable"/> (null or empty: off); bodies read before are re-read. True when it changed.</summary>
    public bool UseLineProbe(string? variable)
    {
        var v = string.IsNullOrWhiteSpace(variable) ? null : variable.Trim().ToUpperInvariant();
        if (v is not null && !Regex.IsMatch(v, @"^P\d+$", RegexOptions.CultureInvariant))
        {
            throw new ArgumentException($"line-probe variable '{variable}' must be a P variable such as P501 (48 bits hold the probe values)", nameof(variable));
        }

        lock (_cache)
        {
            if (v == _lineProbe)
            {
                return false;
            }

            _lineProbe = v;
            _cache.Clear();
            _cacheOrder.Clear();
            return true;
        }
    }

    /// <summary>The probe value of the body line at <paramref name="position"/>: chunk x 100000 + line + 1 (never 0).</summary>
    public static long ProbeValue(StreamPosition position) => (position.Chunk * ProbeLinesPerChunk) + position.Line + 1;

    /// <summary>The position just after the line whose probe value is <paramref name="value"/>; null for 0 or a value outside the program.</summary>
    public StreamPosition? PositionAfterProbe(long value)
    {
        if (value <= 0)
        {
            return null;
        }

        var chunk = value / ProbeLinesPerChunk;
        var line = (value % ProbeLinesPerChunk) - 1;
        if (chunk < 1 || chunk > TotalChunks || line < 0 || line >= Body((int)chunk).Count)
        {
            return null;
        }

        return Normalize(new StreamPosition((int)chunk, (int)line + 1));
    }

    /// <summary>
    /// The file to hand to <c>Download</c> for a chunk: the chunk file itself, or (with a line probe and non-motion
    /// lines in it) an annotated copy in a temporary folder, line for line, so a refused line maps to the same file line.
    /// <paramref name="temporary"/> tells the caller to delete the copy (and what Download wrote next to it).
    /// </summary>
    public string SendPath(int index, out bool temporary)
    {
        temporary = false;
        var path = ChunkPath(index);
        // Checked at every download, not only when first read: Download reads the file itself.
        var bytes = ReadVerified(index);
        if (_lineProbe is null)
        {
            return path;
        }

        var body = Body(index);
        var byFileLine = new Dictionary<int, string>();
        foreach (var l in body)
        {
            if ((ProbesEveryLine || (l.TrackedLine == 0 && !l.IsMotion)) && l.FileLine > 0)
            {
                byFileLine[l.FileLine] = l.Text;
            }
        }

        if (byFileLine.Count == 0)
        {
            return path;
        }

        var dir = Path.Combine(Path.GetTempPath(), "pmacstream-send", $"{Environment.ProcessId}-{Guid.NewGuid():N}");
        Directory.CreateDirectory(dir);
        var copy = Path.Combine(dir, Path.GetFileName(path));
        using (var w = new StreamWriter(copy, append: false, System.Text.Encoding.ASCII))
        {
            var n = 0;
            foreach (var raw in Lines(bytes))
            {
                n++;
                w.Write(byFileLine.TryGetValue(n, out var annotated) ? annotated : raw);
                w.Write("\r\n");
            }
        }

        temporary = true;
        return copy;
    }

    /// <summary>Opens a split program from its <c>manifest.json</c> (or the folder holding it).</summary>
    public static ChunkedProgram Open(string manifestPathOrFolder)
    {
        var path = Directory.Exists(manifestPathOrFolder) ? Path.Combine(manifestPathOrFolder, ChunkManifest.FileName) : manifestPathOrFolder;
        if (!File.Exists(path))
        {
            throw new FileNotFoundException($"{path}: no chunk manifest (split the program first)", path);
        }

        var manifest = ChunkManifest.Load(path);
        if (manifest.Chunks.Count == 0)
        {
            throw new InvalidDataException($"{path}: the manifest lists no chunks");
        }

        return new ChunkedProgram(manifest, Path.GetDirectoryName(Path.GetFullPath(path))!);
    }

    /// <summary>Wraps a manifest already in memory whose chunk files lie in <paramref name="folder"/>.</summary>
    public static ChunkedProgram FromManifest(ChunkManifest manifest, string folder) => new(manifest, folder);

    /// <summary>The chunk's info (1-based index).</summary>
    public ChunkInfo Chunk(int index) => Manifest.Chunks[index - 1];

    /// <summary>Full path of a chunk file (1-based index).</summary>
    public string ChunkPath(int index) => Path.Combine(Folder, Chunk(index).FileName);

    /// <summary>
    /// The body lines of a chunk: everything except <c>CLOSE</c>, <c>OPEN ROT</c>, blank and comment-only lines.
    /// The last four chunks read stay cached.
    /// </summary>
    public IReadOnlyList<ProgramLine> Body(int index)
    {
        lock (_cache)
        {
            if (_cache.TryGetValue(index, out var cached))
            {
                return cached;
            }
        }

        var path = ChunkPath(index);
        var list = new List<ProgramLine>(Math.Max(16, Chunk(index).BlockCount + 8));
        var fileLine = 0;
        foreach (var raw in Lines(ReadVerified(index)))
        {
            fileLine++;
            var t = raw.Trim();
            if (t.Length == 0 || t[0] == ';' || IsFraming(t))
            {
                continue;
            }

            var l = Classify(t, fileLine);
            if (_lineProbe is not null && (ProbesEveryLine || (l.TrackedLine == 0 && !l.IsMotion)))
            {
                l = Annotate(l, ProbeValue(new StreamPosition(index, list.Count)));
            }

            list.Add(l);
        }

        if (_lineProbe is not null && list.Count >= ProbeLinesPerChunk)
        {
            throw new InvalidDataException($"{path}: {list.Count} program lines in one chunk; a line probe addresses at most {ProbeLinesPerChunk - 1} (split into smaller chunks)");
        }

        lock (_cache)
        {
            _cache[index] = list;
            _cacheOrder.Enqueue(index);
            while (_cacheOrder.Count > 4)
            {
                _cache.Remove(_cacheOrder.Dequeue());
            }
        }

        return list;
    }

    /// <summary>
    /// Reads a chunk file whole and checks it against the manifest's SHA-256, so a chunk edited, truncated or
    /// replaced after the split is never sent: its lines would no longer be the blocks the tracking and the
    /// checkpoints count. Throws <see cref="InvalidDataException"/> naming the file.
    /// </summary>
    private byte[] ReadVerified(int index)
    {
        var info = Chunk(index);
        var path = ChunkPath(index);
        var bytes = File.ReadAllBytes(path);
        if (!string.IsNullOrEmpty(info.Sha256))
        {
            var actual = Convert.ToHexStringLower(SHA256.HashData(bytes));
            if (!actual.Equals(info.Sha256, StringComparison.OrdinalIgnoreCase))
            {
                throw new InvalidDataException(
                    $"{path}: chunk {index} changed since the split ({bytes.Length} bytes, SHA-256 {actual[..12]}; the manifest says {info.ByteSize} bytes, {info.Sha256[..Math.Min(12, info.Sha256.Length)]}): split the program again");
            }
        }

        return bytes;
    }

    /// <summary>The lines of a chunk file's bytes, split as <see cref="File.ReadLines(string)"/> does.</summary>
    private static IEnumerable<string> Lines(byte[] bytes)
    {
        using var reader = new StringReader(Encoding.UTF8.GetString(bytes));
        while (reader.ReadLine() is { } line)
        {
            yield return line;
        }
    }

    /// <summary>Classifies one program line (marker, motion, words).</summary>
    public ProgramLine Classify(string text, int fileLine = 0)
    {
        var marked = Sync.TryRead(text, out var tracked);
        var rest = _feedExpression.Replace(marked ? Sync.Without(text) : text, " ");
        return new ProgramLine(text, tracked, MotionWords.IsMatch(rest), Math.Max(1, Values.Count(text)), fileLine);
    }

    private ProgramLine Annotate(ProgramLine l, long probe)
    {
        // After an N label (which must lead the line), before everything else: the probe is set when the line is
        // calculated, whatever the rest of the line calls.
        var t = l.Text;
        var label = Regex.Match(t, @"^N\d+\s*", RegexOptions.CultureInvariant | RegexOptions.IgnoreCase);
        var text = label.Success
            ? string.Concat(t.AsSpan(0, label.Length), $"{_lineProbe}={probe} ", t.AsSpan(label.Length))
            : $"{_lineProbe}={probe} {t}";
        return l with { Text = text, Words = l.Words + 1 };
    }

    /// <summary>True for the lines that frame a chunk (<c>CLOSE</c>, <c>OPEN ROT</c>); they are not buffer content.</summary>
    public static bool IsFraming(string trimmed) =>
        trimmed.Equals("CLOSE", StringComparison.OrdinalIgnoreCase)
        || Regex.IsMatch(trimmed, @"^OPEN\s+ROT(ARY)?$", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant)
        || Regex.IsMatch(trimmed, @"^CLOSE\s+OPEN\s+ROT(ARY)?$", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant);

    /// <summary>The tracked source lines of the whole program in order (reads every chunk once; for checks).</summary>
    public IEnumerable<int> TrackedLines()
    {
        var last = 0;
        for (var c = 1; c <= TotalChunks; c++)
        {
            foreach (var l in Body(c))
            {
                // A block the host expands (a canned cycle, a reference return) is several controller lines that all
                // carry its line: one block.
                if (l.TrackedLine > 0 && l.TrackedLine != last)
                {
                    last = l.TrackedLine;
                    yield return l.TrackedLine;
                }
            }
        }
    }

    /// <summary>
    /// The blocks the host expands into several controller lines that each carry the block's tracking assignment (a
    /// canned cycle, a reference return), by source line, with how many they carry: each fires on the controller, so
    /// an executed-move check counts that many assignments as one block (reads every chunk once).
    /// </summary>
    public IReadOnlyDictionary<int, int> ExpandedBlocks()
    {
        var expanded = new Dictionary<int, int>();
        int last = 0, run = 0;
        for (var c = 1; c <= TotalChunks; c++)
        {
            foreach (var l in Body(c))
            {
                if (l.TrackedLine <= 0)
                {
                    continue;
                }

                run = l.TrackedLine == last ? run + 1 : 1;
                last = l.TrackedLine;
                if (run > 1)
                {
                    expanded[last] = run;
                }
            }
        }

        return expanded;
    }

    /// <summary>The last tracked source line of the program (the block whose execution ends the job).</summary>
    public int FinalTrackedLine
    {
        get
        {
            if (_finalTrackedLine < 0)
            {
                var last = 0;
                for (var c = TotalChunks; c >= 1 && last == 0; c--)
                {
                    foreach (var l in Body(c))
                    {
                        if (l.TrackedLine > 0)
                        {
                            last = l.TrackedLine;
                        }
                    }
                }

                _finalTrackedLine = last;
            }

            return _finalTrackedLine;
        }
    }

    /// <summary>Where <paramref name="trackedLine"/> lies in chunk <paramref name="index"/>, as a fraction of its source lines (0.65 = line 650 of 1000).</summary>
    public double FractionOfChunk(int index, int trackedLine)
    {
        var c = Chunk(index);
        var size = Math.Max(1, c.LastSourceLine - c.FirstSourceLine + 1);
        return (double)(trackedLine - c.FirstSourceLine + 1) / size;
    }

    /// <summary>The chunk executing when the tracking variable reads <paramref name="trackedLine"/> (0: before the first).</summary>
    public int ChunkOfTracked(int trackedLine)
    {
        if (trackedLine <= 0)
        {
            return 1;
        }

        var c = Manifest.ChunkOfLine(trackedLine);
        if (c is not null)
        {
            return c.Index;
        }

        // In a gap or past the end: the last chunk that starts at or before the line.
        var best = 1;
        foreach (var ci in Manifest.Chunks)
        {
            if (ci.FirstSourceLine <= trackedLine)
            {
                best = ci.Index;
            }
        }

        return best;
    }

    /// <summary>
    /// The position just after the block of tracked line <paramref name="trackedLine"/> (its marker line and, when the
    /// marker stands alone, the move that follows it): where sending resumes once that block is known executed.
    /// Returns the start when the line is 0; null when the line is not a tracked line of this program.
    /// </summary>
    public StreamPosition? PositionAfterBlock(int trackedLine)
    {
        if (trackedLine <= 0)
        {
            return new StreamPosition(1, 0);
        }

        var chunk = ChunkOfTracked(trackedLine);
        for (var c = chunk; c <= TotalChunks && c <= chunk + 1; c++)
        {
            var body = Body(c);
            for (var i = 0; i < body.Count; i++)
            {
                if (body[i].TrackedLine != trackedLine)
                {
                    continue;
                }

                var j = i;
                if (!body[i].IsMotion)
                {
                    // Marker alone on its line: the block's move is the next motion line before another marker.
                    for (var k = i + 1; k < body.Count && body[k].TrackedLine == 0; k++)
                    {
                        if (body[k].IsMotion)
                        {
                            j = k;
                            break;
                        }
                    }
                }

                return Normalize(new StreamPosition(c, j + 1));
            }
        }

        return null;
    }

    /// <summary>The position of the first program line of the block that tracks source line <paramref name="sourceLine"/>
    /// or, when that line carries no move, of the first tracked block after it; null past the end.</summary>
    public StreamPosition? PositionOfBlock(int sourceLine)
    {
        for (var c = ChunkOfTracked(sourceLine); c <= TotalChunks; c++)
        {
            var body = Body(c);
            for (var i = 0; i < body.Count; i++)
            {
                if (body[i].TrackedLine >= sourceLine)
                {
                    return new StreamPosition(c, i);
                }
            }
        }

        return null;
    }

    /// <summary>
    /// Motion blocks executed when the tracking variable reads <paramref name="trackedLine"/>: the blocks of earlier
    /// chunks (the manifest's counts) plus the tracked lines up to it in its own chunk.
    /// </summary>
    public int BlocksThrough(int trackedLine)
    {
        if (trackedLine <= 0)
        {
            return 0;
        }

        var c = ChunkOfTracked(trackedLine);
        var n = 0;
        for (var i = 1; i < c; i++)
        {
            n += Chunk(i).MotionBlockCount;
        }

        var last = 0;
        foreach (var l in Body(c))
        {
            // The lines of a block the host expanded carry one line: one block.
            if (l.TrackedLine > 0 && l.TrackedLine <= trackedLine && l.TrackedLine != last)
            {
                last = l.TrackedLine;
                n++;
            }
        }

        return n;
    }

    /// <summary>
    /// Where the program stands stopped: the stop block of <paramref name="trackedLine"/> (the tracking variable names a
    /// stop block while the controller waits there), or with paper placement, where the variable lags a block, the
    /// line the probe says was calculated last (<paramref name="probeValue"/>). The code is the block's first stop code
    /// (<see cref="ChunkManifest.StopCodes"/>); null when the block has none (the program was stopped otherwise).
    /// </summary>
    public ProgramStop StopAt(int trackedLine, long? probeValue = null)
    {
        var line = trackedLine;
        string? text = null;
        if (Sync.LagsOneMove && probeValue is { } value && PositionAfterProbe(value) is { } after && LastLineBefore(after) is { } calculated)
        {
            line = calculated.TrackedLine > 0 ? calculated.TrackedLine : line;
            text = calculated.Text;
        }
        else if (trackedLine > 0 && PositionAfterBlock(trackedLine) is { } end && LastLineBefore(end) is { } block)
        {
            text = block.Text;
        }

        return new ProgramStop(line, text is null ? null : StopCodeIn(text));
    }

    /// <summary>The first of the manifest's stop codes on a chunk line (the tracking assignment and the probe left out).</summary>
    private string? StopCodeIn(string text)
    {
        if (Manifest.StopCodes is not { Count: > 0 } codes)
        {
            return null;
        }

        var rest = Sync.Without(text);
        foreach (Match m in Regex.Matches(rest, @"(?<![A-Z0-9.=])M\s*(\d+(?:\.\d+)?)(?![=\d])", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant))
        {
            var value = double.Parse(m.Groups[1].ValueSpan, System.Globalization.CultureInfo.InvariantCulture);
            foreach (var code in codes.Keys)
            {
                if (double.TryParse(code.AsSpan(1), System.Globalization.NumberStyles.Float, System.Globalization.CultureInfo.InvariantCulture, out var c) && c == value)
                {
                    return code;
                }
            }
        }

        return null;
    }

    /// <summary>The body line just before <paramref name="position"/>, or null at the very start.</summary>
    private ProgramLine? LastLineBefore(StreamPosition position)
    {
        for (var c = Math.Min(position.Chunk, TotalChunks); c >= 1; c--)
        {
            var body = Body(c);
            var i = c == position.Chunk ? position.Line - 1 : body.Count - 1;
            if (i >= 0 && i < body.Count)
            {
                return body[i];
            }
        }

        return null;
    }

    /// <summary>The tracked line of the last marker before <paramref name="position"/> (0 when none).</summary>
    public int LastTrackedBefore(StreamPosition position)
    {
        var c = Math.Min(position.Chunk, TotalChunks);
        var line = position.Chunk > TotalChunks ? int.MaxValue : position.Line;
        for (; c >= 1; c--, line = int.MaxValue)
        {
            var body = Body(c);
            for (var i = Math.Min(line, body.Count) - 1; i >= 0; i--)
            {
                if (body[i].TrackedLine > 0)
                {
                    return body[i].TrackedLine;
                }
            }
        }

        return 0;
    }

    /// <summary>Moves a position that lies at the end of a chunk to the start of the next one.</summary>
    public StreamPosition Normalize(StreamPosition p)
    {
        while (p.Chunk <= TotalChunks && p.Line >= Body(p.Chunk).Count)
        {
            p = new StreamPosition(p.Chunk + 1, 0);
        }

        return p;
    }

    /// <summary>True when the position lies past the last line.</summary>
    public bool IsEnd(StreamPosition p) => Normalize(p).Chunk > TotalChunks;
}
