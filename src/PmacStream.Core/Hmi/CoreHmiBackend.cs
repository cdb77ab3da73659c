using System.Globalization;
using System.Runtime.CompilerServices;
using System.Security.Cryptography;
using PmacStream.GCode;
using PmacStream.Pmac;
using PmacStream.Program;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Hmi;

/// <summary>
/// The real <see cref="IHmiBackend"/>: the one-pass <see cref="Checker"/>, the <see cref="Splitter"/>, a
/// <see cref="StreamingSession"/> per job with its job record and checkpoints in the SQLite <see cref="JobStore"/>
/// the CLI uses (so a job started here can be resumed by <c>pmacstream resume</c> and the other way round), the
/// restore preamble from the interpreter's modal state, and the transports of <see cref="PmacConnections"/>.
/// </summary>
public sealed class CoreHmiBackend : IHmiBackend
{
    /// <summary>Diagnostics listed at most (the counts stay exact; a screen of 10,000 rows is already plenty).</summary>
    public const int MaxListedDiagnostics = 10_000;

    /// <summary>Motion blocks whose times are kept for the ETA (12 bytes each); longer programs use the measured rate.</summary>
    public const int MaxTimedBlocks = 2_000_000;

    private static readonly ILogger Log = Serilog.Log.ForContext<CoreHmiBackend>();

    private readonly Func<CancellationToken, Task<IPmacConnection>>? _simulator;
    private readonly MachineProfile _profile;
    private readonly StreamingOptions _options;
    private readonly TimeProvider _time;
    private readonly Dictionary<string, MoveTimeTable> _moveTimes = new(StringComparer.Ordinal);

    // The connection spec each link was opened with, recorded in the job so `pmacstream resume` can reopen it.
    private readonly ConditionalWeakTable<IPmacConnection, string> _specs = [];

    /// <summary>
    /// Creates the backend. <paramref name="simulator"/> opens a connection to a built-in simulated controller (the
    /// WinForms app supplies one; without it the Simulator device type reports that it is not available).
    /// <paramref name="jobDatabase"/> is the job store; null means the CLI's default (<see cref="JobStore.DefaultPath"/>).
    /// </summary>
    public CoreHmiBackend(
        Func<CancellationToken, Task<IPmacConnection>>? simulator = null,
        MachineProfile? profile = null,
        StreamingOptions? streaming = null,
        TimeProvider? time = null,
        string? jobDatabase = null,
        StartPlanOptions? startPlan = null)
    {
        JobDatabase = Path.GetFullPath(jobDatabase ?? JobStore.DefaultPath);
        _simulator = simulator;
        _profile = profile ?? MachineProfile.Default;
        _options = streaming ?? new StreamingOptions();
        _time = time ?? TimeProvider.System;
        StartPlanOptions = (startPlan ?? new StartPlanOptions()) with { Profile = _profile };
    }

    /// <summary>
    /// How starts from a line are planned (safe Z mode and height, clearance): <see cref="StartFromLine.Plan(string, int, StartPlanOptions, CancellationToken)"/>
    /// with the same options as the CLI's <c>--safe-z-mode</c>/<c>--safe-z</c>/<c>--clearance</c>, so both show and run the same preamble.
    /// </summary>
    public StartPlanOptions StartPlanOptions { get; }

    /// <summary>The SQLite job store the HMI records its jobs and checkpoints in (the CLI's <c>--job-db</c>).</summary>
    public string JobDatabase { get; }

    /// <inheritdoc />
    public IReadOnlyList<string> Strategies { get; } = ["chunk", "pr", "adaptive"];

