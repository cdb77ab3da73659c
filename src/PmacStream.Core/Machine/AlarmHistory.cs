using System.Globalization;
using System.Text;
using System.Text.Json;

namespace PmacStream.Machine;

/// <summary>One alarm as it came and went.</summary>
/// <param name="Code">Stable code (<see cref="AlarmText"/>).</param>
/// <param name="Motor">Motor number.</param>
/// <param name="Axis">Axis letter.</param>
/// <param name="Text">Clear text when it was raised.</param>
/// <param name="Raised">When the console first saw it.</param>
/// <param name="Cleared">When the console saw it gone (cleared, or moved off), or null while active.</param>
public sealed record AlarmRecord(string Code, int Motor, string Axis, string Text, DateTimeOffset Raised, DateTimeOffset? Cleared)
{
    /// <summary>The job on the machine when it was raised, or null (none, or not recorded).</summary>
    public long? JobId { get; init; }
}

/// <summary>
/// Where the console keeps the alarms it has seen. Small on purpose: the stores are being moved behind one store
/// abstraction (issue 26), and this is the seam.
/// </summary>
public interface IAlarmHistory
{
    /// <summary>
    /// Takes the alarms active now: those not open yet are recorded as raised, open ones no longer active as cleared.
    /// Separate processes (one command line call after another) see each other's records.
    /// </summary>
    void Observe(IReadOnlyList<MachineAlarm> active, DateTimeOffset now);

    /// <summary>As <see cref="Observe(IReadOnlyList{MachineAlarm}, DateTimeOffset)"/>, naming the job on the machine (recorded with an alarm raised now).</summary>
    void Observe(IReadOnlyList<MachineAlarm> active, DateTimeOffset now, long? jobId) => Observe(active, now);

    /// <summary>Every record, newest first.</summary>
    IReadOnlyList<AlarmRecord> List();
}

/// <summary>
/// The alarm history as a JSON-lines file beside the job store (before the store kept it: <see cref="StoreAlarmHistory"/>
/// reads such a file in once; tests without a store use it) (<c>alarms.jsonl</c>): one line per raise or clear,
/// appended, so a crash loses at most the line being written.
/// </summary>
public sealed class AlarmHistoryFile : IAlarmHistory
{
    private readonly object _lock = new();

    /// <summary>A history in <paramref name="path"/> (made on the first alarm).</summary>
    public AlarmHistoryFile(string path) => Path = System.IO.Path.GetFullPath(path);

    /// <summary>The file.</summary>
    public string Path { get; }

    /// <summary>The history beside a job store: <c>alarms.jsonl</c> in its folder.</summary>
    public static AlarmHistoryFile Beside(string jobDatabase) =>
        new(System.IO.Path.Combine(System.IO.Path.GetDirectoryName(System.IO.Path.GetFullPath(jobDatabase))!, "alarms.jsonl"));

    /// <inheritdoc />
    public void Observe(IReadOnlyList<MachineAlarm> active, DateTimeOffset now)
    {
        lock (_lock)
        {
            var open = List().Where(r => r.Cleared is null).ToList();
            var lines = new StringBuilder();
            foreach (var a in active.Where(a => !open.Any(o => Same(o, a))))
            {
                lines.Append(Line("raised", a.Code, a.Motor, a.Axis, a.Text, now)).Append('\n');
            }

            foreach (var o in open.Where(o => !active.Any(a => Same(o, a))))
            {
                lines.Append(Line("cleared", o.Code, o.Motor, o.Axis, o.Text, now)).Append('\n');
            }

            if (lines.Length > 0)
            {
                Directory.CreateDirectory(System.IO.Path.GetDirectoryName(Path)!);
                File.AppendAllText(Path, lines.ToString(), new UTF8Encoding(false));
            }
        }
    }

    /// <inheritdoc />
    public IReadOnlyList<AlarmRecord> List()
    {
        var records = new List<AlarmRecord>();
        if (!File.Exists(Path))
        {
            return records;
        }

        foreach (var line in File.ReadAllLines(Path))
        {
            if (Read(line) is not { } e)
            {
                continue; // a line cut by a crash
            }

            if (e.Event == "raised")
            {
                records.Add(new AlarmRecord(e.Code, e.Motor, e.Axis, e.Text, e.Time, null));
            }
            else if (records.FindLastIndex(r => r.Cleared is null && r.Code == e.Code && r.Motor == e.Motor) is var i and >= 0)
            {
                records[i] = records[i] with { Cleared = e.Time };
            }
        }

        records.Reverse();
        return records;
    }

    private static bool Same(AlarmRecord r, MachineAlarm a) => r.Code == a.Code && r.Motor == a.Motor;

    private static string Line(string kind, string code, int motor, string axis, string text, DateTimeOffset time)
    {
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer))
        {
            w.WriteStartObject();
            w.WriteString("event", kind);
            w.WriteString("code", code);
            w.WriteNumber("motor", motor);
            w.WriteString("axis", axis);
            w.WriteString("text", text);
            w.WriteString("time", time.ToString("O", CultureInfo.InvariantCulture));
            w.WriteEndObject();
        }

        return Encoding.UTF8.GetString(buffer.ToArray());
    }

    private static (string Event, string Code, int Motor, string Axis, string Text, DateTimeOffset Time)? Read(string line)
    {
        try
        {
            using var doc = JsonDocument.Parse(line);
            var r = doc.RootElement;
            return (r.GetProperty("event").GetString()!, r.GetProperty("code").GetString()!, r.GetProperty("motor").GetInt32(), r.GetProperty("axis").GetString()!,
                r.GetProperty("text").GetString()!, DateTimeOffset.Parse(r.GetProperty("time").GetString()!, CultureInfo.InvariantCulture));
        }
        catch (Exception e) when (e is JsonException or KeyNotFoundException or InvalidOperationException or FormatException)
        {
            return null;
        }
    }
}
