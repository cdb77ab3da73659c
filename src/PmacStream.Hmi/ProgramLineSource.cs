using Microsoft.Win32.SafeHandles;
using PmacStream.GCode;

namespace PmacStream.Hmi;

/// <summary>
/// Serves the lines of a program file by number without loading it: a background scan records the byte offset of
/// every <see cref="Stride"/>-th line in a fixed-size table, and a line is read by seeking to the nearest recorded
/// offset and skipping forward. When the table fills, every other entry is dropped and the stride doubles, so the
/// index never takes more than <see cref="MaxCheckpoints"/> offsets whatever the file size (a 10,000,000-line
/// program costs the same 32 KB as a 10-line one). Lines end at LF, CR or CRLF, as <see cref="GCodeReader"/> counts them.
/// </summary>
public sealed class ProgramLineSource : IDisposable
{
    /// <summary>Offsets the index holds at most (a fixed table: memory does not grow with the file).</summary>
    public const int MaxCheckpoints = 4096;

    /// <summary>Characters of one line shown at most; longer lines are cut and end with an ellipsis.</summary>
    public const int MaxDisplayBytes = 1024;

    private const int PageLines = 64;
    private const int CachedPages = 32;
    private const int ScanBufferSize = 1 << 20;

    private readonly SafeFileHandle _handle;
    private readonly long[] _checkpoints;
    private readonly object _gate = new();
    private readonly CancellationTokenSource _cancel = new();
    private readonly LinkedList<(int Page, string[] Lines)> _pages = new();
    private readonly TaskCompletionSource _done = new(TaskCreationOptions.RunContinuationsAsynchronously);
    private readonly List<(int Lines, TaskCompletionSource Waiter)> _waiters = [];
    private int _checkpointCount;
    private int _stride;
    private int _indexedLines;
    private bool _disposed;

    private ProgramLineSource(string path, int maxCheckpoints, int initialStride)
    {
        Path = path;
        _handle = File.OpenHandle(path, FileMode.Open, FileAccess.Read, FileShare.ReadWrite | FileShare.Delete);
        FileSize = RandomAccess.GetLength(_handle);
        _checkpoints = new long[maxCheckpoints];
        _stride = initialStride;
    }

    /// <summary>The file being served.</summary>
    public string Path { get; }

    /// <summary>File size in bytes when it was opened (later growth is ignored).</summary>
    public long FileSize { get; }

    /// <summary>Lines counted so far; the final line count once <see cref="IsComplete"/>.</summary>
    public int IndexedLines => Volatile.Read(ref _indexedLines);

    /// <summary>True once the whole file has been scanned.</summary>
    public bool IsComplete => _done.Task.IsCompleted;

    /// <summary>Completes when the scan has reached the end of the file (faults if the file could not be read).</summary>
    public Task Completion => _done.Task;

    /// <summary>Bytes scanned so far, for an indexing progress display.</summary>
    public long ScannedBytes { get; private set; }

    /// <summary>Lines between two recorded offsets (a power of two that doubles as the file grows).</summary>
    public int Stride
    {
        get
        {
            lock (_gate)
            {
                return _stride;
            }
        }
    }

    /// <summary>Offsets recorded now (at most the table size).</summary>
    public int CheckpointCount
    {
        get
        {
            lock (_gate)
            {
                return _checkpointCount;
            }
        }
    }

    /// <summary>Bytes the offset table takes: fixed at open, independent of the file size.</summary>
    public long IndexBytes => _checkpoints.LongLength * sizeof(long);

    /// <summary>Opens a file and starts indexing it in the background.</summary>
    public static ProgramLineSource Open(string path) => Open(path, MaxCheckpoints);

    /// <summary>Opens with a smaller table (tests exercise the stride doubling with small files).</summary>
    internal static ProgramLineSource Open(string path, int maxCheckpoints, int initialStride = 16)
    {
        if (maxCheckpoints < 2 || initialStride < 1)
        {
            throw new ArgumentOutOfRangeException(nameof(maxCheckpoints));
        }

        var source = new ProgramLineSource(path, maxCheckpoints, initialStride);
        _ = Task.Run(source.Scan);
        return source;
    }