    /// <inheritdoc />
    public async Task<IPmacConnection> ConnectAsync(ConnectionSettings settings, CancellationToken cancellationToken = default)
    {
        var connection = settings.Device switch
        {
            DeviceKind.Simulator => _simulator is null
                ? throw new NotSupportedException("no built-in simulator in this build: run `pmacstream sim` and connect over Ethernet to 127.0.0.1:1025")
                : await _simulator(cancellationToken).ConfigureAwait(false),
            DeviceKind.Ethernet or DeviceKind.Serial or DeviceKind.Pcomm32 => PmacConnections.Create(ConnectionSpec(settings)),
            _ => throw new ArgumentOutOfRangeException(nameof(settings), settings.Device, "unknown device type"),
        };

        try
        {
            // Proves the link: any reply (even an ERR) means a controller is there; a link failure throws.
            string version;
            try
            {
                version = (await connection.GetResponseAsync("VERSION", cancellationToken).ConfigureAwait(false)).Trim();
            }
            catch (PmacErrorException e)
            {
                version = $"(VERSION answered ERR{e.Number:000})";
            }

            Log.Information("Connected to {Device:l} ({Settings}), firmware {Version:l}", connection.Description, settings, version);
            _specs.AddOrUpdate(connection, ConnectionSpec(settings));
            return connection;
        }
        catch
        {
            await connection.DisposeAsync().ConfigureAwait(false);
            throw;
        }
    }

    /// <inheritdoc />
    public Task<HmiCheckResult> CheckAsync(string path, HmiLanguage language, CancellationToken cancellationToken = default) =>
        Task.Run(() =>
        {
            // For this check only: the diagnostic culture follows the async flow, and this task is the check's own.
            DiagnosticText.Culture = HmiText.Culture(language);

            var diagnostics = new List<Diagnostic>();
            var times = new List<(int Line, double Seconds, double Feed)>();
            var timed = true;
            var summary = new Checker(_profile).CheckFile(
                path,
                d =>
                {
                    if (diagnostics.Count < MaxListedDiagnostics)
                    {
                        diagnostics.Add(d);
                    }
                },
                b =>
                {
                    if (!timed || b.Motion == MotionKind.None)
                    {
                        return;
                    }

                    if (times.Count >= MaxTimedBlocks)
                    {
                        timed = false;
                        times = [];
                        return;
                    }

                    times.Add((b.Line, b.DurationSeconds, b.Modal.Feed ?? double.NaN));
                },
                cancellationToken);

            lock (_moveTimes)
            {
                var key = Path.GetFullPath(path);
                if (timed)
                {
                    _moveTimes[key] = new MoveTimeTable(times);
                }
                else
                {
                    _moveTimes.Remove(key);
                }
            }

            Log.Information("Checked {Path:l}: {Summary:l}, estimated run time {Seconds:0} s", path, summary.ToString(), summary.EstimatedSeconds);
            return new HmiCheckResult(diagnostics, summary.Blocks, summary.Errors, summary.Warnings);
        }, cancellationToken);

    /// <inheritdoc />
    public async Task<HmiSplitResult> SplitAsync(HmiSplitRequest request, CancellationToken cancellationToken = default)
    {
        var result = await Splitter.SplitAsync(request.SourcePath, new SplitOptions { LinesPerChunk = request.LinesPerChunk }, null, cancellationToken)
            .ConfigureAwait(false);
        return new HmiSplitResult(result.Manifest, result.OutputDirectory);
    }

    /// <inheritdoc />
    /// <remarks>The G-code of <see cref="StartFromLine.Plan(string, int, StartPlanOptions, CancellationToken)"/>: what the CLI shows for the same line.</remarks>
    public async Task<IReadOnlyList<string>> BuildPreambleAsync(HmiSplitResult program, int line, CancellationToken cancellationToken = default) =>
        (await PlanStartAsync(program, line, cancellationToken).ConfigureAwait(false)).GCode;

    /// <summary>Plans a start at <paramref name="line"/> of a split program (the CLI's planner, this backend's options).</summary>
    public Task<StartPlan> PlanStartAsync(HmiSplitResult program, int line, CancellationToken cancellationToken = default) =>
        Task.Run(() => StartFromLine.Plan(program.Manifest.SourcePath, line, StartPlanOptions.For(program.Manifest, StartPlanOptions), cancellationToken), cancellationToken);

