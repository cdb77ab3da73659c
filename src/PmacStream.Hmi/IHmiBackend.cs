using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preview;

namespace PmacStream.Hmi;

/// <summary>The kinds of controller link the connection panel offers.</summary>
public enum DeviceKind
{
    /// <summary>The built-in simulated Turbo PMAC.</summary>
    Simulator,

    /// <summary>Ethernet (VR_PMAC packets on TCP port 1025).</summary>
    Ethernet,

    /// <summary>RS-232 serial port.</summary>
    Serial,

    /// <summary>Delta Tau's PComm32 driver (Windows).</summary>
    Pcomm32,
}

/// <summary>What the connection panel holds.</summary>
/// <param name="Device">Link type.</param>
/// <param name="EthernetAddress">Host or IP, optionally with <c>:port</c> (default port 1025).</param>
/// <param name="SerialPort">Serial port name (COM1, /dev/ttyS0).</param>
/// <param name="Baud">Serial baud rate.</param>
/// <param name="PcommDevice">PComm32 device number.</param>
public sealed record ConnectionSettings(
    DeviceKind Device,
    string EthernetAddress = "192.168.0.200",
    string SerialPort = "COM1",
    int Baud = 38400,
    int PcommDevice = 0)
{
    /// <summary>The link as every face spells it (<c>sim</c>, <c>tcp://host:port</c>, <c>serial:port@baud</c>, <c>pcomm32:n</c>).</summary>
    /// <exception cref="FormatException">The address or port is not valid.</exception>
    public ConnectionSpec ToSpec() => Device switch
    {
        DeviceKind.Ethernet => ConnectionSpec.Ethernet(EthernetAddress),
        DeviceKind.Serial => ConnectionSpec.SerialLine(SerialPort, Baud),
        DeviceKind.Pcomm32 => ConnectionSpec.Pcomm(PcommDevice),
        _ => ConnectionSpec.Simulator,
    };

    /// <summary>A short description for the log.</summary>
    public override string ToString() => Device switch
    {
        DeviceKind.Ethernet => $"ethernet {EthernetAddress}",
        DeviceKind.Serial => $"serial {SerialPort}@{Baud}",
        DeviceKind.Pcomm32 => $"pcomm32 device {PcommDevice}",
        _ => "simulator",
    };
}

/// <summary>A check's findings.</summary>
/// <param name="Diagnostics">The findings in line order (a huge program's list may be cut; the counts are not).</param>
/// <param name="Blocks">Blocks in the program.</param>
/// <param name="Errors">Findings that stop the program.</param>
/// <param name="Warnings">Findings that let it run.</param>
public sealed record HmiCheckResult(IReadOnlyList<Diagnostic> Diagnostics, long Blocks, int Errors, int Warnings)
{
    /// <summary>Counts the severities of a complete list.</summary>
    public static HmiCheckResult FromList(IReadOnlyList<Diagnostic> diagnostics, long blocks) =>
        new(diagnostics, blocks, diagnostics.Count(d => d.Severity == Severity.Error), diagnostics.Count(d => d.Severity == Severity.Warning));
}

/// <summary>Where a job stands.</summary>
public enum HmiJobState
{
    /// <summary>Created, not started.</summary>
    Idle,

    /// <summary>Executing (or waiting in single-block mode for the next start).</summary>
    Running,

    /// <summary>Feed hold.</summary>
    Held,

    /// <summary>Every block executed.</summary>
    Completed,

    /// <summary>Stopped by the operator.</summary>
    Aborted,

    /// <summary>Stopped by an error; resumable from its checkpoint.</summary>
    Failed,

    /// <summary>At a program stop (M00, M01 with optional stop on): the controller waits; Resume continues.</summary>
    Stopped,
}

