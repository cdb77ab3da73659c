using PmacStream.Pmac;

namespace PmacStream.Streaming;

/// <summary>
/// A one-device <see cref="IPmacDevices"/> over a single connection, for sessions built on a bare connection
/// (tests, the in-process demo) before or without the full device facade. Download reads the file, drops blank and
/// comment lines, sends the rest with <see cref="IPmacConnection.DownloadAsync"/> and maps a refusal back to its file line.
/// </summary>
internal sealed class ConnectionDevices(IPmacConnection connection) : IPmacDevices
{
    public IPmacConnection this[int pmacNumber] => connection;

    public bool GetResponse(int pmacNumber, string command, out string answer)
    {
        try
        {
            answer = connection.GetResponseAsync(command).GetAwaiter().GetResult();
            return true;
        }
        catch (PmacErrorException e)
        {
            answer = $"ERR{e.Number:000}";
            return false;
        }
    }

    public void Download(int pmacNumber, string path, bool macro, bool map, bool log, bool dnld, out bool success) =>
        success = DownloadAsync(pmacNumber, path, new DownloadOptions(macro, map, log, dnld)).GetAwaiter().GetResult().Success;

    public Task<string> GetResponseAsync(int pmacNumber, string command, CancellationToken cancellationToken = default) =>
        connection.GetResponseAsync(command, cancellationToken);

    public async Task<DownloadReport> DownloadAsync(int pmacNumber, string path, DownloadOptions options, CancellationToken cancellationToken = default)
    {
        var lines = new List<string>();
        var fileLines = new List<int>();
        var n = 0;
        foreach (var raw in File.ReadLines(path))
        {
            n++;
            var t = raw.Trim();
            if (t.Length == 0 || t[0] == ';')
            {
                continue;
            }

            lines.Add(t);
            fileLines.Add(n);
        }

        if (!options.Dnld)
        {
            return new DownloadReport(true, 0, null);
        }

        try
        {
            await connection.DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
            return new DownloadReport(true, lines.Count, null);
        }
        catch (PmacErrorException e) when (e.LineInBatch is { } i && i >= 0 && i < lines.Count)
        {
            return new DownloadReport(false, i, new DownloadError(e.Number, path, fileLines[i], lines[i]));
        }
    }
}