    /// <inheritdoc />
    public async Task<IHmiJob> StartAsync(IPmacConnection connection, HmiJobRequest request, CancellationToken cancellationToken = default)
    {
        var split = request.Program;
        var strategy = ParseStrategy(request.Strategy);
        var plan = request.FromLine is { } from ? await PlanStartAsync(split, from, cancellationToken).ConfigureAwait(false) : null;
        var store = JobStore.Open(JobDatabase);
        try
        {
            var spec = _specs.TryGetValue(connection, out var known) ? known : connection.Description;
            var jobId = store.CreateJob(split.Manifest.SourcePath, split.Manifest.SourceSha256, Path.Combine(split.Directory, ChunkManifest.FileName),
                strategy, spec, request.FromLine, _options.LineProbeVariable);
            var session = NewSession(connection, split, strategy, request.SingleBlock, store.SinkFor(jobId));
            try
            {
                // Refused before the feed is set: P500 (or the % override) belongs to whatever program is running.
                await session.EnsureIdleAsync(cancellationToken).ConfigureAwait(false);
                await SetFeedBeforeStartAsync(connection, split.Manifest, request.Feed, cancellationToken).ConfigureAwait(false);
                await session.StartAsync(plan?.Line, plan?.PmacLines, cancellationToken).ConfigureAwait(false);
            }
            catch (Exception e) when (e is PmacLinkException or PmacErrorException or InvalidOperationException)
            {
                store.SetMessage(jobId, e.Message);
                throw;
            }

            Log.Information("Job {Job} started on {Device:l}: {Chunks} chunks, strategy {Strategy:l}{From:l} (job store {Store:l})", jobId, connection.Description,
                split.Manifest.Chunks.Count, request.Strategy, request.FromLine is { } f ? $", from line {f}" : string.Empty, store.Path);
            return new SessionJob(session, request.Feed, store, jobId);
        }
        catch
        {
            store.Dispose();
            throw;
        }
    }

