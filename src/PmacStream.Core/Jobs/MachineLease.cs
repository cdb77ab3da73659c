using System.Data.Common;
using System.Globalization;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>
/// This station's lease of one machine, held while it drives the controller: taken before anything is sent, renewed
/// by a heartbeat, given back when the job ends. When the store cannot be reached the heartbeat only logs and tries
/// again at its next beat: the job runs on, and the lease is renewed as soon as the store answers (if the outage lasted
/// longer than the expiry, another station may have taken the machine meanwhile: that is logged as an error).
/// </summary>
public sealed class MachineLease : IAsyncDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<MachineLease>();
    private readonly MachineLeases _leases;
    private readonly TimeSpan _expiry;
    private readonly CancellationTokenSource _stop = new();
    private readonly object _lock = new();
    private readonly Task _heartbeat;
    private readonly string _station;
    private long? _jobId;
    private bool _unreachable;

    private MachineLease(MachineLeases leases, string machine, string station, long? jobId, StationSettings settings)
    {
        _leases = leases;
        Machine = machine;
        _station = station;
        _jobId = jobId;
        _expiry = settings.LeaseExpiry;
        _heartbeat = Task.Run(() => BeatAsync(settings.LeaseHeartbeat, _stop.Token));
    }

    /// <summary>The machine leased.</summary>
    public string Machine { get; }

    /// <summary>Heartbeats written since the lease was taken.</summary>
    public int Heartbeats { get; private set; }

    /// <summary>
    /// Takes <paramref name="machine"/>'s lease for this station, or refuses with who holds it (nothing was sent to
    /// the controller then). The same station takes its own lease back when the process that held it is gone.
    /// </summary>
    /// <exception cref="JobException">Another station holds the machine, or the store cannot be reached (the lease cannot be proven free).</exception>
    public static MachineLease Take(StoreLocation store, string machine, string station, long? jobId, StationSettings settings)
    {
        ArgumentNullException.ThrowIfNull(store);
        ArgumentNullException.ThrowIfNull(settings);
        var leases = MachineLeasesOf(store);
        try
        {
            var take = leases.Take(machine, station, jobId, settings.LeaseExpiry);
            if (!take.Taken)
            {
                throw new JobException(Refusal(take.Holder, machine), JobErrorKind.Failed);
            }

            Log.Information("Machine {Machine:l} leased by station {Station:l} (pid {Pid}) in {Store:l}", machine, station, Environment.ProcessId, store.Display);
            return new MachineLease(leases, machine, station, jobId, settings);
        }
        catch (Exception e) when (e is DbException)
        {
            leases.Dispose();
            throw new JobException($"machine {machine}: its lease cannot be taken: {store.Display} cannot be reached ({StoreLocation.Redact(e.Message)}); nothing was sent", JobErrorKind.Failed, e);
        }
        catch
        {
            leases.Dispose();
            throw;
        }
    }

    /// <summary>The refusal the operator reads: who holds the machine, since when, and when it frees itself.</summary>
    public static string Refusal(LeaseHolder? holder, string machine)
    {
        if (holder is null)
        {
            return $"machine {machine}: its lease could not be taken (try again)";
        }

        var job = holder.JobId is { } j ? string.Create(CultureInfo.InvariantCulture, $", job {j}") : string.Empty;
        return string.Create(CultureInfo.InvariantCulture,
            $"machine {machine} is leased by station {holder.Station} (pid {holder.Pid}{job}) since {holder.Since.ToLocalTime():HH:mm:ss}; it expires {holder.Expiry.TotalSeconds:0.#} s after its last heartbeat ({holder.Heartbeat.ToLocalTime():HH:mm:ss})");
    }

    /// <summary>Names the job the machine runs (written at the next heartbeat, and at once when the store answers).</summary>
    public void SetJob(long? jobId)
    {
        if (jobId is null)
        {
            return;
        }

        _jobId = jobId;
        try
        {
            Renew();
        }
        catch (DbException e)
        {
            Unreachable(e);
        }
    }

    /// <summary>Stops the heartbeat and gives the lease back (an unreachable store lets it expire instead).</summary>
    public async ValueTask DisposeAsync()
    {
        await _stop.CancelAsync().ConfigureAwait(false);
        try
        {
            await _heartbeat.ConfigureAwait(false);
        }
        catch (OperationCanceledException)
        {
        }

        try
        {
            _leases.Release(Machine);
            Log.Information("Machine {Machine:l}: lease given back by station {Station:l}", Machine, _station);
        }
        catch (DbException e)
        {
            Log.Warning("Machine {Machine:l}: the lease could not be given back ({Error:l}); it expires {Seconds:0} s after its last heartbeat", Machine, StoreLocation.Redact(e.Message), _expiry.TotalSeconds);
        }

        _leases.Dispose();
        _stop.Dispose();
    }

    private static MachineLeases MachineLeasesOf(StoreLocation store)
    {
        try
        {
            return MachineLeases.Open(store);
        }
        catch (JobStoreException e)
        {
            throw new JobException($"machine lease: {e.Message}; nothing was sent", JobErrorKind.Failed, e);
        }
    }

    private async Task BeatAsync(TimeSpan period, CancellationToken ct)
    {
        using var timer = new PeriodicTimer(period);
        while (await timer.WaitForNextTickAsync(ct).ConfigureAwait(false))
        {
            try
            {
                Renew();
            }
            catch (Exception e) when (e is DbException or InvalidOperationException or TimeoutException)
            {
                Unreachable(e);
            }
        }
    }

    private void Renew()
    {
        lock (_lock)
        {
            if (_leases.Renew(Machine, _jobId))
            {
                Heartbeats++;
                if (_unreachable)
                {
                    _unreachable = false;
                    Log.Information("Machine {Machine:l}: the store answers again; lease renewed", Machine);
                }

                return;
            }

            // The row is gone or another process holds it: the outage outlasted the expiry. Take it again when free.
            var take = _leases.Take(Machine, _station, _jobId, _expiry);
            _unreachable = false;
            if (take.Taken)
            {
                Log.Warning("Machine {Machine:l}: the lease had expired (the store could not be reached for longer than {Seconds:0} s); taken again", Machine, _expiry.TotalSeconds);
            }
            else
            {
                Log.Error("Machine {Machine:l}: this station lost its lease while the store could not be reached: {Refusal:l}", Machine, Refusal(take.Holder, Machine));
            }
        }
    }

    private void Unreachable(Exception e)
    {
        if (!_unreachable)
        {
            _unreachable = true;
            Log.Warning("Machine {Machine:l}: the lease cannot be renewed ({Error:l}); the job runs on and the lease is renewed when the store answers", Machine,
                StoreLocation.Redact(e.Message));
        }
    }
}
