namespace PmacStream.Streaming;

/// <summary>
/// <see cref="ChunkedProgram.BlocksThrough"/> kept as running totals for the status of every tick: the blocks of the
/// chunks before (summed once) and, per chunk execution is in, its tracked lines read once when execution enters it,
/// so a tick costs a binary search instead of a rescan of the chunk. A chunk whose tracked lines do not rise (none
/// the splitter writes today) is counted by <see cref="ChunkedProgram.BlocksThrough"/> itself, so the count is the
/// same whatever the program. Thread-safe: the status may be read off the ticking thread.
/// </summary>
internal sealed class ExecutedBlockCount
{
    private readonly ChunkedProgram _program;
    private int[]? _blocksBefore;
    private int _chunk;
    private readonly List<int> _lines = [];
    private bool _rising;
    private int _lastTracked = -1;
    private int _last;

    /// <summary>Counts for <paramref name="program"/>.</summary>
    public ExecutedBlockCount(ChunkedProgram program) => _program = program;

    /// <summary>Motion blocks executed when the tracking variable reads <paramref name="trackedLine"/> (as <see cref="ChunkedProgram.BlocksThrough"/>).</summary>
    public int Through(int trackedLine)
    {
        if (trackedLine <= 0)
        {
            return 0;
        }

        lock (_lines)
        {
            return Count(trackedLine);
        }
    }

    private int Count(int trackedLine)
    {
        if (trackedLine == _lastTracked)
        {
            return _last;
        }

        var chunk = _program.ChunkOfTracked(trackedLine);
        if (chunk != _chunk)
        {
            Enter(chunk);
        }

        if (_rising)
        {
            // The lines are distinct and rising: those at or before the tracked one are a prefix.
            var at = System.Runtime.InteropServices.CollectionsMarshal.AsSpan(_lines).BinarySearch(trackedLine);
            _last = BlocksBefore(chunk) + (at >= 0 ? at + 1 : ~at);
        }
        else
        {
            _last = _program.BlocksThrough(trackedLine);
        }

        _lastTracked = trackedLine;
        return _last;
    }

    private int BlocksBefore(int chunk)
    {
        if (_blocksBefore is null)
        {
            var sums = new int[_program.TotalChunks + 1];
            for (var i = 1; i < sums.Length; i++)
            {
                sums[i] = sums[i - 1] + _program.Chunk(i).MotionBlockCount;
            }

            _blocksBefore = sums;
        }

        return _blocksBefore[chunk - 1];
    }

    /// <summary>Reads the chunk's tracked lines once: distinct, in order, and whether they rise.</summary>
    private void Enter(int chunk)
    {
        _chunk = 0; // a chunk that cannot be read is read again next time
        var lines = _lines;
        lines.Clear();
        var rising = true;
        foreach (var l in _program.Body(chunk))
        {
            if (l.TrackedLine <= 0 || (lines.Count > 0 && l.TrackedLine == lines[^1]))
            {
                continue;
            }

            rising &= lines.Count == 0 || l.TrackedLine > lines[^1];
            lines.Add(l.TrackedLine);
        }

        _chunk = chunk;
        _rising = rising;
    }
}
