using System.Globalization;
using System.Security.Cryptography;
using PmacStream.GCode;
using PmacStream.Pmac;
using PmacStream.Program;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Hmi;

/// <summary>
/// The real <see cref="IHmiBackend"/>: the one-pass <see cref="Checker"/>, the <see cref="Splitter"/>, a
/// <see cref="StreamingSession"/> per job with its checkpoints in an <see cref="HmiJobJournal"/>, the restore
/// preamble from the interpreter's modal state, and the transports of <see cref="PmacConnections"/>.
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

    /// <summary>
    /// Creates the backend. <paramref name="simulator"/> opens a connection to a built-in simulated controller (the
    /// WinForms app supplies one; without it the Simulator device type reports that it is not available).
    /// </summary>
    public CoreHmiBackend(
        Func<CancellationToken, Task<IPmacConnection>>? simulator = null,
        MachineProfile? profile = null,
        StreamingOptions? streaming = null,
        TimeProvider? time = null)
    {
        _simulator = simulator;
        _profile = profile ?? MachineProfile.Default;
        _options = streaming ?? new StreamingOptions();
        _time = time ?? TimeProvider.System;
    }

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
            DeviceKind.Ethernet => PmacConnections.Create(settings.EthernetAddress.Contains("://", StringComparison.Ordinal)
                ? settings.EthernetAddress.Trim()
                : "tcp://" + settings.EthernetAddress.Trim()),
            DeviceKind.Serial => PmacConnections.Create(string.Create(CultureInfo.InvariantCulture, $"serial:{settings.SerialPort.Trim()}@{settings.Baud}")),
            DeviceKind.Pcomm32 => PmacConnections.Create(string.Create(CultureInfo.InvariantCulture, $"pcomm32:{settings.PcommDevice}")),
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
            var wantChinese = language == HmiLanguage.Chinese;
            if (DiagnosticText.Culture.Name.StartsWith("zh", StringComparison.OrdinalIgnoreCase) != wantChinese)
            {
                // Diagnostic texts follow one process-wide culture; the HMI is the only user in its process.
                DiagnosticText.Culture = HmiText.Culture(language);
            }

            var diagnostics = new List<Diagnostic>();
            var times = new List<(int Line, double Seconds)>();
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

                    times.Add((b.Line, b.DurationSeconds));
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
    public Task<IReadOnlyList<string>> BuildPreambleAsync(HmiSplitResult program, int line, CancellationToken cancellationToken = default) =>
        Task.Run(() => BuildPreamble(program.Manifest.SourcePath, line, cancellationToken), cancellationToken);

    /// <inheritdoc />
    public async Task<IHmiJob> StartAsync(IPmacConnection connection, HmiJobRequest request, CancellationToken cancellationToken = default)
    {
        var split = request.Program;
        var preamble = request.FromLine is { } from ? await BuildPreambleAsync(split, from, cancellationToken).ConfigureAwait(false) : null;
        var jobId = _time.GetUtcNow().ToUnixTimeMilliseconds();
        var journal = new HmiJobJournal(jobId, split.Manifest.SourcePath, split.Manifest.SourceSha256, split.Directory, request.Strategy);
        var session = NewSession(connection, split, request.Strategy, request.SingleBlock, journal);
        await SetFeedBeforeStartAsync(connection, split.Manifest, request.Feed, cancellationToken).ConfigureAwait(false);
        await session.StartAsync(request.FromLine, preamble, cancellationToken).ConfigureAwait(false);
        Log.Information("Job {Job} started on {Device:l}: {Chunks} chunks, strategy {Strategy:l}{From:l}", jobId, connection.Description,
            split.Manifest.Chunks.Count, request.Strategy, request.FromLine is { } f ? $", from line {f}" : string.Empty);
        return new SessionJob(session, request.Feed);
    }

    /// <inheritdoc />
    public Task<HmiInterruptedJob?> FindInterruptedAsync(string sourcePath, CancellationToken cancellationToken = default) =>
        Task.Run(() =>
        {
            var record = HmiJobJournal.Read(sourcePath);
            if (record is null || record.Checkpoint.State == SessionState.Completed)
            {
                return null;
            }

            var program = ChunkedProgram.Open(record.ChunkFolder);
            var now = Sha256Hex(sourcePath, cancellationToken);
            if (!string.Equals(now, record.SourceSha256, StringComparison.OrdinalIgnoreCase))
            {
                throw new InvalidOperationException(
                    $"{sourcePath} changed since job {record.JobId} was split (SHA-256 differs): split it again and start from a line instead");
            }

            var line = record.Checkpoint.LastExecutedLine > 0 ? record.Checkpoint.LastExecutedLine : program.Manifest.Chunks[0].FirstSourceLine;
            return (HmiInterruptedJob?)new HmiInterruptedJob(record.JobId, new HmiSplitResult(program.Manifest, program.Folder), line,
                record.Checkpoint.CurrentChunk, record.Strategy, record.Checkpoint.TimeUtc, record);
        }, cancellationToken);

    /// <inheritdoc />
    public async Task<IHmiJob> ResumeInterruptedAsync(IPmacConnection connection, HmiInterruptedJob job, double feed, CancellationToken cancellationToken = default)
    {
        var record = job.Record as HmiJobRecord ?? throw new ArgumentException("not a job recorded by this backend", nameof(job));
        var split = job.Program;
        var journal = new HmiJobJournal(record.JobId, record.SourcePath, record.SourceSha256, record.ChunkFolder, record.Strategy);
        if (record.Checkpoint.State != SessionState.Aborted)
        {
            var session = NewSession(connection, split, record.Strategy, singleBlock: false, journal);
            try
            {
                // The controller may still hold (or be running) the buffered lines: continue sending where the job stopped.
                await session.ResumeAsync(record.Checkpoint, cancellationToken).ConfigureAwait(false);
                Log.Information("Job {Job} resumed from its checkpoint at line {Line}", record.JobId, record.Checkpoint.LastExecutedLine);
                return new SessionJob(session, feed);
            }
            catch (InvalidOperationException e)
            {
                Log.Warning("Job {Job}: {Message:l}; restarting at line {Line} with the restore preamble", record.JobId, e.Message, job.ResumeLine);
            }
        }

        // The controller lost the job (reset, abort): start again at the interrupted line behind the preamble.
        var restart = NewSession(connection, split, record.Strategy, singleBlock: false, journal);
        var preamble = await BuildPreambleAsync(split, job.ResumeLine, cancellationToken).ConfigureAwait(false);
        await SetFeedBeforeStartAsync(connection, split.Manifest, feed, cancellationToken).ConfigureAwait(false);
        await restart.StartAsync(job.ResumeLine, preamble, cancellationToken).ConfigureAwait(false);
        Log.Information("Job {Job} restarted at line {Line}", record.JobId, job.ResumeLine);
        return new SessionJob(restart, feed);
    }

    /// <summary>
    /// The restore preamble for starting at <paramref name="line"/>: the modal state and position after the last
    /// block before it (from the interpreter), approached from the highest Z the program reached so far.
    /// </summary>
    internal IReadOnlyList<string> BuildPreamble(string sourcePath, int line, CancellationToken cancellationToken)
    {
        DecodedBlock? last = null;
        double? safeZ = null;
        using var stop = CancellationTokenSource.CreateLinkedTokenSource(cancellationToken);
        try
        {
            new Checker(_profile).CheckFile(sourcePath, _ => { }, b =>
            {
                if (b.Line >= line)
                {
                    stop.Cancel();
                    return;
                }

                last = b;
                if (b.Motion != MotionKind.None)
                {
                    safeZ = Math.Max(safeZ ?? double.MinValue, Math.Max(b.Start.Z, b.End.Z));
                }
            }, stop.Token);
        }
        catch (OperationCanceledException) when (!cancellationToken.IsCancellationRequested)
        {
            // Reached the line: the rest of the program is not needed.
        }

        if (last is null)
        {
            return [];
        }

        var lines = last.Modal.ToPreamble(last.End).ToList();
        if (safeZ is { } z)
        {
            // Retract before moving in XY: the tool may stand anywhere after an interruption.
            lines.Insert(1, "G90 G00 Z" + ModalState.Num(z));
        }

        return lines;
    }

    private StreamingSession NewSession(IPmacConnection connection, HmiSplitResult split, string strategy, bool singleBlock, HmiJobJournal journal)
    {
        var program = ChunkedProgram.FromManifest(split.Manifest, split.Directory);
        var options = _options with { Strategy = ParseStrategy(strategy), SingleBlock = singleBlock };
        MoveTimeTable? times;
        lock (_moveTimes)
        {
            _moveTimes.TryGetValue(Path.GetFullPath(split.Manifest.SourcePath), out times);
        }

        return new StreamingSession(connection, program, options, journal, times, _time);
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
    private sealed class SessionJob(StreamingSession session, double feed) : IHmiJob
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

        public ValueTask DisposeAsync() => ValueTask.CompletedTask;
    }
}