    /// <inheritdoc />
    /// <remarks>
    /// The newest job of the program in the job store, whoever started it (HMI or CLI); null when that job completed
    /// (an older interrupted one was superseded by it).
    /// </remarks>
    public Task<HmiInterruptedJob?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) =>
        Task.Run(() =>
        {
            JobRecord? record;
            using (var store = JobStore.Open(JobDatabase))
            {
                var full = Path.GetFullPath(sourcePath);
                var comparison = OperatingSystem.IsWindows() ? StringComparison.OrdinalIgnoreCase : StringComparison.Ordinal;
                record = store.List().FirstOrDefault(j => string.Equals(j.ProgramPath, full, comparison));
            }

            if (record is null || !record.Unfinished)
            {
                return null;
            }

            var now = Sha256Hex(sourcePath, cancellationToken);
            if (!string.Equals(now, record.ProgramSha256, StringComparison.OrdinalIgnoreCase))
            {
                throw new InvalidOperationException(
                    $"{sourcePath} changed since job {record.Id} started (SHA-256 differs): split it again and start from a line instead");
            }

            ChunkedProgram program;
            try
            {
                program = ChunkedProgram.Open(record.ManifestPath);
            }
            catch (Exception e) when (e is IOException or System.Text.Json.JsonException)
            {
                throw new InvalidOperationException($"job {record.Id}: its split ({record.ManifestPath}) cannot be read ({e.Message}): split the program again and start from a line", e);
            }

            if (!string.Equals(program.Manifest.SourceSha256, record.ProgramSha256, StringComparison.OrdinalIgnoreCase))
            {
                throw new InvalidOperationException($"job {record.Id}: the split in {program.Folder} no longer matches the program: start from a line instead");
            }

            var cp = record.Checkpoint;
            var line = cp is { LastExecutedLine: > 0 } ? cp.LastExecutedLine : record.FromLine ?? program.Manifest.Chunks[0].FirstSourceLine;
            var chunk = cp?.CurrentChunk ?? program.PositionOfBlock(line)?.Chunk ?? 1;
            return (HmiInterruptedJob?)new HmiInterruptedJob(record.Id, new HmiSplitResult(program.Manifest, program.Folder), line,
                chunk, StrategyName(record.Strategy), cp?.TimeUtc ?? record.Created, record);
        }, cancellationToken);

    /// <inheritdoc />
    public async Task<IHmiJob> ResumeInterruptedAsync(IPmacConnection connection, HmiInterruptedJob job, double feed, CancellationToken cancellationToken = default)
    {
        var record = job.Record as JobRecord ?? throw new ArgumentException("not a job recorded in the job store", nameof(job));
        var split = job.Program;
        var store = JobStore.Open(JobDatabase);
        try
        {
            var sink = store.SinkFor(record.Id);
            if (record.Checkpoint is { State: not SessionState.Aborted } cp)
            {
                var session = NewSession(connection, split, record.Strategy, singleBlock: false, sink);
                try
                {
                    // The controller may still hold (or be running) the buffered lines: continue sending where the job stopped.
                    // From the record: its line probe, and a start that broke off while loading is loaded again.
                    await session.ResumeAsync(record, cancellationToken).ConfigureAwait(false);
                    Log.Information("Job {Job} resumed from its checkpoint at line {Line}", record.Id, cp.LastExecutedLine);
                    return new SessionJob(session, feed, store, record.Id);
                }
                catch (InvalidOperationException e)
                {
                    Log.Warning("Job {Job}: {Message:l}; restarting at line {Line} with the restore preamble", record.Id, e.Message, job.ResumeLine);
                }
            }

            // The controller lost the job (reset, abort) or it never started: start again at the interrupted line behind the preamble.
            var restart = NewSession(connection, split, record.Strategy, singleBlock: false, sink);
            var plan = await PlanStartAsync(split, job.ResumeLine, cancellationToken).ConfigureAwait(false);
            await restart.EnsureIdleAsync(cancellationToken).ConfigureAwait(false);
            await SetFeedBeforeStartAsync(connection, split.Manifest, feed, cancellationToken).ConfigureAwait(false);
            await restart.StartAsync(plan.Line, plan.PmacLines, cancellationToken).ConfigureAwait(false);
            Log.Information("Job {Job} restarted at line {Line}", record.Id, job.ResumeLine);
            return new SessionJob(restart, feed, store, record.Id);
        }
        catch
        {
            store.Dispose();
            throw;
        }
    }

    private StreamingSession NewSession(IPmacConnection connection, HmiSplitResult split, StrategyKind strategy, bool singleBlock, ICheckpointSink checkpoints)
    {
        var program = ChunkedProgram.FromManifest(split.Manifest, split.Directory);
        var options = _options with { Strategy = strategy, SingleBlock = singleBlock };
        MoveTimeTable? times;
        lock (_moveTimes)
        {
            _moveTimes.TryGetValue(Path.GetFullPath(split.Manifest.SourcePath), out times);
        }

        return new StreamingSession(connection, program, options, checkpoints, times, _time);
    }

    /// <summary>The operator's feed is in force before the first block is calculated (no buffer is open then).</summary>
    private async Task SetFeedBeforeStartAsync(IPmacConnection connection, ChunkManifest manifest, double feed, CancellationToken cancellationToken)
    {
        var value = feed.ToString("0.###", CultureInfo.InvariantCulture);
        await connection.GetResponseAsync("CLOSE", cancellationToken).ConfigureAwait(false);
        var variable = string.IsNullOrWhiteSpace(manifest.FeedVariable) ? "P500" : manifest.FeedVariable.Trim();
        var command = (_options.Feed ?? manifest.Feed) == FeedMode.Paper
            ? $"{variable}={value}"
            : string.Create(CultureInfo.InvariantCulture, $"&{_options.CoordinateSystem} %{value}");
        await connection.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
    }

    private static StrategyKind ParseStrategy(string name) => name.Trim().ToLowerInvariant() switch
    {
        "pr" => StrategyKind.Pr,
        "adaptive" => StrategyKind.Adaptive,
        "chunk" or "" => StrategyKind.Chunk,
        _ => throw new ArgumentException($"unknown strategy '{name}': expected chunk, pr or adaptive", nameof(name)),
    };

    private static string StrategyName(StrategyKind kind) => kind.ToString().ToLowerInvariant();

    /// <summary>The CLI's spelling of a link (<c>sim</c>, <c>tcp://host:port</c>, <c>serial:dev@baud</c>, <c>pcomm32:n</c>).</summary>
    internal static string ConnectionSpec(ConnectionSettings settings) => settings.Device switch
    {
        DeviceKind.Ethernet => settings.EthernetAddress.Contains("://", StringComparison.Ordinal)
            ? settings.EthernetAddress.Trim()
            : "tcp://" + settings.EthernetAddress.Trim(),
        DeviceKind.Serial => string.Create(CultureInfo.InvariantCulture, $"serial:{settings.SerialPort.Trim()}@{settings.Baud}"),
        DeviceKind.Pcomm32 => string.Create(CultureInfo.InvariantCulture, $"pcomm32:{settings.PcommDevice}"),
        _ => "sim",
    };

    private static string Sha256Hex(string path, CancellationToken cancellationToken)
    {
        using var s = new FileStream(path, FileMode.Open, FileAccess.Read, FileShare.Read, 1 << 16, FileOptions.SequentialScan);
        using var sha = IncrementalHash.CreateHash(HashAlgorithmName.SHA256);
        var buffer = new byte[1 << 20];
        int n;
        while ((n = s.Read(buffer, 0, buffer.Length)) > 0)
        {
            cancellationToken.ThrowIfCancellationRequested();
            sha.AppendData(buffer, 0, n);
        }

        return Convert.ToHexStringLower(sha.GetHashAndReset());
    }

    /// <summary>A streaming session as the presenter drives it.</summary>
    private sealed class SessionJob(StreamingSession session, double feed, JobStore store, long jobId) : IHmiJob
    {
        public HmiJobStatus Status
        {
            get
            {
                var s = session.Status;
                var state = s.State switch
                {
                    SessionState.Running => HmiJobState.Running,
                    SessionState.Held => HmiJobState.Held,
                    SessionState.Completed => HmiJobState.Completed,
                    SessionState.Aborted => HmiJobState.Aborted,
                    SessionState.Faulted => HmiJobState.Failed,
                    _ => HmiJobState.Idle,
                };
                return new HmiJobStatus(state, s.CurrentChunk, s.CurrentLine, s.Percent, s.Feed ?? feed, s.Elapsed, s.Eta,
                    string.IsNullOrEmpty(s.Message) ? null : s.Message);
            }
        }

        public Task TickAsync(CancellationToken cancellationToken = default) => session.TickAsync(cancellationToken);

        public Task HoldAsync(CancellationToken cancellationToken = default) => session.HoldAsync(cancellationToken);

        public Task ResumeAsync(CancellationToken cancellationToken = default) =>
            session.SingleBlock && session.State == SessionState.Running ? session.StepAsync(cancellationToken) : session.ResumeMotionAsync(cancellationToken);

        public Task AbortAsync(CancellationToken cancellationToken = default) => session.AbortAsync(cancellationToken);

        public Task SetFeedAsync(double value, CancellationToken cancellationToken = default) => session.SetFeedAsync(value, cancellationToken);

        public Task SetSingleBlockAsync(bool on, CancellationToken cancellationToken = default)
        {
            session.SetSingleBlock(on);
            return Task.CompletedTask;
        }

        public ValueTask DisposeAsync()
        {
            // The reason a job stopped stays with its record, as the CLI leaves it.
            if (session.Status.Message is { Length: > 0 } message)
            {
                store.SetMessage(jobId, message);
            }

            store.Dispose();
            return ValueTask.CompletedTask;
        }
    }
}
