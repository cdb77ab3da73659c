using System.Diagnostics;
using System.Globalization;
using System.Text;
using Serilog;

namespace PmacStream.Pmac;

/// <summary>
/// The PComm-style device API over any <see cref="IPmacConnection"/>: devices are configured by number
/// (<see cref="Add"/> or <see cref="AddFromSpec"/>), <c>GetResponse</c> and <c>Download</c> keep PComm's meaning.
/// Downloads are prepared on the host (comments, macros, includes) and sent with the transport's fastest path
/// (<see cref="IPmacConnection.DownloadAsync(IReadOnlyList{string}, CancellationToken)"/>: WRITEBUFFER batches over Ethernet).
/// </summary>
public sealed class PmacDevices : IPmacDevices, IAsyncDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacDevices>();
    private readonly Dictionary<int, IPmacConnection> _devices = [];

    /// <summary>Configures device <paramref name="pmacNumber"/> (replacing none: a number is configured once).</summary>
    public void Add(int pmacNumber, IPmacConnection connection)
    {
        ArgumentNullException.ThrowIfNull(connection);
        lock (_devices)
        {
            if (!_devices.TryAdd(pmacNumber, connection))
            {
                throw new ArgumentException($"PMAC device {pmacNumber} is already configured ({_devices[pmacNumber].Description})", nameof(pmacNumber));
            }
        }
    }

    /// <summary>A facade with one device configured: <paramref name="connection"/> as <paramref name="pmacNumber"/>.</summary>
    public static PmacDevices Of(int pmacNumber, IPmacConnection connection)
    {
        var devices = new PmacDevices();
        devices.Add(pmacNumber, connection);
        return devices;
    }

    /// <summary>Configures device <paramref name="pmacNumber"/> from a connection spec (see <see cref="ConnectionSpec.Parse"/>).</summary>
    public void AddFromSpec(int pmacNumber, string spec, TimeSpan? timeout = null) => Add(pmacNumber, PmacConnections.Create(spec, timeout));

    /// <summary>The configured device numbers.</summary>
    public IReadOnlyCollection<int> Numbers
    {
        get
        {
            lock (_devices)
            {
                return [.. _devices.Keys];
            }
        }
    }

    /// <inheritdoc />
    public IPmacConnection this[int pmacNumber]
    {
        get
        {
            lock (_devices)
            {
                return _devices.TryGetValue(pmacNumber, out var c)
                    ? c
                    : throw new ArgumentOutOfRangeException(nameof(pmacNumber), $"PMAC device {pmacNumber} is not configured (configured: {string.Join(", ", _devices.Keys)})");
            }
        }
    }

    /// <inheritdoc />
    public bool GetResponse(int pmacNumber, string command, out string answer)
    {
        try
        {
            answer = GetResponseAsync(pmacNumber, command).GetAwaiter().GetResult();
            return true;
        }
        catch (PmacErrorException e)
        {
            answer = $"ERR{e.Number:000}: {PmacErrors.Describe(e.Number)}";
            return false;
        }
        catch (PmacLinkException e)
        {
            Log.Warning("PMAC {Device}: {Error}", pmacNumber, e.Message);
            answer = e.Message;
            return false;
        }
    }

    /// <inheritdoc />
    public void Download(int pmacNumber, string path, bool macro, bool map, bool log, bool dnld, out bool success)
    {
        var report = DownloadAsync(pmacNumber, path, new DownloadOptions(macro, map, log, dnld)).GetAwaiter().GetResult();
        success = report.Success;
    }

    /// <inheritdoc />
    public Task<string> GetResponseAsync(int pmacNumber, string command, CancellationToken cancellationToken = default) =>
        this[pmacNumber].GetResponseAsync(command, cancellationToken);

    /// <inheritdoc />
    /// <remarks>
    /// <see cref="DownloadReport.LinesSent"/> counts lines the controller accepted. A link failure throws
    /// <see cref="PmacLinkException"/> (after writing the log); a refused line or a source problem (missing include,
    /// bad directive: <see cref="DownloadError.Number"/> 0) is reported, never thrown. The log is
    /// <c>path</c> with extension <c>.log</c>, the map <c>.map</c>.
    /// </remarks>
    public async Task<DownloadReport> DownloadAsync(int pmacNumber, string path, DownloadOptions options, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(path);
        ArgumentNullException.ThrowIfNull(options);
        var connection = options.Dnld ? this[pmacNumber] : null;
        var sw = Stopwatch.StartNew();
        var prepared = PmacSourcePreprocessor.Prepare(path, options.Macro);
        if (options.Map)
        {
            WriteAtomically(Path.ChangeExtension(path, ".map"), w => WriteMap(w, path, prepared));
        }

        DownloadReport report;
        Exception? linkFailure = null;
        if (prepared.Error is not null)
        {
            report = new DownloadReport(false, 0, prepared.Error);
        }
        else if (connection is null)
        {
            report = new DownloadReport(true, 0, null);
        }
        else
        {
            var texts = new string[prepared.Lines.Count];
            for (var i = 0; i < texts.Length; i++)
            {
                texts[i] = prepared.Lines[i].Text;
            }

            try
            {
                await connection.DownloadAsync(texts, cancellationToken).ConfigureAwait(false);
                report = new DownloadReport(true, texts.Length, null);
            }
            catch (PmacErrorException e) when (e.LineInBatch is { } index && index >= 0 && index < texts.Length)
            {
                var line = prepared.Lines[index];
                report = new DownloadReport(false, index, new DownloadError(e.Number, line.File, line.Line, line.Text));
            }
            catch (PmacLinkException e)
            {
                linkFailure = e;
                report = new DownloadReport(false, 0, null);
            }
        }

        if (options.Log)
        {
            WriteAtomically(Path.ChangeExtension(path, ".log"), w => WriteLog(w, pmacNumber, connection, path, options, prepared, report, linkFailure));
        }

        if (report.Error is { } err)
        {
            Log.Warning(
                "PMAC {Device} download of {Path} failed at {File}:{Line}: {What} '{Text}'",
                pmacNumber,
                path,
                err.File,
                err.Line,
                err.Number == 0 ? "source error" : $"ERR{err.Number:000} ({PmacErrors.Describe(err.Number)})",
                err.Text);
        }
        else if (linkFailure is null)
        {
            Log.Debug("PMAC {Device} download of {Path}: {Lines} lines {Action} ({Ms:0.0} ms)", pmacNumber, path, prepared.Lines.Count, options.Dnld ? "sent" : "prepared", sw.Elapsed.TotalMilliseconds);
        }

        if (linkFailure is not null)
        {
            throw linkFailure;
        }

        return report;
    }

    /// <summary>Disposes every configured connection.</summary>
    public async ValueTask DisposeAsync()
    {
        IPmacConnection[] all;
        lock (_devices)
        {
            all = [.. _devices.Values];
            _devices.Clear();
        }

        foreach (var c in all)
        {
            await c.DisposeAsync().ConfigureAwait(false);
        }
    }

    private static void WriteMap(TextWriter w, string path, PreparedSource prepared)
    {
        w.WriteLine($"; macro map of {path}");
        foreach (var m in prepared.Macros)
        {
            w.WriteLine($"{m.Name}\t{m.Value}\t; {m.File}:{m.Line}");
        }
    }

    private static void WriteLog(TextWriter w, int pmacNumber, IPmacConnection? connection, string path, DownloadOptions options, PreparedSource prepared, DownloadReport report, Exception? linkFailure)
    {
        w.WriteLine($"; PmacStream download log of {path}");
        w.WriteLine($"; device {pmacNumber} ({connection?.Description ?? "not sent: dnld=false"}), {DateTime.Now.ToString("yyyy-MM-dd HH:mm:ss", CultureInfo.InvariantCulture)}, macro={options.Macro} map={options.Map}");
        // What went over the wire: everything on success or when nothing is sent (listed as prepared), up to and
        // including the refused line on an ERR, nothing on a source error or a lost link (unknown how far it got).
        var shown = connection is null || report.Success ? prepared.Lines.Count : report.Error is { Number: > 0 } ? report.LinesSent + 1 : 0;
        for (var i = 0; i < shown && i < prepared.Lines.Count; i++)
        {
            var l = prepared.Lines[i];
            w.Write(l.File);
            w.Write(':');
            w.Write(l.Line.ToString(CultureInfo.InvariantCulture));
            w.Write(": ");
            w.WriteLine(l.Text);
        }

        if (report.Error is { } e)
        {
            var what = e.Number == 0 ? "source error" : $"ERR{e.Number:000} ({PmacErrors.Describe(e.Number)})";
            w.WriteLine($"; {what} at {e.File}:{e.Line}: {e.Text}");
        }

        if (linkFailure is not null)
        {
            w.WriteLine($"; link failed: {linkFailure.Message}");
        }

        w.WriteLine(connection is null
            ? $"; result: {(report.Success ? "OK" : "FAILED")}, {prepared.Lines.Count} lines prepared, nothing sent (dnld=false)"
            : $"; result: {(report.Success ? "OK" : "FAILED")}, {report.LinesSent} lines accepted");
    }

    /// <summary>Writes a file through a temporary beside it, so a failure never leaves half a file.</summary>
    private static void WriteAtomically(string path, Action<TextWriter> write)
    {
        var temp = path + ".tmp";
        try
        {
            using (var w = new StreamWriter(temp, false, new UTF8Encoding(false)))
            {
                write(w);
            }

            File.Move(temp, path, true);
        }
        catch
        {
            File.Delete(temp);
            throw;
        }
    }
}
