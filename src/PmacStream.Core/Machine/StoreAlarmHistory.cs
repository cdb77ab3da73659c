using System.Data.Common;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;
using Serilog;

namespace PmacStream.Machine;

/// <summary>
/// The alarm history in the store the job service uses (table <c>alarms</c>, migration 5, on SQLite or PostgreSQL):
/// per machine (the controller's connection), each alarm with the job that was on the machine when it came, and when
/// it was cleared. An <c>alarms.jsonl</c> an earlier version kept beside the job store is read into it once (and renamed
/// <c>alarms.jsonl.imported</c>). The store is written only when the active alarms change, so a console polling its
/// DRO does not write each sample; a store that cannot be reached loses the change with a warning, never the sample.
/// </summary>
public sealed class StoreAlarmHistory : IAlarmHistory
{
    private static readonly ILogger Log = Serilog.Log.ForContext<StoreAlarmHistory>();
    private readonly object _lock = new();
    private string? _written;

    /// <summary>The history of <paramref name="machine"/> in <paramref name="store"/>, importing <paramref name="legacyFile"/> when it exists.</summary>
    public StoreAlarmHistory(StoreLocation store, string machine, string? legacyFile = null)
    {
        Store = store ?? throw new ArgumentNullException(nameof(store));
        Machine = machine ?? throw new ArgumentNullException(nameof(machine));
        LegacyFile = legacyFile;
    }

    /// <summary>The history in <paramref name="jobs"/>' store for <paramref name="machine"/>, reading in the alarms.jsonl an earlier version kept beside it.</summary>
    public static StoreAlarmHistory Of(JobService jobs, string machine)
    {
        ArgumentNullException.ThrowIfNull(jobs);
        return new StoreAlarmHistory(jobs.Store, machine, Path.Combine(MachineConsoleOptions.StateFolder(jobs), "alarms.jsonl"));
    }

    /// <summary>The store.</summary>
    public StoreLocation Store { get; }

    /// <summary>The machine the alarms are recorded for (a connection such as <c>tcp:127.0.0.1:1025</c>).</summary>
    public string Machine { get; }

    /// <summary>An old <c>alarms.jsonl</c> to read in once, or null.</summary>
    public string? LegacyFile { get; }

    /// <summary>The same history for another machine (the HMI knows its controller only once connected).</summary>
    public StoreAlarmHistory On(string machine) => new(Store, machine, LegacyFile);

    /// <inheritdoc />
    public void Observe(IReadOnlyList<MachineAlarm> active, DateTimeOffset now) => Observe(active, now, null);

    /// <inheritdoc />
    public void Observe(IReadOnlyList<MachineAlarm> active, DateTimeOffset now, long? jobId)
    {
        ArgumentNullException.ThrowIfNull(active);
        var key = string.Join(",", active.Select(a => a.Code + ":" + a.Motor));
        lock (_lock)
        {
            if (key == _written)
            {
                return;
            }

            try
            {
                using var store = Open();
                var open = store.List(Machine).Where(r => r.Cleared is null).ToList();
                foreach (var a in active.Where(a => !open.Any(o => o.Code == a.Code && o.Motor == a.Motor)))
                {
                    store.Raise(Machine, a.Code, a.Motor, a.Axis, a.Text, now, jobId);
                }

                foreach (var o in open.Where(o => !active.Any(a => o.Code == a.Code && o.Motor == a.Motor)))
                {
                    store.Clear(o.Id, now);
                }

                _written = key;
            }
            catch (Exception e) when (e is DbException or InvalidOperationException or IOException or UnauthorizedAccessException)
            {
                Log.Warning("Alarm history in {Store:l} not written: {Message:l}", Store.Display, StoreLocation.Redact(e.Message));
            }
        }
    }

    /// <inheritdoc />
    public IReadOnlyList<AlarmRecord> List()
    {
        try
        {
            using var store = Open();
            return store.List(Machine).Select(r => new AlarmRecord(r.Code, r.Motor, r.Axis, r.Text, r.Raised, r.Cleared) { JobId = r.JobId }).ToList();
        }
        catch (Exception e) when (e is DbException or InvalidOperationException or IOException or UnauthorizedAccessException)
        {
            Log.Warning("Alarm history in {Store:l} not read: {Message:l}", Store.Display, StoreLocation.Redact(e.Message));
            return [];
        }
    }

    private IAlarmStore Open()
    {
        var store = AlarmStores.Open(Store);
        try
        {
            ImportLegacy(store);
            return store;
        }
        catch
        {
            store.Dispose();
            throw;
        }
    }

    /// <summary>
    /// Reads an old <c>alarms.jsonl</c> into the store once: the file is first renamed (so two processes do not both
    /// read it), its records written, and it stays as <c>alarms.jsonl.imported</c>.
    /// </summary>
    private void ImportLegacy(IAlarmStore store)
    {
        if (LegacyFile is null || !File.Exists(LegacyFile))
        {
            return;
        }

        var claimed = LegacyFile + ".imported";
        try
        {
            File.Move(LegacyFile, claimed, overwrite: false);
        }
        catch (IOException)
        {
            return; // another process took it, or it was imported before
        }

        var records = new AlarmHistoryFile(claimed).List().Reverse().ToList();
        foreach (var r in records)
        {
            var id = store.Raise(Machine, r.Code, r.Motor, r.Axis, r.Text, r.Raised, null);
            if (r.Cleared is { } cleared)
            {
                store.Clear(id, cleared);
            }
        }

        Log.Information("Alarm history: {Count} records of {File:l} read into {Store:l}", records.Count, LegacyFile, Store.Display);
    }
}
