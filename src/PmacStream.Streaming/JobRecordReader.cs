using System.Globalization;
using System.Text.RegularExpressions;
using System.Data.Common;

namespace PmacStream.Streaming;

/// <summary>
/// Reads one row of the jobs table into a <see cref="JobRecord"/>, checking every field against what the store writes:
/// SQLite keeps whatever a damaged or hand-edited file holds (text in an integer column, a NULL, a number beyond
/// <see cref="int"/>), and a resume must not act on it. A bad field is a <see cref="JobStoreException"/> naming the
/// file, the job, the column and the value.
/// </summary>
internal static partial class JobRecordReader
{
    /// <summary>The columns read, in order.</summary>
    public const string Columns = "id, created, program_path, program_sha256, manifest_path, strategy, connection, from_line, message, "
        + "cp_time, cp_state, cp_last_line, cp_chunk, cp_next_chunk, cp_next_line, cp_next_exact, cp_chunks_downloaded, cp_started, line_probe, preamble, cp_loaded, settings, profile, profile_identity, "
        + "program_id, station, machine, os_user, runner, ended, outcome, blocks_executed, blocks_total, stops, alarms, resumes, source_location, to_line";

    public static JobRecord Read(DbDataReader r, string path)
    {
        var row = new Row(r, path);
        var id = row.Int(0, 1, long.MaxValue)!.Value;
        row.Job = id;
        var strategy = row.Text(5)!;
        StrategyKind kind;
        try
        {
            kind = StreamingStrategies.Parse(strategy);
        }
        catch (ArgumentException)
        {
            throw row.Bad(5, "a strategy (chunk, pr or adaptive)");
        }

        var sha = row.Text(3)!;
        if (!Sha256Hex().IsMatch(sha))
        {
            throw row.Bad(3, "a SHA-256 digest in hex");
        }

        var probe = row.Text(18, nullable: true, empty: true) ?? "P501";
        if (probe.Length > 0 && !ProbeVariable().IsMatch(probe))
        {
            throw row.Bad(18, "a PMAC variable such as P501, or nothing");
        }

        Checkpoint? cp = null;
        if (!r.IsDBNull(9))
        {
            var time = row.Time(9);
            // Exactly a name the store writes: Enum.Parse would also take "3" or "Running, Held".
            var stateText = row.Text(10)!;
            if (!Enum.GetNames<SessionState>().Contains(stateText, StringComparer.Ordinal))
            {
                throw row.Bad(10, $"a session state ({string.Join(", ", Enum.GetNames<SessionState>())})");
            }

            var state = Enum.Parse<SessionState>(stateText);

            cp = new Checkpoint(
                row.Line(11)!.Value,
                row.Line(12)!.Value,
                new StreamPosition(row.Line(13)!.Value, row.Line(14)!.Value),
                row.Flag(15)!.Value,
                row.Line(16)!.Value,
                state,
                time,
                row.Flag(17)!.Value,
                row.Flag(20, nullable: true) ?? true);
        }

        return new JobRecord(
            id,
            row.Text(2)!,
            sha,
            row.Text(4)!,
            kind,
            row.Text(6)!,
            row.Line(7, nullable: true, min: 1),
            row.Text(8, nullable: true, empty: true) ?? string.Empty,
            cp,
            row.Time(1),
            row.Text(19, nullable: true, empty: true) is { } pre ? pre.Split('\n') : null,
            probe.Length > 0 ? probe : null,
            row.Text(21, nullable: true, empty: true),
            row.Text(22, nullable: true),
            row.Text(23, nullable: true))
        {
            History = ReadHistory(row),
            SourceLocation = row.Text(36, nullable: true, empty: true),
            ToLine = row.Line(37, nullable: true, min: 1),
        };
    }

    private static JobHistory ReadHistory(Row row) => new(
        row.Int(24, 1, long.MaxValue, nullable: true),
        row.Text(25, nullable: true, empty: true),
        row.Text(26, nullable: true, empty: true),
        row.Text(27, nullable: true, empty: true),
        row.Text(28, nullable: true, empty: true),
        row.Text(29, nullable: true) is not null ? row.Time(29) : null,
        row.Text(30, nullable: true),
        row.Int(31, 0, long.MaxValue, nullable: true),
        row.Int(32, 0, long.MaxValue, nullable: true),
        (int)(row.Int(33, 0, int.MaxValue, nullable: true) ?? 0),
        (int)(row.Int(34, 0, int.MaxValue, nullable: true) ?? 0),
        (int)(row.Int(35, 0, int.MaxValue, nullable: true) ?? 0));

    [GeneratedRegex("^[0-9a-fA-F]{1,128}$")]
    private static partial Regex Sha256Hex();

    [GeneratedRegex("^[PQMI][0-9]{1,4}$")]
    private static partial Regex ProbeVariable();

    private sealed class Row(DbDataReader r, string path)
    {
        private static readonly string[] Names = Columns.Split(", ");

        public long? Job { get; set; }

        public long? Int(int column, long min, long max, bool nullable = false)
        {
            var value = r.GetValue(column);
            if (value is DBNull && nullable)
            {
                return null;
            }

            return value is long n && n >= min && n <= max
                ? n
                : throw Bad(column, min == max ? $"{min}" : $"a whole number from {min} to {max}");
        }

        public int? Line(int column, bool nullable = false, int min = 0) => (int?)Int(column, min, int.MaxValue, nullable);

        public bool? Flag(int column, bool nullable = false) => Int(column, 0, 1, nullable) is { } n ? n != 0 : null;

        public string? Text(int column, bool nullable = false, bool empty = false)
        {
            var value = r.GetValue(column);
            if (value is DBNull && nullable)
            {
                return null;
            }

            return value is string s && (empty || s.Trim().Length > 0)
                ? s
                : throw Bad(column, "text");
        }

        public DateTimeOffset Time(int column)
        {
            var text = Text(column);
            return DateTimeOffset.TryParse(text, CultureInfo.InvariantCulture, DateTimeStyles.RoundtripKind, out var t)
                ? t
                : throw Bad(column, "a date and time such as 2026-01-31T12:00:00Z");
        }

        public JobStoreException Bad(int column, string expected)
        {
            var value = r.GetValue(column);
            var shown = value switch
            {
                DBNull => "NULL",
                string s => $"'{(s.Length > 40 ? s[..40] + "..." : s)}'",
                byte[] b => $"{b.Length} bytes of binary data",
                double d => d.ToString("R", CultureInfo.InvariantCulture),
                _ => Convert.ToString(value, CultureInfo.InvariantCulture),
            };
            var job = Job is { } id ? $"job {id}" : "a job";
            return new JobStoreException(
                path,
                JobStoreProblem.BadRecord,
                $"{path}: {job}: {Names[column]} holds {shown}, expected {expected}: the job's record is damaged and it cannot be resumed from it (check where the machine is, then start the program again from a line)");
        }
    }
}
