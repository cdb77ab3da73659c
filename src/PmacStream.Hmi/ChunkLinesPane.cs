using PmacStream.Jobs;

namespace PmacStream.Hmi;

/// <summary>
/// "Lines of the selected file": the lines of one chunk file. While a job runs they follow execution: the executing
/// chunk is selected in ListBox1 and its row holding the executing block's synchronous assignment (<c>M0==line</c>)
/// is highlighted and kept in view. The operator may select another chunk meanwhile; the list then stays where the
/// operator put it and follows again once the operator selects the executing chunk, or once execution reaches the
/// chunk the operator is looking at, or when the next job starts.
/// </summary>
internal sealed class ChunkLinesPane : IDisposable
{
    private readonly IMainView _view;
    private readonly IHmiBackend _backend;
    private SplitView? _split;
    private ProgramLineSource? _lines;
    private int _shown = -1;
    private int[] _trackedLines = [];
    private int[] _fileLines = [];
    private int _executingRow;
    private bool _following = true;

    /// <summary>The pane on <paramref name="view"/>; <paramref name="backend"/> says which rows carry the tracked lines.</summary>
    public ChunkLinesPane(IMainView view, IHmiBackend backend)
    {
        _view = view;
        _backend = backend;
    }

    /// <summary>The chunk shown (0-based), -1 for none.</summary>
    public int Shown => _shown;

    /// <summary>True while the list follows execution (no other chunk chosen by the operator).</summary>
    public bool Following => _following;

    /// <summary>The split whose chunks are listed (null: none); shows no chunk.</summary>
    public void SetProgram(SplitView? split)
    {
        _split = split;
        Show(-1);
        _following = true;
    }

    /// <summary>
    /// The operator selected chunk <paramref name="index"/> (0-based, -1 for none) in ListBox1. While a job executes
    /// chunk <paramref name="executingChunk"/> (1-based, 0 for no job) the list follows again only when it is that one.
    /// </summary>
    public void Select(int index, int executingChunk)
    {
        Show(index);
        _following = executingChunk == 0 || index == executingChunk - 1;
    }

    /// <summary>A job starts: the list follows it.</summary>
    public void BeginJob() => _following = true;

    /// <summary>
    /// Shows where the job stands: selects the executing chunk (1-based) while following, and highlights the row of
    /// <paramref name="executingLine"/> when the executing chunk is the one shown.
    /// </summary>
    public void Follow(int executingChunk, int executingLine)
    {
        var index = executingChunk - 1;
        if (_split is null || index < 0 || index >= _split.Chunks.Count)
        {
            return;
        }

        if (!_following && index == _shown)
        {
            // Execution reached the chunk the operator is looking at.
            _following = true;
        }

        if (_following && index != _shown)
        {
            Show(index);
            _view.SelectedChunk = index;
        }

        ShowExecutingRow(index == _shown ? RowOf(executingLine) : 0);
    }

    /// <summary>The text of row <paramref name="line"/> of the chunk file shown.</summary>
    public string Line(int line) =>
        _lines is { } c && line >= 1 && line <= c.IndexedLines ? c.GetLine(line) : string.Empty;

    /// <inheritdoc />
    public void Dispose()
    {
        _lines?.Dispose();
        _lines = null;
    }

    private void Show(int index)
    {
        _lines?.Dispose();
        _lines = null;
        _shown = -1;
        _trackedLines = [];
        _fileLines = [];
        ShowExecutingRow(0);
        if (_split is not { } split || index < 0 || index >= split.Chunks.Count)
        {
            _view.ChunkLineCount = 0;
            return;
        }

        var chunk = split.Chunks[index];
        _shown = index;
        try
        {
            // Chunk files are small (the rotary-buffer budget), so waiting for the whole index is quick.
            var lines = ProgramLineSource.Open(split.ChunkPath(chunk));
            lines.Completion.Wait(TimeSpan.FromSeconds(5));
            _lines = lines;
            _view.ChunkLineCount = lines.IndexedLines;

            // Which file row carries each block's M0==line, read as the session reads the chunk.
            var rows = _backend.ReadChunkRows(split, index + 1);
            _trackedLines = [.. rows.TrackedLines];
            _fileLines = [.. rows.FileLines];
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException or AggregateException or InvalidDataException)
        {
            _view.ChunkLineCount = _lines?.IndexedLines ?? 0;
            _view.ShowError($"{chunk.FileName}: {e.GetBaseException().Message}");
        }
    }

    /// <summary>The file row of the block of <paramref name="line"/> (or of the last block before it), 0 when none.</summary>
    private int RowOf(int line)
    {
        var i = Array.BinarySearch(_trackedLines, line);
        if (i < 0)
        {
            i = ~i - 1;
        }

        return i >= 0 ? _fileLines[i] : 0;
    }

    private void ShowExecutingRow(int row)
    {
        if (row != _executingRow)
        {
            _executingRow = row;
            _view.ChunkExecutingLine = row;
        }
    }
}