/// <summary>A job's status as the status bar shows it.</summary>
/// <param name="State">Job state.</param>
/// <param name="CurrentChunk">1-based chunk executing (0 before the first).</param>
/// <param name="CurrentLine">Source line executing, from the tracking variable (0 before the first move).</param>
/// <param name="Percent">Executed share of the program, 0..100.</param>
/// <param name="FeedOverride">The coordinate system's feed override in percent as the controller last reported it (it slews to a new setting); null when unknown.</param>
/// <param name="ProgrammedFeed">The program's feed (F) in force at the executing block; null before the first block or when unknown.</param>
/// <param name="Elapsed">Time since start.</param>
/// <param name="Eta">Estimated time to the end, when known.</param>
/// <param name="Message">Why it stopped, for Failed (and Aborted) jobs.</param>
/// <param name="Stop">Where the program stands stopped while <paramref name="State"/> is <see cref="HmiJobState.Stopped"/>, else null.</param>
/// <param name="OptionalStop">True while the controller stops at M01 (the optional-stop switch).</param>
public sealed record HmiJobStatus(
    HmiJobState State,
    int CurrentChunk,
    int CurrentLine,
    double Percent,
    double? FeedOverride,
    double? ProgrammedFeed,
    TimeSpan Elapsed,
    TimeSpan? Eta,
    string? Message = null,
    JobStop? Stop = null,
    bool OptionalStop = true)
{
    /// <summary>
    /// Where <see cref="CurrentLine"/> came from when the program was expanded (subprograms, macros, loops: <c>O1002 line
    /// 7, call 3 of 4 from line 12</c>); null for a program whose lines are its source lines.
    /// </summary>
    public string? SourceLocation { get; init; }

    /// <summary>True once the job will not move again.</summary>
    public bool IsFinished => State is HmiJobState.Completed or HmiJobState.Aborted or HmiJobState.Failed;
}

/// <summary>Everything needed to start streaming a split program.</summary>
/// <param name="Program">The split program.</param>
/// <param name="Strategy">Download strategy name (one of <see cref="IHmiBackend.Strategies"/>).</param>
/// <param name="FromLine">Start at this source line (with the restore preamble), or null for the beginning.</param>
/// <param name="SingleBlock">One block per start.</param>
/// <param name="FeedOverride">The feed override (percent) set before the start.</param>
/// <param name="Settings">Buffer words, download window, tick period and safe Z of the job.</param>
public sealed record HmiJobRequest(SplitView Program, string Strategy, int? FromLine, bool SingleBlock, double FeedOverride, RunSettings Settings)
{
    /// <summary>The machine profile the program was checked and split under (start plans and move times use it; the job record keeps it).</summary>
    public MachineProfile Profile { get; init; } = MachineProfile.Default;

    /// <summary>Optional stop on: the controller stops at M01.</summary>
    public bool OptionalStop { get; init; } = true;

    /// <summary>
    /// The store's program revision the program is (opened from the Store page, or a file its split stored), or null:
    /// the job history names it, as <c>stream --program ID</c> and <c>stream FILE</c>.
    /// </summary>
    public long? ProgramId { get; init; }

    /// <summary>Selected blocks: the job ends after this line's block (<c>stream --to-line</c>); null: at the program's end.</summary>
    public int? ToLine { get; init; }
}

/// <summary>
/// A running job as the presenter drives it: <see cref="TickAsync"/> from the form's <c>timer1_Tick</c> does the
/// streaming work (read M0, download the next chunk once, write the checkpoint); the rest are operator commands.
/// </summary>
public interface IHmiJob : IAsyncDisposable
{
    /// <summary>The status after the last tick or command.</summary>
    HmiJobStatus Status { get; }

    /// <summary>One timer period of streaming work.</summary>
    Task TickAsync(CancellationToken cancellationToken = default);

    /// <summary>Feed hold (<c>H</c>).</summary>
    Task HoldAsync(CancellationToken cancellationToken = default);

    /// <summary>Resume after hold, or the next block in single-block mode (<c>R</c>).</summary>
    Task ResumeAsync(CancellationToken cancellationToken = default);

    /// <summary>Abort (<c>A</c>); the job stays resumable from its checkpoint.</summary>
    Task AbortAsync(CancellationToken cancellationToken = default);

    /// <summary>Live feed override change in percent (<c>&amp;n %</c>; never written into an open buffer).</summary>
    Task SetFeedOverrideAsync(double percent, CancellationToken cancellationToken = default);

    /// <summary>Single-block mode on or off.</summary>
    Task SetSingleBlockAsync(bool on, CancellationToken cancellationToken = default);

    /// <summary>The optional-stop switch on or off: the next M01 stops or not.</summary>
    Task SetOptionalStopAsync(bool on, CancellationToken cancellationToken = default);
}

/// <summary>
/// What the presenter needs from the rest of PmacStream: the seam between the screen and the job service. The real
/// one (<see cref="CoreHmiBackend"/>) maps each call onto <see cref="JobService"/>, the service the command line
/// calls too; tests of the presenter's own logic use a fake. The machine profile the operator chose is given with
/// every call that reads a program or prepares the controller.
/// </summary>
public interface IHmiBackend
{
    /// <summary>Strategy names for the selector, the default first.</summary>
    IReadOnlyList<string> Strategies { get; }