    /// <summary>Completes when at least <paramref name="lines"/> lines are indexed or the scan has ended.</summary>
    public Task WaitForLinesAsync(int lines, CancellationToken cancellationToken = default)
    {
        lock (_gate)
        {
            if (_indexedLines >= lines || _done.Task.IsCompleted)
            {
                return Task.CompletedTask;
            }

            var tcs = new TaskCompletionSource(TaskCreationOptions.RunContinuationsAsynchronously);
            _waiters.Add((lines, tcs));
            return tcs.Task.WaitAsync(cancellationToken);
        }
    }

    /// <summary>
    /// The text of a 1-based line, decoded as UTF-8 or GBK. Only lines already indexed can be asked for
    /// (<see cref="IndexedLines"/>); the view's list size follows that count.
    /// </summary>
    public string GetLine(int lineNumber)
    {
        if (lineNumber < 1 || lineNumber > IndexedLines)
        {
            throw new ArgumentOutOfRangeException(nameof(lineNumber), lineNumber, $"{Path}: line {lineNumber} is outside 1..{IndexedLines}");
        }

        var page = (lineNumber - 1) / PageLines;
        var lines = GetPage(page);
        var i = lineNumber - 1 - (page * PageLines);
        return i < lines.Length ? lines[i] : string.Empty;
    }

    /// <inheritdoc />
    public void Dispose()
    {
        lock (_gate)
        {
            if (_disposed)
            {
                return;
            }

            _disposed = true;
        }

        _cancel.Cancel();
        // The scan may still hold the handle for one read; the OS handle closes when the last user lets go.
        _handle.Dispose();
        _done.TrySetCanceled();
        ReleaseWaiters();
    }

    private string[] GetPage(int page)
    {
        lock (_gate)
        {
            for (var node = _pages.First; node is not null; node = node.Next)
            {
                if (node.Value.Page == page)
                {
                    // Most recently used first, so scrolling back and forth stays cached.
                    _pages.Remove(node);
                    _pages.AddFirst(node);
                    return node.Value.Lines;
                }
            }
        }

        var first = (page * PageLines) + 1;
        var count = Math.Min(PageLines, IndexedLines - first + 1);
        var lines = ReadLines(first, count);
        lock (_gate)
        {
            // A page read while the scan was still short of its end may be incomplete: cache only full pages.
            if (lines.Length == PageLines || IsComplete)
            {
                _pages.AddFirst((page, lines));
                if (_pages.Count > CachedPages)
                {
                    _pages.RemoveLast();
                }
            }
        }

        return lines;
    }

    private string[] ReadLines(int firstLine, int count)
    {
        long offset;
        int lineAtOffset;
        lock (_gate)
        {
            ObjectDisposedException.ThrowIf(_disposed, this);
            var k = Math.Min((firstLine - 1) / _stride, _checkpointCount - 1);
            offset = _checkpoints[k];
            lineAtOffset = (k * _stride) + 1;
        }

        var cursor = new LineCursor(_handle, offset, FileSize);
        for (var line = lineAtOffset; line < firstLine; line++)
        {
            cursor.SkipLine();
        }

        var result = new string[count];
        for (var i = 0; i < count; i++)
        {
            result[i] = cursor.ReadLine();
        }

        return result;
    }

    private void Scan()
    {
        try
        {
            var buffer = new byte[ScanBufferSize];
            var size = FileSize;
            if (size > 0)
            {
                Commit(0);
            }

            long bufferOffset = 0;
            var crAtEnd = false;
            while (bufferOffset < size)
            {
                _cancel.Token.ThrowIfCancellationRequested();
                var n = RandomAccess.Read(_handle, buffer, bufferOffset);
                if (n <= 0)
                {
                    break;
                }

                var span = buffer.AsSpan(0, n);
                var i = 0;
                if (crAtEnd)
                {
                    // The previous buffer ended in CR: a LF here belongs to it (CRLF is one line end).
                    crAtEnd = false;
                    if (span[0] == (byte)'\n')
                    {
                        i = 1;
                    }

                    if (bufferOffset + i < size)
                    {
                        Commit(bufferOffset + i);
                    }
                }

                while (i < n)
                {
                    var j = span[i..].IndexOfAny((byte)'\n', (byte)'\r');
                    if (j < 0)
                    {
                        break;
                    }

                    j += i;
                    if (span[j] == (byte)'\r')
                    {
                        if (j + 1 < n)
                        {
                            if (span[j + 1] == (byte)'\n')
                            {
                                j++;
                            }
                        }
                        else if (bufferOffset + j + 1 < size)
                        {
                            crAtEnd = true;
                            break;
                        }
                    }

                    var start = bufferOffset + j + 1;
                    if (start < size)
                    {
                        Commit(start);
                    }

                    i = j + 1;
                }

                bufferOffset += n;
                ScannedBytes = bufferOffset;
                ReleaseWaiters();
            }

            _done.TrySetResult();
        }
        catch (OperationCanceledException)
        {
            _done.TrySetCanceled();
        }
        catch (ObjectDisposedException)
        {
            _done.TrySetCanceled();
        }
        catch (Exception e)
        {
            _done.TrySetException(new IOException($"{Path}: cannot index the program: {e.Message}", e));
        }

        ReleaseWaiters();
    }

