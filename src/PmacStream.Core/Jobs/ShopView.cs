using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>One machine of the shop: who holds its lease, and the job it runs (or ran last).</summary>
/// <param name="Machine">The machine's name (<c>--machine</c>, else its connection).</param>
/// <param name="Lease">Its lease, or null (no station holds it).</param>
/// <param name="Job">The lease's job, else the newest job recorded on the machine, or null.</param>
public sealed record ShopMachine(string Machine, LeaseHolder? Lease, JobRecord? Job);

/// <summary>One machine of the shop as a screen shows it (what <c>pmacstream shop --json</c> prints), without the store's types.</summary>
/// <param name="Machine">The machine's name.</param>
/// <param name="Station">The station holding its lease, or null.</param>
/// <param name="Pid">The holder's process, or null.</param>
/// <param name="JobId">The job there (the lease's, else the machine's newest), or null.</param>
/// <param name="ProgramId">That job's stored revision, or null.</param>
/// <param name="Program">That job's program file name, or null.</param>
/// <param name="Line">The line of its latest checkpoint, or null.</param>
/// <param name="BlocksExecuted">Blocks executed, or null without a job.</param>
/// <param name="BlocksTotal">Blocks of the program, or null.</param>
/// <param name="Outcome">running, completed, aborted, interrupted or alarm; null without a job.</param>
/// <param name="State">leased, expired or free.</param>
/// <param name="Heartbeat">The lease's last heartbeat, or null.</param>
public sealed record ShopMachineView(string Machine, string? Station, long? Pid, long? JobId, long? ProgramId, string? Program, long? Line,
    long? BlocksExecuted, long? BlocksTotal, string? Outcome, string State, DateTimeOffset? Heartbeat);

/// <summary>The shop view: every machine the store knows (leased now, or named in the job history).</summary>
public sealed partial class JobService
{
    /// <summary>
    /// Takes <paramref name="machine"/>'s lease in this service's store for <paramref name="station"/> (<see cref="MachineLease.Take"/>):
    /// what a face calls before a job sends anything.
    /// </summary>
    /// <exception cref="JobException">Another station holds the machine, or the store cannot be reached.</exception>
    public MachineLease TakeLease(string machine, string station, StationSettings settings) => MachineLease.Take(Store, machine, station, null, settings);

    /// <summary>The machine a job was recorded on (<c>--machine</c> or the HMI's), or null when it named none (its connection is the machine).</summary>
    /// <exception cref="JobException">No such job.</exception>
    public string? RecordedMachine(long jobId) => FindJob(jobId).History.Machine;

    /// <summary>The shop (<see cref="Shop"/>) as views a screen reads (the HMI's Store page).</summary>
    /// <exception cref="JobStoreException">The store cannot be opened or reached.</exception>
    public IReadOnlyList<ShopMachineView> ShopViews() => Shop().Select(m =>
    {
        var (j, l) = (m.Job, m.Lease);
        return new ShopMachineView(m.Machine, l?.Station, l?.Pid, j?.Id, j?.History.ProgramId, j is null ? null : Path.GetFileName(j.ProgramPath),
            j?.Checkpoint?.LastExecutedLine, j is null ? null : j.History.BlocksExecuted ?? 0, j?.History.BlocksTotal, j?.Outcome,
            l is null ? "free" : l.Expired ? "expired" : "leased", l?.Heartbeat);
    }).ToList();

    /// <summary>
    /// The shop: every machine with a lease or a job in the store, by name, with its lease holder and the job running
    /// there (its checkpoint's line and blocks executed). Empty when the store has nothing yet.
    /// </summary>
    /// <exception cref="JobStoreException">The store cannot be opened or reached.</exception>
    public IReadOnlyList<ShopMachine> Shop()
    {
        if (!JobStores.Exists(Store))
        {
            return [];
        }

        IReadOnlyList<LeaseHolder> leases;
        using (var l = MachineLeases.Open(Store))
        {
            try
            {
                leases = l.List();
            }
            catch (System.Data.Common.DbException e)
            {
                throw new JobStoreException(Store.Display, JobStoreProblem.Unavailable, $"{Store.Display}: cannot read the leases: {Preparation.Store.StoreLocation.Redact(e.Message)}", e);
            }
        }

        IReadOnlyList<JobRecord> jobs;
        using (var store = JobStores.Open(Store))
        {
            jobs = store.List(); // newest first
        }

        var byId = jobs.ToDictionary(j => j.Id);
        var names = leases.Select(l => l.Machine).Concat(jobs.Select(j => j.History.Machine ?? MachineNameOf(j.Connection))).Distinct(StringComparer.Ordinal).Order(StringComparer.Ordinal);
        return names.Select(m =>
        {
            var lease = leases.FirstOrDefault(l => l.Machine == m);
            var job = lease?.JobId is { } id && byId.TryGetValue(id, out var leased) ? leased : jobs.FirstOrDefault(j => (j.History.Machine ?? MachineNameOf(j.Connection)) == m);
            return new ShopMachine(m, lease, job);
        }).ToList();
    }

    private static string MachineNameOf(string connection)
    {
        try
        {
            return MachineName(Pmac.ConnectionSpec.Parse(connection));
        }
        catch (FormatException)
        {
            return connection;
        }
    }
}
