using PmacStream.Pmac;

namespace PmacStream.Testing;

/// <summary>Thrown by the fault wrapper to model the host process dying mid-call.</summary>
public sealed class HostKilledException : Exception
{
    public HostKilledException()
        : base("host killed")
    {
    }
}

/// <summary>
/// An in-process connection that injects seeded faults: link resets before a command, replies lost after it ran,
/// ERR replies, slow replies (the virtual clock runs on while waiting) and host kills; downloads break off part-way,
/// or (on demand) are stored whole and their reply lost.
/// </summary>
public sealed class FaultyConnection(IPmacPortEndpoint port, Random random, Action<double> slow) : IPmacConnection
{
    private readonly InProcessConnection _inner = new(port, "faulty");

    public double FaultRate { get; set; }

    public double KillRate { get; set; }

    public bool Down { get; set; }

    /// <summary>
    /// Set: the next download is stored whole by the controller, then its reply is lost (the link goes down) or, with
    /// <see cref="KillWithLostReply"/>, the host dies before the reply arrives. Cleared once it happened.
    /// </summary>
    public bool LoseNextDownloadReply { get; set; }

    /// <summary>With <see cref="LoseNextDownloadReply"/>: the host dies instead of seeing the link fail.</summary>
    public bool KillWithLostReply { get; set; }

    public int Injected { get; private set; }

    public string Description => "faulty in-process";

    public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        if (Down)
        {
            throw new PmacLinkException("link down");
        }

        switch (Pick())
        {
            case 1:
                Down = true;
                throw new PmacLinkException("link reset");
            case 2:
                await _inner.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
                Down = true;
                throw new PmacLinkException("reply lost");
            case 3:
                throw new PmacErrorException(3, command);
            case 4:
                slow(0.02 + (random.NextDouble() * 0.2));
                break;
            case 5:
                if (random.Next(2) == 0)
                {
                    await _inner.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
                }

                throw new HostKilledException();
        }

        return await _inner.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
    }

    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        if (Down)
        {
            throw new PmacLinkException("link down");
        }

        if (LoseNextDownloadReply)
        {
            // The controller stored every line; the reply that says so never reaches the host.
            LoseNextDownloadReply = false;
            await _inner.DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
            Injected++;
            if (KillWithLostReply)
            {
                throw new HostKilledException();
            }

            Down = true;
            throw new PmacLinkException("reply lost after the controller stored the lines");
        }

        var fault = Pick();
        if (fault is 0 or 4)
        {
            if (fault == 4)
            {
                slow(0.02 + (random.NextDouble() * 0.2));
            }

            await _inner.DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
            return;
        }

        var cut = random.Next(lines.Count + 1);
        await _inner.DownloadAsync(lines.Take(cut).ToList(), cancellationToken).ConfigureAwait(false);
        switch (fault)
        {
            case 1:
            case 2:
                Down = true;
                throw new PmacLinkException("link reset during download");
            case 3:
                if (cut == lines.Count)
                {
                    return;
                }

                throw new PmacErrorException(6, lines[cut], cut);
            default:
                throw new HostKilledException();
        }
    }

    public Task FlushAsync(CancellationToken cancellationToken = default) => _inner.FlushAsync(cancellationToken);

    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => _inner.ControlAsync(control, cancellationToken);

    public ValueTask DisposeAsync() => ValueTask.CompletedTask;

    private int Pick()
    {
        if (random.NextDouble() >= FaultRate + KillRate)
        {
            return 0;
        }

        Injected++;
        if (random.NextDouble() < KillRate / (FaultRate + KillRate))
        {
            return 5;
        }

        return 1 + random.Next(4);
    }
}

/// <summary>
/// An in-process connection that breaks the link or kills the host at one chosen operation (a command or a batch
/// download), counting operations from the first; a download cut by a fault delivers the first part of its lines
/// (the scripted faults of a start or resume, where <see cref="FaultyConnection"/> seeds random ones).
/// </summary>
public sealed class ScriptedConnection(IPmacPortEndpoint port) : IPmacConnection
{
    private readonly InProcessConnection _inner = new(port, "scripted");

    /// <summary>Operations so far.</summary>
    public int Ops { get; private set; }

    /// <summary>Operation whose link breaks (a command does not run; a download delivers half of its lines).</summary>
    public int? BreakAt { get; set; }

    /// <summary>Operation during which the host dies.</summary>
    public int? KillAt { get; set; }

