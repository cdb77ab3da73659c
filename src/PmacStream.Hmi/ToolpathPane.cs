using PmacStream.Preview;
using Serilog;
using SkiaSharp;

namespace PmacStream.Hmi;

/// <summary>
/// What the toolpath pane shows, computed for the passive view: the planned toolpath drawn once per program by the
/// preview renderer (off the UI thread, decimated to the pane's pixels), the executed part drawn over it as the
/// job's M0 advances (only the moves between the last one drawn and the executing block, from the status the job
/// already has: the controller is not asked for more), and a marker where the tool stands. Memory stays that of
/// three pane-sized pictures and one pass over the program, whatever its length.
/// </summary>
internal sealed class ToolpathPane : IDisposable
{
    /// <summary>Longest the UI thread spends drawing executed moves in one tick (the rest follows on the next).</summary>
    public static readonly TimeSpan TickBudget = TimeSpan.FromMilliseconds(8);

    /// <summary>Width of the executed path's stroke, pixels.</summary>
    public const float ExecutedWidth = 3;

    // Pane-sized pictures are copied pixel for pixel: no filtering.
    private static readonly SKSamplingOptions Copy = new(SKFilterMode.Nearest);

    private readonly IMainView _view;
    private readonly IHmiBackend _backend;
    private readonly ILogger _log;
    private readonly PreviewPalette _palette = new();
    private readonly ToolpathFrame _frame;
    private readonly SKCanvas _frameCanvas;
    private CancellationTokenSource? _work;
    private string? _path;
    private long? _programId; // the store revision drawn from its stored blocks, or null (the file)
    private GCode.MachineProfile? _profile;
    private Task<PreviewPicture>? _rendering;
    private double _renderFraction;
    private PreviewPicture? _planned;
    private SKBitmap? _executed;
    private SKCanvas? _executedCanvas;
    private ExecutedPathTracer? _tracer;
    private CancellationTokenSource? _traceWork;
    private Task? _skipping;
    private int _pendingFirstLine;
    private string? _failure;
    private string _caption = string.Empty;

    /// <summary>A pane of <see cref="HmiLayout.ToolpathPane"/>'s size showing on <paramref name="view"/>.</summary>
    public ToolpathPane(IMainView view, IHmiBackend backend, ILogger log)
    {
        _view = view;
        _backend = backend;
        _log = log;
        _frame = new ToolpathFrame(HmiLayout.ToolpathPane.Width, HmiLayout.ToolpathPane.Height, _palette.Background);
        _frameCanvas = new SKCanvas(_frame.Bitmap);
        _view.Toolpath = _frame;
    }

    /// <summary>The colour of the executed path (tests and the UI test count its pixels).</summary>
    public SKColor ExecutedColour => _palette.Executed;

    /// <summary>The language of the caption.</summary>
    public HmiLanguage Language { get; set; }

    /// <summary>True once the planned picture is shown.</summary>
    public bool Ready => _planned is not null;

    /// <summary>Executed moves drawn for the current job.</summary>
    public long ExecutedMoves => _tracer?.Drawn ?? 0;

    /// <summary>Draws the planned toolpath of a newly opened program (or of the same under another profile), in the background.</summary>
    /// <param name="path">The program file.</param>
    /// <param name="profile">The profile it is interpreted under.</param>
    /// <param name="programId">The store's revision it is (opened from the store): drawn from its stored blocks; null: the file.</param>
    public void Open(string path, GCode.MachineProfile profile, long? programId = null)
    {
        Forget();
        _programId = programId;
        _frame.Bitmap.Erase(_palette.Background);
        _view.Toolpath = _frame;
        _path = path;
        _profile = profile;
        _work = new CancellationTokenSource();
        var token = _work.Token;
        var source = Source();
        var options = new PreviewOptions
        {
            Width = _frame.Width,
            Height = _frame.Height,
            Legend = false,
            Palette = _palette,
            Progress = (f, _) => Volatile.Write(ref _renderFraction, f),
        };
        _renderFraction = 0;
        _rendering = Task.Run(() => PreviewRenderer.Render(source, options, null, token), token);
        Show();
    }

    /// <summary>
    /// The open program is now stored revision <paramref name="programId"/> (its split found or imported it; null: a
    /// file): what is read from now on (the executed path) reads its stored blocks. The planned picture stays: it was
    /// drawn from the same bytes under the same profile, so drawing it again would show nothing new.
    /// </summary>
    public void Stored(long? programId)
    {
        if (_path is not null)
        {
            _programId = programId;
        }
    }

    /// <summary>The program's toolpath: a stored revision's stored blocks, else the file.</summary>
    private IToolpathSource Source() =>
        _programId is { } id ? _backend.OpenStoredToolpath(id, _path!, _profile!) : _backend.OpenToolpath(_path!, _profile!);

    /// <summary>Forgets the program (a new one is opened, or it is closed) and shows the empty pane.</summary>
    public void Close()
    {
        Forget();
        _frame.Bitmap.Erase(_palette.Background);
        _view.Toolpath = _frame;
        Show();
    }

