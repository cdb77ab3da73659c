namespace PmacStream.Sim;

/// <summary>
/// The simulator's virtual clock as a <see cref="TimeProvider"/>, so a streaming session's elapsed time, ETA and
/// checkpoint times are machine time however fast the simulator is stepped.
/// </summary>
/// <param name="sim">The simulated controller whose clock (<see cref="PmacSimulator.Now"/>) is read.</param>
/// <param name="epoch">Wall time at virtual second 0; null means the wall time when this provider was made.</param>
public sealed class SimTimeProvider(PmacSimulator sim, DateTimeOffset? epoch = null) : TimeProvider
{
    private readonly DateTimeOffset _epoch = epoch ?? System.GetUtcNow();

    /// <inheritdoc />
    public override long TimestampFrequency => 1_000_000;

    /// <inheritdoc />
    public override long GetTimestamp() => (long)(sim.Now * 1_000_000);

    /// <inheritdoc />
    public override DateTimeOffset GetUtcNow() => _epoch.AddSeconds(sim.Now);
}