    /// <summary>How much of the killed operation happens: 0 nothing, 0.5 half a download (a command runs), 1 all of it.</summary>
    public double KillFraction { get; set; }

    public List<string> Log { get; } = [];

    public string Description => "scripted in-process";

    public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        var op = ++Ops;
        Log.Add($"{op} {command}");
        if (op == BreakAt)
        {
            throw new PmacLinkException("link reset");
        }

        if (op == KillAt && KillFraction == 0)
        {
            throw new HostKilledException();
        }

        var reply = await _inner.GetResponseAsync(command, cancellationToken).ConfigureAwait(false);
        return op == KillAt ? throw new HostKilledException() : reply;
    }

    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        var op = ++Ops;
        Log.Add($"{op} download {lines.Count}: {string.Join(" ; ", lines.Take(3))} ..");
        if (op == BreakAt)
        {
            await _inner.DownloadAsync(lines.Take(lines.Count / 2).ToList(), cancellationToken).ConfigureAwait(false);
            throw new PmacLinkException("link reset during download");
        }

        if (op == KillAt)
        {
            await _inner.DownloadAsync(lines.Take((int)(lines.Count * KillFraction)).ToList(), cancellationToken).ConfigureAwait(false);
            throw new HostKilledException();
        }

        await _inner.DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
    }

    public Task FlushAsync(CancellationToken cancellationToken = default) => _inner.FlushAsync(cancellationToken);

    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => _inner.ControlAsync(control, cancellationToken);

    public ValueTask DisposeAsync() => ValueTask.CompletedTask;
}

/// <summary>
/// An in-process connection that pipelines program downloads as the Ethernet transport does (packets of
/// <see cref="LinesPerPacket"/> lines, up to the window in flight) and, on the <see cref="RefuseDownload"/>th
/// pipelined download, refuses the first tracked line (<c>M0==</c>) of its second packet, as a controller answering
/// ERR003 would: the lines of that packet before it are stored, the rest of the packet is not, and the packets already
/// in flight behind it are stored whole, after the gap. Then it throws what the transport throws.
/// </summary>
public sealed class PipelinedRefusalConnection(IPmacPortEndpoint port) : IPmacConnection
{
    private readonly InProcessConnection _inner = new(port, "pipelined refusal");
    private int _pipelined;

    /// <summary>Lines per simulated WRITEBUFFER packet.</summary>
    public int LinesPerPacket { get; set; } = 29;

    /// <summary>The pipelined download (1-based) whose second packet is refused.</summary>
    public int RefuseDownload { get; set; } = 5;

    /// <summary>The refused line, once refused.</summary>
    public string? Refused { get; private set; }

    /// <summary>Lines stored behind the gap.</summary>
    public int StoredAfterGap { get; private set; }

    public string Description => "pipelined refusal in-process";

    public Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default) => _inner.GetResponseAsync(command, cancellationToken);

    public Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default) => _inner.DownloadAsync(lines, cancellationToken);

    public async Task DownloadAsync(IReadOnlyList<string> lines, int packetsInFlight, CancellationToken cancellationToken = default)
    {
        var packets = lines.Chunk(LinesPerPacket).ToList();
        if (packetsInFlight <= 1 || ++_pipelined != RefuseDownload || packets.Count < 3)
        {
            await _inner.DownloadAsync(lines, cancellationToken).ConfigureAwait(false);
            return;
        }

        await _inner.DownloadAsync(packets[0], cancellationToken).ConfigureAwait(false);
        var second = packets[1];
        var refused = Array.FindIndex(second, l => l.Contains("M0==", StringComparison.Ordinal));
        refused = refused < 0 ? 0 : refused;
        await _inner.DownloadAsync(second.Take(refused).ToList(), cancellationToken).ConfigureAwait(false);
        Refused = second[refused];

        // The packets sent before the refusal came back: stored whole, behind the gap.
        foreach (var p in packets.Skip(2).Take(packetsInFlight - 1))
        {
            await _inner.DownloadAsync(p, cancellationToken).ConfigureAwait(false);
            StoredAfterGap += p.Length;
        }

        throw new PmacErrorException(PmacErrors.UnknownCommand, Refused, LinesPerPacket + refused) { LinesStoredAfterGap = StoredAfterGap };
    }

    public Task FlushAsync(CancellationToken cancellationToken = default) => _inner.FlushAsync(cancellationToken);

    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => _inner.ControlAsync(control, cancellationToken);

    public ValueTask DisposeAsync() => ValueTask.CompletedTask;
}