    /// <summary>
    /// Opens the controller link the jobs of this backend run on (the profile's library is downloaded to the built-in
    /// simulator); returns its description. The backend holds the link until <see cref="DisconnectAsync"/>.
    /// </summary>
    Task<string> ConnectAsync(ConnectionSettings settings, MachineProfile profile, CancellationToken cancellationToken = default);

    /// <summary>Closes the controller link, when one is open.</summary>
    Task DisconnectAsync();

    /// <summary>
    /// Another profile was chosen: downloads its PROG 1000/1001 library and tables to the built-in simulator (a
    /// <see cref="Jobs.JobException"/> when it runs a program). Whether another controller runs that library is checked
    /// by the job service when a job starts or resumes.
    /// </summary>
    Task LoadLibraryAsync(MachineProfile profile, CancellationToken cancellationToken = default);

    /// <summary>Checks a program under a profile (every diagnostic, in the language asked).</summary>
    Task<HmiCheckResult> CheckAsync(string path, MachineProfile profile, HmiLanguage language, CancellationToken cancellationToken = default);

    /// <summary>
    /// Checks and splits a program under a profile with the job's settings (reusing a matching earlier split): the job
    /// gate. A program with errors, or with codes the controller cannot run yet, is refused with
    /// <see cref="ProgramRefusedException"/> listing them, whether or not a check ran first.
    /// </summary>
    Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default);

    /// <summary>
    /// <see cref="PrepareAsync(string, RunSettings, MachineProfile, CancellationToken)"/> of a stored revision's source
    /// (<paramref name="programId"/>): the preparation stored with the revision is reused, as <c>stream --program ID</c>
    /// does. Null: a file, which a backend with a store finds in it or imports first, as <c>stream FILE</c> does; the
    /// split names the revision (<see cref="SplitView.ProgramId"/>), or says why the store could not keep it
    /// (<see cref="SplitView.NotStored"/>: the file is prepared without one).
    /// </summary>
    Task<SplitView> PrepareAsync(string sourcePath, RunSettings settings, MachineProfile profile, long? programId, CancellationToken cancellationToken = default) =>
        PrepareAsync(sourcePath, settings, profile, cancellationToken);

    /// <summary>The G-code preamble that restores the machine state before starting at a source line (what is shown and sent).</summary>
    Task<IReadOnlyList<string>> BuildPreambleAsync(SplitView program, int line, RunSettings settings, MachineProfile profile, CancellationToken cancellationToken = default);

    /// <summary>Which rows of chunk <paramref name="chunk"/> (1-based) of a split carry a block's tracked line (<c>M0==line</c>).</summary>
    ChunkRows ReadChunkRows(SplitView program, int chunk);

    /// <summary>Prepares the controller, downloads the first chunk and starts execution (<c>&amp;1R</c>).</summary>
    Task<IHmiJob> StartAsync(HmiJobRequest request, CancellationToken cancellationToken = default);

    /// <summary>The newest unfinished job recorded for a program, or null.</summary>
    Task<InterruptedJobView?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default);

    /// <summary>
    /// Continues an interrupted job from its checkpoint, without losing or repeating a block, with the operator's feed
    /// override (percent) and optional stop in force, under the profile it ran under (another <paramref name="profile"/>
    /// is refused with a <see cref="JobException"/>).
    /// </summary>
    Task<IHmiJob> ResumeInterruptedAsync(InterruptedJobView job, double feedOverride, RunSettings settings, MachineProfile profile, bool optionalStop,
        CancellationToken cancellationToken = default);

    /// <summary>The program's moves as a machine profile interprets them, for the toolpath pane (read anew on each pass).</summary>
    IToolpathSource OpenToolpath(string sourcePath, MachineProfile profile);

    /// <summary>
    /// The toolpath of a program opened from the store (revision <paramref name="programId"/>, its source written to
    /// <paramref name="sourcePath"/>): drawn from the revision's stored blocks, as <c>preview --program ID</c> draws it;
    /// by default (a backend without a store) the file's.
    /// </summary>
    IToolpathSource OpenStoredToolpath(long programId, string sourcePath, MachineProfile profile) => OpenToolpath(sourcePath, profile);
}