    /// <summary>Records that a new line starts at <paramref name="offset"/>.</summary>
    private void Commit(long offset)
    {
        var lineIndex = _indexedLines; // 0-based index of the line that starts here; only the scan writes it
        if (lineIndex % _stride == 0)
        {
            lock (_gate)
            {
                if (_checkpointCount == _checkpoints.Length)
                {
                    // Full: keep every other offset and double the stride, so the table size is fixed.
                    for (var k = 0; k < _checkpointCount / 2; k++)
                    {
                        _checkpoints[k] = _checkpoints[2 * k];
                    }

                    _checkpointCount /= 2;
                    _stride *= 2;
                }

                if (lineIndex % _stride == 0)
                {
                    _checkpoints[_checkpointCount++] = offset;
                }
            }
        }

        Volatile.Write(ref _indexedLines, lineIndex + 1);
    }

    private void ReleaseWaiters()
    {
        List<TaskCompletionSource>? ready = null;
        lock (_gate)
        {
            for (var i = _waiters.Count - 1; i >= 0; i--)
            {
                if (_waiters[i].Lines <= _indexedLines || _done.Task.IsCompleted)
                {
                    (ready ??= []).Add(_waiters[i].Waiter);
                    _waiters.RemoveAt(i);
                }
            }
        }

        if (ready is not null)
        {
            foreach (var w in ready)
            {
                w.TrySetResult();
            }
        }
    }

    /// <summary>Reads lines forward from a byte offset with a small buffer.</summary>
    private sealed class LineCursor(SafeFileHandle handle, long offset, long size)
    {
        private readonly byte[] _buffer = new byte[1 << 16];
        private readonly byte[] _line = new byte[MaxDisplayBytes];
        private long _bufferOffset = offset;
        private int _pos;
        private int _len;

        public void SkipLine() => Next(null, out _);

        public string ReadLine()
        {
            Next(_line, out var length);
            var text = TextDecoding.Decode(_line.AsSpan(0, Math.Min(length, _line.Length)));
            return length > _line.Length ? text + "…" : text;
        }

        private bool Fill()
        {
            _bufferOffset += _len;
            _pos = 0;
            _len = _bufferOffset >= size ? 0 : RandomAccess.Read(handle, _buffer, _bufferOffset);
            if (_bufferOffset + _len > size)
            {
                _len = (int)(size - _bufferOffset);
            }

            return _len > 0;
        }

        /// <summary>Consumes one line, copying up to the target's length of it; length is the whole line's length.</summary>
        private void Next(byte[]? target, out int length)
        {
            length = 0;
            while (true)
            {
                if (_pos >= _len && !Fill())
                {
                    return;
                }

                var span = _buffer.AsSpan(_pos, _len - _pos);
                var end = span.IndexOfAny((byte)'\n', (byte)'\r');
                var take = end < 0 ? span.Length : end;
                if (target is not null && length < target.Length)
                {
                    span[..Math.Min(take, target.Length - length)].CopyTo(target.AsSpan(length));
                }

                length += take;
                _pos += take;
                if (end < 0)
                {
                    continue;
                }

                var cr = span[end] == (byte)'\r';
                _pos++;
                if (cr && (_pos < _len || Fill()) && _buffer[_pos] == (byte)'\n')
                {
                    _pos++;
                }

                return;
            }
        }
    }
}
