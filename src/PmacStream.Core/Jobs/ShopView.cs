using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>One machine of the shop: who holds its lease, and the job it runs (or ran last).</summary>
/// <param name="Machine">The machine's name (<c>--machine</c>, else its connection).</param>
/// <param name="Lease">Its lease, or null (no station holds it).</param>
/// <param name="Job">The lease's job, else the newest job recorded on the machine, or null.</param>
public sealed record ShopMachine(string Machine, LeaseHolder? Lease, JobRecord? Job);

/// <summary>The shop view: every machine the store knows (leased now, or named in the job history).</summary>
public sealed partial class JobService
{
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
