using PmacStream.Hmi;

namespace PmacStream.Benchmarks.Hmi;

/// <summary>
/// The screen for the HMI benchmarks, reduced to what they read (the program list's size, the toolpath frames shown,
/// the pane's caption) and the clicks they make (connect, split, execute).
/// </summary>
internal sealed class QuietView : IMainView
{
    public int Frames { get; private set; }

    public string Caption { get; private set; } = string.Empty;

    public IReadOnlyDictionary<TextId, string> Texts { set { } }
    public HmiLanguage Language => HmiLanguage.English;
    public ConnectionSettings ConnectionSettings => new(DeviceKind.Simulator);
    public string ConnectionState { set { } }
    public string ProgramPath { set { } }
    public IReadOnlyList<string> Diagnostics { set { } }
    public int BlocksPerChunk { get; set; }
    public (double Start, double End) DownloadWindow { get; set; }
    public IReadOnlyList<string> Strategies { set { } }
    public string SelectedStrategy => "chunk";
    public IReadOnlyList<string> ChunkFiles { set { } }
    public int SelectedChunk { set { } }
    public int ChunkLineCount { set { } }
    public int ChunkExecutingLine { set { } }
    public int ProgramLineCount { get; set; }
    public int ExecutingLine { set { } }
    public int FocusedLine { set { } }
    public int SelectedLine => 0;
    public CommandStates Commands { set { } }
    public bool SingleBlock => false;
    public double FeedOverride { get; set; }
    public ToolpathFrame Toolpath { set => Frames++; }
    public string ToolpathCaption { set => Caption = value; }
    public StatusDisplay Status { set { } }
    public IReadOnlyList<string> Profiles { set { } }
    public string SelectedProfile { get; set; } = string.Empty;
    public bool OptionalStop { get; set; } = true;
    public string ProgramStopBanner { set { } }
#pragma warning disable CS0067 // events the benchmark never raises
    public event EventHandler? LanguageChanged;
    public event EventHandler? DisconnectRequested;
    public event EventHandler<string>? OpenRequested;
    public event EventHandler? CheckRequested;
    public event EventHandler<int>? DiagnosticActivated;
    public event EventHandler<int>? ChunkSelected;
    public event EventHandler<LineRequestEventArgs>? ChunkLineNeeded;
    public event EventHandler<LineRequestEventArgs>? ProgramLineNeeded;
    public event EventHandler? HoldRequested;
    public event EventHandler? ResumeRequested;
    public event EventHandler? AbortRequested;
    public event EventHandler? StartFromLineRequested;
    public event EventHandler? ResumeInterruptedRequested;
    public event EventHandler? SingleBlockChanged;
    public event EventHandler? FeedOverrideChanged;
    public event EventHandler? DownloadWindowChanged;
    public event EventHandler? ProfileChanged;
    public event EventHandler? OptionalStopChanged;
#pragma warning restore CS0067
    public event EventHandler? ConnectRequested;
    public event EventHandler? SplitRequested;
    public event EventHandler? ExecuteRequested;

    public void Connect() => ConnectRequested?.Invoke(this, EventArgs.Empty);

    public void Split() => SplitRequested?.Invoke(this, EventArgs.Empty);

    public void Execute() => ExecuteRequested?.Invoke(this, EventArgs.Empty);

    public void AppendLog(IReadOnlyList<string> lines) { }
    public Task<bool> ConfirmAsync(string title, string text) => Task.FromResult(false);
    public void ShowError(string message) => throw new InvalidOperationException(message);
}
