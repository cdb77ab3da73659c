namespace PmacStream.Pmac;

/// <summary>
/// The bookkeeping of one WRITEBUFFER download with several packets in flight: which lines each packet carries, the
/// replies still due (in order: one TCP stream), the first refusal and what the controller stored after it. Replies
/// are matched to packets by order alone, so a probe's reply (READREADY, 2 bytes) takes its place in the queue too.
/// Once a line is refused nothing more is sent; the replies of the packets already on the wire are still read, and
/// every line they carried that the controller accepted is counted: those lines sit behind the gap.
/// </summary>
internal sealed class PipelinedDownload(int lineCount, int window, int maxProbes)
{
    private readonly Queue<InFlight> _inFlight = new();
    private int _packetsInFlight;

    /// <summary>The first line not yet sent.</summary>
    public int NextLine { get; private set; }

    /// <summary>Packets sent.</summary>
    public int Packets { get; private set; }

    /// <summary>READREADY probes sent.</summary>
    public int ProbesSent { get; private set; }

    /// <summary>The first refused line (its index in the download) and its ERR number, or null.</summary>
    public (int Line, int Number)? Refusal { get; private set; }

    /// <summary>Lines of packets after the refused one that the controller stored.</summary>
    public int StoredAfterGap { get; private set; }

    /// <summary>True when another packet may go: lines left, room in the window, nothing refused.</summary>
    public bool MaySend => NextLine < lineCount && _packetsInFlight < window && Refusal is null;

    /// <summary>True when a probe may go: everything that will be sent is sent (the tail, where no later reply can reveal a lost one), and probes are left.</summary>
    public bool MayProbe => (NextLine >= lineCount || Refusal is not null) && ProbesSent < maxProbes;

    /// <summary>True when the oldest reply due is a probe's.</summary>
    public bool HeadIsProbe => _inFlight.Count > 0 && _inFlight.Peek().Probe;

    /// <summary>True when every reply due was read and nothing more will be sent.</summary>
    public bool Finished => _inFlight.Count == 0 && (NextLine >= lineCount || Refusal is not null);

    /// <summary>A packet with lines <paramref name="start"/> up to (not including) <paramref name="end"/> went out.</summary>
    public void Sent(int start, int end)
    {
        _inFlight.Enqueue(new InFlight(start, end, false));
        _packetsInFlight++;
        Packets++;
        NextLine = end;
    }

    /// <summary>A READREADY probe went out.</summary>
    public void Probed()
    {
        _inFlight.Enqueue(new InFlight(0, 0, true));
        ProbesSent++;
    }

    /// <summary>The oldest reply due arrived: a packet's 4-byte status, or (for a probe) anything.</summary>
    public void Received(ReadOnlySpan<byte> status)
    {
        var p = _inFlight.Dequeue();
        if (p.Probe)
        {
            return;
        }

        _packetsInFlight--;
        var refused = VrPmac.TryReadWriteBufferError(status, out var number, out var lineInPacket);
        var count = p.End - p.Start;
        if (Refusal is null)
        {
            if (refused)
            {
                Refusal = (p.Start + Math.Min(lineInPacket, count - 1), number);
            }

            return;
        }

        // A packet sent before the refusal came back: the controller stored what it accepted of it, behind the gap.
        StoredAfterGap += refused ? Math.Min(lineInPacket, count) : count;
    }

    private readonly record struct InFlight(int Start, int End, bool Probe);
}
