namespace PmacStream.Pmac;

/// <summary>Options of a PComm-style download (the meaning of PComm's <c>macro, map, log, dnld</c> flags).</summary>
/// <param name="Macro">Expand <c>#define</c> macros and <c>#include</c> files.</param>
/// <param name="Map">Write a <c>.map</c> file of the macro names beside the source.</param>
/// <param name="Log">Write a <c>.log</c> file of what was sent and every error with its line.</param>
/// <param name="Dnld">Actually send the lines (false: only prepare, log and map).</param>
public sealed record DownloadOptions(bool Macro = true, bool Map = false, bool Log = false, bool Dnld = true);

/// <summary>What a download did.</summary>
/// <param name="Success">True when every line was accepted (or, with <c>dnld=false</c>, prepared without error).</param>
/// <param name="LinesSent">Program lines sent to the controller.</param>
/// <param name="Error">The refusal, when a line was refused: ERR number, the line's source file and 1-based line.</param>
public sealed record DownloadReport(bool Success, int LinesSent, DownloadError? Error);

/// <summary>A line the controller refused during a download.</summary>
/// <param name="Number">ERR number.</param>
/// <param name="File">Source file of the line (after <c>#include</c> expansion).</param>
/// <param name="Line">1-based line in that file.</param>
/// <param name="Text">The line as sent.</param>
public sealed record DownloadError(int Number, string File, int Line, string Text);

/// <summary>
/// The device API legacy HMI code knows from Delta Tau's PComm32 COM object: devices chosen by number,
/// <c>GetResponse</c> and <c>Download</c> with PComm's meaning, plus async equivalents for new code.
/// </summary>
public interface IPmacDevices
{
    /// <summary>The open connection of a configured device.</summary>
    IPmacConnection this[int pmacNumber] { get; }

    /// <summary>PComm's <c>GetResponse</c>: false (and the error text in <paramref name="answer"/>) when the controller refused.</summary>
    bool GetResponse(int pmacNumber, string command, out string answer);

    /// <summary>PComm's <c>Download</c>: reads a PMAC source file and sends it line by line.</summary>
    void Download(int pmacNumber, string path, bool macro, bool map, bool log, bool dnld, out bool success);

    /// <summary>Async <c>GetResponse</c>; throws <see cref="PmacErrorException"/> on ERR replies.</summary>
    Task<string> GetResponseAsync(int pmacNumber, string command, CancellationToken cancellationToken = default);

    /// <summary>Async <c>Download</c> with a full report.</summary>
    Task<DownloadReport> DownloadAsync(int pmacNumber, string path, DownloadOptions options, CancellationToken cancellationToken = default);
}