    /// <inheritdoc />
    /// <remarks>No view calls: the window may already be gone.</remarks>
    public void Dispose()
    {
        Forget();
        _frameCanvas.Dispose();
        _frame.Dispose();
    }

    private void Forget()
    {
        _work?.Cancel();
        if (_rendering is { IsCompleted: false } pending)
        {
            // Nobody waits for a cancelled drawing; whatever it made is freed when it ends.
            _ = pending.ContinueWith(t => { if (t.IsCompletedSuccessfully) { t.Result.Dispose(); } }, TaskScheduler.Default);
        }

        EndTrace();
        _rendering = null;
        _planned?.Dispose();
        _planned = null;
        _executedCanvas?.Dispose();
        _executedCanvas = null;
        _executed?.Dispose();
        _executed = null;
        _work?.Dispose();
        _work = null;
        _path = null;
        _failure = null;
    }

    /// <summary>
    /// A job starts at <paramref name="firstLine"/>: the executed part is drawn anew from there (lines before it did
    /// not run in this job and are passed over, off the UI thread).
    /// </summary>
    public void BeginJob(int firstLine)
    {
        EndTrace();
        _pendingFirstLine = Math.Max(1, firstLine);
        if (_planned is not null)
        {
            StartTrace();
        }
    }

    /// <summary>
    /// One timer period: installs the planned picture once drawn, shows the drawing progress meanwhile, and draws the
    /// executed moves up to the job's executing line (all of them once the job completed).
    /// </summary>
    public void Tick(HmiJobStatus? status)
    {
        if (_rendering is { IsCompleted: true } done)
        {
            _rendering = null;
            Install(done);
        }

        if (_tracer is { } tracer && status is not null && _skipping is null or { IsCompleted: true })
        {
            _skipping = null;
            var through = status.State == HmiJobState.Completed ? long.MaxValue : status.CurrentLine;
            var before = tracer.Position;
            if (tracer.DrawBefore(through, TickBudget) > 0 || before != tracer.Position)
            {
                Compose();
            }
        }

        Show();
    }

    private void Install(Task<PreviewPicture> done)
    {
        if (!done.IsCompletedSuccessfully)
        {
            if (!done.IsCanceled)
            {
                _failure = done.Exception?.GetBaseException().Message ?? "unknown error";
                _log.Warning("Toolpath of {Path:l} cannot be drawn: {Message:l}", _path, _failure);
            }

            return;
        }

        _planned = done.Result;
        _executed = _planned.Image.Copy(SKColorType.Bgra8888);
        _executedCanvas = new SKCanvas(_executed);
        if (_pendingFirstLine > 0)
        {
            StartTrace();
        }

        Compose();
    }

    private void StartTrace()
    {
        // The executed part of this job only: the planned picture again under it.
        _executedCanvas!.DrawBitmap(_planned!.Image, 0, 0, Copy);

        _traceWork = CancellationTokenSource.CreateLinkedTokenSource(_work!.Token);
        var token = _traceWork.Token;
        var tracer = new ExecutedPathTracer(Source(), _planned.Projection, _executedCanvas, _palette.Executed, ExecutedWidth, token);
        _tracer = tracer;
        var first = _pendingFirstLine;
        _skipping = first > 1 ? Task.Run(() => tracer.SkipBefore(first), token) : null;
        Compose();
    }

    private void EndTrace()
    {
        var tracer = _tracer;
        var work = _traceWork;
        work?.Cancel();
        if (_skipping is { IsCompleted: false } skipping)
        {
            // The pass over the skipped lines ends at the cancellation; its tracer is freed after it.
            _ = skipping.ContinueWith(_ => Free(tracer, work), TaskScheduler.Default);
        }
        else
        {
            Free(tracer, work);
        }

        _tracer = null;
        _traceWork = null;
        _skipping = null;
        _pendingFirstLine = 0;

        static void Free(ExecutedPathTracer? tracer, CancellationTokenSource? work)
        {
            tracer?.Dispose();
            work?.Dispose();
        }
    }

    private void Compose()
    {
        if (_executed is null)
        {
            return;
        }

        _frameCanvas.DrawBitmap(_executed, 0, 0, Copy);
        _frameCanvas.Flush();
        if (_tracer?.Position is { } at)
        {
            _planned!.DrawMarker(_frame.Bitmap, at);
        }

        _view.Toolpath = _frame;
    }

    private void Show()
    {
        var name = _path is null ? string.Empty : Path.GetFileName(_path);
        var caption = _path is null ? HmiText.Get(TextId.Toolpath, Language)
            : _failure is not null ? HmiText.Format(TextId.ToolpathFailed, Language, name, _failure)
            : _planned is null ? HmiText.Format(TextId.ToolpathDrawing, Language, name, (int)(Volatile.Read(ref _renderFraction) * 100))
            : HmiText.Format(TextId.ToolpathReady, Language, name, _planned.Extents.Moves);
        if (caption != _caption)
        {
            _caption = caption;
            _view.ToolpathCaption = caption;
        }
    }
}
