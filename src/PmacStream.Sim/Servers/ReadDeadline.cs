namespace PmacStream.Sim.Servers;

/// <summary>
/// The one cancellation source a connection's reads wait on, linked to the server's stop and armed anew for each read
/// (the idle timeout before a packet, the packet timeout inside one). Reset and reused while it has not fired, so
/// serving a packet allocates no source and no timer; only a deadline that fired (the connection then ends) or a
/// different stop token makes a new one.
/// </summary>
internal sealed class ReadDeadline : IDisposable
{
    private CancellationTokenSource? _source;
    private CancellationToken _linked;

    /// <summary>A token cancelled by <paramref name="stop"/> or once <paramref name="after"/> has passed (infinite or zero: never).</summary>
    public CancellationToken Arm(CancellationToken stop, TimeSpan after)
    {
        if (_source is null || _linked != stop || !_source.TryReset())
        {
            _source?.Dispose();
            _source = CancellationTokenSource.CreateLinkedTokenSource(stop);
            _linked = stop;
        }

        if (after > TimeSpan.Zero && after != Timeout.InfiniteTimeSpan)
        {
            _source.CancelAfter(after);
        }

        return _source.Token;
    }

    /// <summary>Stops the armed deadline (its timer) without cancelling, so the source can be reused.</summary>
    public void Disarm() => _source?.TryReset();

    /// <inheritdoc />
    public void Dispose()
    {
        _source?.Dispose();
        _source = null;
    }
}
