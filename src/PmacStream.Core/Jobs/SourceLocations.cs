using System.Globalization;
using System.Text;
using PmacStream.GCode.Expansion;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>
/// Where the lines of an expanded program (subprograms, macros, loops) came from, on every face: in such a program
/// <c>M0==</c> counts expanded lines, and the split's <see cref="ExpansionMap"/> maps each back to its file, line, call
/// and iteration (<c>O1002 line 7, call 3 of 4 from line 12</c>). A program without subprograms or macros has no map:
/// its lines are its source lines, tracked as before.
/// </summary>
public static class SourceLocations
{
    /// <summary>Calls listed when a start line is ambiguous.</summary>
    public const int ListedCalls = 20;

    /// <summary>The split's map (<see cref="ExpansionMap.FileName"/> in <paramref name="chunkFolder"/>), null when the program was not expanded.</summary>
    public static ExpansionMap? MapOf(string chunkFolder)
    {
        var path = Path.Combine(chunkFolder, ExpansionMap.FileName);
        return File.Exists(path) ? ExpansionMap.Load(path) : null;
    }

    /// <summary>The source location of expanded line <paramref name="line"/>, null without a map (or before the first line).</summary>
    public static string? Describe(ExpansionMap? map, long line) => map == null || line <= 0 ? null : map.Describe(line);

    /// <summary>
    /// The expanded line a start at source line <paramref name="line"/> means: its <paramref name="call"/>-th run (1-based;
    /// needed when it runs more than once), of the file or called program <paramref name="file"/> names (needed when more
    /// than one file has that line number).
    /// </summary>
    /// <exception cref="JobException">The line never runs, runs more than once without a call, is in more than one file without a file, or the call is beyond its runs; the message lists the choices.</exception>
    public static int Resolve(ExpansionMap map, int line, int? call, string? file)
    {
        ArgumentNullException.ThrowIfNull(map);
        var runs = map.Occurrences(line, file);
        var where = file is null ? string.Empty : $" of {file}";
        if (runs.Count == 0)
        {
            throw new JobException($"line {line}{where} never runs in the expanded program", JobErrorKind.BadRequest);
        }

        var files = runs.Select(r => r.File).Distinct().ToList();
        if (files.Count > 1)
        {
            var names = string.Join(", ", files.Select(f => Path.GetFileName(map.Files[f])));
            throw new JobException($"line {line} is a line of more than one file ({names}): say which with --file NAME", JobErrorKind.BadRequest);
        }

        if (call is { } k)
        {
            return k >= 1 && k <= runs.Count
                ? checked((int)runs[k - 1].Expanded)
                : throw new JobException($"line {line}{where} runs {runs.Count} time{(runs.Count == 1 ? string.Empty : "s")}: --call 1 to {runs.Count}", JobErrorKind.BadRequest);
        }

        if (runs.Count == 1)
        {
            return checked((int)runs[0].Expanded);
        }

        var sb = new StringBuilder();
        sb.Append(CultureInfo.InvariantCulture, $"line {line}{where} runs {runs.Count} times (a subprogram, macro or loop): say which with --call N");
        for (var i = 0; i < Math.Min(runs.Count, ListedCalls); i++)
        {
            sb.Append(CultureInfo.InvariantCulture, $"{Environment.NewLine}  --call {i + 1}: {map.Describe(runs[i].Expanded)}");
        }

        if (runs.Count > ListedCalls)
        {
            sb.Append(CultureInfo.InvariantCulture, $"{Environment.NewLine}  ... and {runs.Count - ListedCalls} more");
        }

        throw new JobException(sb.ToString(), JobErrorKind.BadRequest);
    }

    /// <summary>
    /// The start options that name expanded line <paramref name="expanded"/> (<c>--from-line 7 --call 3 --file O1002.nc</c>):
    /// the inverse of <see cref="Resolve"/>, for a message that says how to start there again.
    /// </summary>
    public static string StartOptions(ExpansionMap map, long expanded)
    {
        ArgumentNullException.ThrowIfNull(map);
        if (map.Find(expanded) is not { } o)
        {
            return FormattableString.Invariant($"--from-line LINE (expanded line {expanded} is no longer mapped)");
        }

        var file = o.File != 0 ? Path.GetFileName(map.Files[o.File]) : null;
        var runs = map.Occurrences(o.Line, file);
        var call = runs.FindIndex(r => r.Expanded == expanded) + 1;
        var text = FormattableString.Invariant($"--from-line {o.Line}");
        text += runs.Count > 1 ? FormattableString.Invariant($" --call {call}") : string.Empty;
        return text + (file is null ? string.Empty : " --file " + file);
    }

    /// <summary>
    /// Checkpoints as <paramref name="inner"/> writes them, and the job record's source location (<see cref="IJobStore.SetSourceLocation"/>)
    /// whenever the executed line's location changes.
    /// </summary>
    internal static ICheckpointSink Track(ICheckpointSink inner, IJobStore store, long jobId, ExpansionMap? map) =>
        map == null ? inner : new TrackingSink(inner, store, jobId, map);

    private sealed class TrackingSink(ICheckpointSink inner, IJobStore store, long jobId, ExpansionMap map) : ICheckpointSink
    {
        private int _line = -1;
        private string? _written;

        public void Save(Checkpoint checkpoint, bool durable)
        {
            inner.Save(checkpoint, durable);
            if (checkpoint.LastExecutedLine == _line)
            {
                return;
            }

            _line = checkpoint.LastExecutedLine;
            var text = Describe(map, _line);
            if (text != _written)
            {
                store.SetSourceLocation(jobId, text);
                _written = text;
            }
        }

        public void RecordStart(JobStart start) => inner.RecordStart(start);
    }
}
