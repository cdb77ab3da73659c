namespace PmacStream.Pmac;

/// <summary>
/// One open link to a Turbo PMAC (Ethernet, serial, PComm32 or in-process). Every transport frames and parses
/// replies the same way: the returned text is the reply without its final ACK, with a newline (LF) between values (see <see cref="ReplyParser.Parse"/>);
/// <c>ERRnnn</c> replies throw <see cref="PmacErrorException"/>, link failures <see cref="PmacLinkException"/>.
/// Calls are serialized by the implementation: one command is outstanding at a time, as on the wire.
/// </summary>
public interface IPmacConnection : IAsyncDisposable
{
    /// <summary>A short description for logs ("tcp 127.0.0.1:1025", "serial /dev/ttyS0@38400").</summary>
    string Description { get; }

    /// <summary>Sends one command line (no CR) and returns its reply text (values separated by LF, no ACK).</summary>
    Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default);

    /// <summary>
    /// Sends program lines as fast as the transport allows (WRITEBUFFER batches over Ethernet). Stops at the first
    /// line the controller refuses and throws <see cref="PmacErrorException"/> whose <see cref="PmacErrorException.LineInBatch"/>
    /// is that line's index; nothing after it is sent.
    /// </summary>
    Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default);

    /// <summary>
    /// As <see cref="DownloadAsync(IReadOnlyList{string}, CancellationToken)"/>, with up to <paramref name="packetsInFlight"/>
    /// packets sent before their replies arrive, where the transport can (Ethernet: replies come back in order on one
    /// TCP stream). Over a lossy link that lets TCP recover a lost reply from the next one's duplicate ACKs instead of
    /// its retransmission timeout. A refusal then may find later packets already stored: the exception's
    /// <see cref="PmacErrorException.LinesStoredAfterGap"/> counts their lines. Transports that cannot pipeline send one
    /// packet at a time (nothing is ever stored after a refusal).
    /// </summary>
    Task DownloadAsync(IReadOnlyList<string> lines, int packetsInFlight, CancellationToken cancellationToken = default) =>
        DownloadAsync(lines, cancellationToken);

    /// <summary>Discards pending replies (Ctrl-X).</summary>
    Task FlushAsync(CancellationToken cancellationToken = default);

    /// <summary>Sends a control character (Ctrl-B, C, F, G, P, V ...) and returns its unterminated reply.</summary>
    Task<string> ControlAsync(char control, CancellationToken cancellationToken = default);
}

/// <summary>
/// The seam the in-process transport talks through: one port of a controller engine, speaking the ASCII protocol.
/// The simulator implements it; Core does not reference the simulator.
/// </summary>
public interface IPmacPortEndpoint
{
    /// <summary>Runs one command line (no CR) and returns the raw reply bytes as the port would send them (I3/I6 framing).</summary>
    byte[] Execute(string commandLine);

    /// <summary>Handles a Ctrl-X flush on this port.</summary>
    void Flush();

    /// <summary>Answers a control character, raw bytes, no terminator.</summary>
    byte[] Control(char control);
}
