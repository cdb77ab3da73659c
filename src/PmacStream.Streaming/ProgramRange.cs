using System.Security.Cryptography;
using System.Text;
using PmacStream.Preparation;

namespace PmacStream.Streaming;

/// <summary>
/// Selected-block execution (the seed's third mode): the blocks of source lines A..B of a split program as a program of
/// their own, so the controller receives exactly those blocks, every one once and in order, and nothing after B. Its
/// chunks are the split's chunks that hold A..B, the first starting at A's block (where a start from A begins anyway)
/// and the last ending after B's last line-tracking assignment (and B's move, when the assignment stands alone), then
/// the program's tail and an end code so the rotary program finishes. Its tracked lines, block counts and manifest
/// are those of the range, so the job completes when B has executed and counts the blocks of the range.
/// </summary>
public static class ProgramRange
{
    /// <summary>
    /// The position of the last program line of the block of tracked line <paramref name="line"/> (the last line
    /// carrying its <c>M0==</c>, or the move after a marker that stands alone), or null when no line tracks it.
    /// </summary>
    public static StreamPosition? EndOfBlock(ChunkedProgram program, int line)
    {
        ArgumentNullException.ThrowIfNull(program);
        if (line <= 0)
        {
            return null;
        }

        StreamPosition? last = null;
        var chunk = program.ChunkOfTracked(line);
        for (var c = chunk; c <= program.TotalChunks && c <= chunk + 1; c++)
        {
            var body = program.Body(c);
            for (var i = 0; i < body.Count; i++)
            {
                if (body[i].TrackedLine == line)
                {
                    last = new StreamPosition(c, i);
                }
                else if (body[i].TrackedLine > line && last is not null)
                {
                    return WithMove(program, last.Value);
                }
            }
        }

        return last is { } found ? WithMove(program, found) : null;
    }

    /// <summary>
    /// Writes the range's program into <paramref name="folder"/> (replaced when it holds another) and opens it. The
    /// range starts at the block of <paramref name="fromLine"/> (the first tracked block at or after it; null: the
    /// program's first line) and ends after the block of <paramref name="toLine"/>, followed by <paramref name="end"/>
    /// (the program's tail and end code).
    /// </summary>
    /// <exception cref="ArgumentException">No line tracks <paramref name="toLine"/>, or it lies before the start.</exception>
    public static ChunkedProgram Cut(ChunkedProgram program, int? fromLine, int toLine, string folder, IReadOnlyList<string> end)
    {
        ArgumentNullException.ThrowIfNull(program);
        ArgumentNullException.ThrowIfNull(end);
        var start = fromLine is { } from
            ? program.PositionOfBlock(from) ?? throw new ArgumentException($"line {from}: no block to start at after it", nameof(fromLine))
            : new StreamPosition(1, 0);
        var stop = EndOfBlock(program, toLine)
            ?? throw new ArgumentException($"line {toLine} is not a move the controller tracks (M0=={toLine} is on no line of the split): end the range on a move", nameof(toLine));
        if (stop.Chunk < start.Chunk || (stop.Chunk == start.Chunk && stop.Line < start.Line))
        {
            throw new ArgumentException($"line {toLine} lies before the range's first block (line {program.Body(start.Chunk)[start.Line].TrackedLine})", nameof(toLine));
        }

        var staging = folder + ".tmp-" + Environment.ProcessId.ToString(System.Globalization.CultureInfo.InvariantCulture);
        if (Directory.Exists(staging))
        {
            Directory.Delete(staging, true);
        }

        Directory.CreateDirectory(staging);
        var name = Path.GetFileNameWithoutExtension(program.Manifest.SourcePath);
        var chunks = new List<ChunkInfo>();
        for (var c = start.Chunk; c <= stop.Chunk; c++)
        {
            var first = c == start.Chunk ? start.Line : 0;
            var lastLine = c == stop.Chunk ? stop.Line : program.Body(c).Count - 1;
            chunks.Add(WriteChunk(program, c, first, lastLine, c == stop.Chunk ? end : [], staging, $"{name}_{chunks.Count + 1:0000}.pmc", chunks.Count + 1));
        }

        var manifest = program.Manifest with
        {
            Chunks = chunks,
            TotalBlocks = chunks.Sum(k => k.BlockCount),
            TotalMotionBlocks = chunks.Sum(k => k.MotionBlockCount),
        };
        manifest.Save(Path.Combine(staging, ChunkManifest.FileName));
        Replace(staging, folder, manifest);
        return ChunkedProgram.FromManifest(manifest, folder);
    }

    /// <summary>The tail and the end code that end a range (the end code: M30 when the profile has it, else M02, else none).</summary>
    public static IReadOnlyList<string> EndLines(ChunkManifest manifest, string? endCode)
    {
        ArgumentNullException.ThrowIfNull(manifest);
        var lines = (manifest.ProgramTail ?? string.Empty).Split('\n').Select(l => l.Trim()).Where(l => l.Length > 0).ToList();
        if (endCode is not null)
        {
            lines.Add(endCode);
        }

        return lines;
    }

    /// <summary>A block whose marker stands alone on its line ends with the move after it.</summary>
    private static StreamPosition WithMove(ChunkedProgram program, StreamPosition p)
    {
        var body = program.Body(p.Chunk);
        if (body[p.Line].IsMotion)
        {
            return p;
        }

        for (var k = p.Line + 1; k < body.Count && body[k].TrackedLine == 0; k++)
        {
            if (body[k].IsMotion)
            {
                return new StreamPosition(p.Chunk, k);
            }
        }

        return p;
    }

    /// <summary>Chunk <paramref name="index"/>'s body lines <paramref name="first"/>..<paramref name="last"/> as the file has them, framed, then <paramref name="end"/>.</summary>
    private static ChunkInfo WriteChunk(ChunkedProgram program, int index, int first, int last, IReadOnlyList<string> end, string folder, string fileName, int newIndex)
    {
        var body = program.Body(index);
        var (fromFileLine, toFileLine) = (body[first].FileLine, body[last].FileLine);
        var text = new StringBuilder("CLOSE\r\nOPEN ROT\r\n");
        int words = 0, blocks = 0, motion = 0, tracked = 0, firstTracked = 0, lastTracked = 0;
        using (var reader = new StringReader(Encoding.UTF8.GetString(File.ReadAllBytes(program.ChunkPath(index)))))
        {
            var n = 0;
            while (reader.ReadLine() is { } raw)
            {
                n++;
                var t = raw.Trim();
                if (n < fromFileLine || n > toFileLine || t.Length == 0 || ChunkedProgram.IsFraming(t))
                {
                    continue;
                }

                text.Append(raw).Append("\r\n");
                if (t[0] == ';')
                {
                    continue;
                }

                var line = program.Classify(t);
                words += line.Words;
                blocks += line.TrackedLine == 0 || line.TrackedLine != tracked ? 1 : 0;
                if (line.TrackedLine > 0 && line.TrackedLine != tracked)
                {
                    // The lines of a block the host expanded carry one line: one block.
                    motion++;
                    tracked = line.TrackedLine;
                    firstTracked = firstTracked == 0 ? tracked : firstTracked;
                    lastTracked = tracked;
                }
            }
        }

        foreach (var e in end)
        {
            text.Append(e).Append("\r\n");
            words += program.Classify(e).Words;
        }

        text.Append("CLOSE\r\n");
        var bytes = Encoding.ASCII.GetBytes(text.ToString());
        File.WriteAllBytes(Path.Combine(folder, fileName), bytes);
        var info = program.Chunk(index);
        return new ChunkInfo(newIndex, fileName, firstTracked > 0 ? firstTracked : info.FirstSourceLine, lastTracked > 0 ? lastTracked : info.LastSourceLine,
            blocks, motion, bytes.Length, words, Convert.ToHexStringLower(SHA256.HashData(bytes)));
    }

    /// <summary>
    /// Puts the staged range in place: a folder that already holds the same chunks (the same range of the same split)
    /// is kept as it is (a job may be running from it); another one is replaced.
    /// </summary>
    private static void Replace(string staging, string folder, ChunkManifest manifest)
    {
        var existing = Path.Combine(folder, ChunkManifest.FileName);
        if (File.Exists(existing))
        {
            var held = ChunkManifest.Load(existing);
            if (held.SourceSha256 == manifest.SourceSha256 && held.Chunks.Select(c => c.Sha256).SequenceEqual(manifest.Chunks.Select(c => c.Sha256)))
            {
                Directory.Delete(staging, true);
                return;
            }
        }

        if (Directory.Exists(folder))
        {
            Directory.Delete(folder, true);
        }

        Directory.Move(staging, folder);
    }
}
