using System.Globalization;
using PmacStream.Jobs;

namespace PmacStream.Hmi;

/// <summary>What the status panel is made from: the job's last status and what the screen knows besides.</summary>
/// <param name="Job">The running or last job's status, null before the first job.</param>
/// <param name="JobActive">True while the job runs or is held.</param>
/// <param name="Split">The split, null before one.</param>
/// <param name="Program">The open program's line index, null before one is opened.</param>
/// <param name="FeedOverride">The operator's feed override setting, percent.</param>
/// <param name="Settings">The running job's settings (its download window), else the settings the next job starts with.</param>
/// <param name="Strategy">The running job's strategy, else the selected one.</param>
internal sealed record StatusFacts(
    HmiJobStatus? Job, bool JobActive, SplitView? Split, ProgramLineSource? Program, double FeedOverride, RunSettings Settings, string Strategy);

/// <summary>
/// The status panel's texts (state, files, lines, current file and line, progress, feed override, feed, download
/// window, elapsed, remaining) in the chosen language.
/// </summary>
internal static class StatusStrip
{
    /// <summary>What the panel shows.</summary>
    public static StatusDisplay Show(StatusFacts f, HmiLanguage language)
    {
        var s = f.Job;
        var manifest = f.Split;
        string programLines;
        if (f.Program is not { } program)
        {
            programLines = "-";
        }
        else if (program.IsComplete)
        {
            programLines = program.IndexedLines.ToString("N0", CultureInfo.InvariantCulture);
        }
        else
        {
            programLines = HmiText.Format(TextId.Indexing, language, program.IndexedLines);
        }

        var currentFile = "-";
        if (s is not null && manifest is not null && s.CurrentChunk >= 1 && s.CurrentChunk <= manifest.Chunks.Count)
        {
            currentFile = $"{s.CurrentChunk}/{manifest.Chunks.Count}  {manifest.Chunks[s.CurrentChunk - 1].FileName}";
        }

        var state = s is { State: HmiJobState.Stopped, Stop: { } stop } ? StopText(TextId.StateStopped, stop, language) : HmiText.Get(s?.State switch
        {
            HmiJobState.Running => TextId.StateRunning,
            HmiJobState.Held => TextId.StateHeld,
            HmiJobState.Completed => TextId.StateCompleted,
            HmiJobState.Aborted => TextId.StateAborted,
            HmiJobState.Failed => TextId.StateFailed,
            _ => TextId.StateIdle,
        }, language);

        var percent = s is null ? 0 : Math.Clamp(s.Percent, 0, 100);
        var inForce = f.JobActive && s?.FeedOverride is { } reported ? reported : f.FeedOverride;
        return new StatusDisplay(
            State: state,
            TotalFiles: manifest is null ? "-" : manifest.Chunks.Count.ToString(CultureInfo.InvariantCulture),
            ProgramLines: programLines,
            CurrentFile: currentFile,
            CurrentLine: s is null || s.CurrentLine == 0 ? "-" : s.CurrentLine.ToString("N0", CultureInfo.InvariantCulture) + (s.SourceLocation is { } origin ? $" ({origin})" : string.Empty),
            ProgressPercent: (int)Math.Round(percent),
            Progress: percent.ToString("0.0", CultureInfo.InvariantCulture) + " %",
            FeedOverride: Math.Abs(inForce - f.FeedOverride) >= 0.05
                ? string.Create(CultureInfo.InvariantCulture, $"{inForce:0.#} % → {f.FeedOverride:0.#} %") // slewing to the setting
                : string.Create(CultureInfo.InvariantCulture, $"{f.FeedOverride:0.#} %"),
            Feed: s?.ProgrammedFeed is { } programmed
                ? string.Create(CultureInfo.InvariantCulture, $"F{programmed:0.#} × {inForce:0.#} % = {FeedOverrides.Resulting(programmed, inForce):0.#}")
                : "-",
            DownloadWindow: Window(f, language),
            Elapsed: s is null ? "-" : Clock(s.Elapsed),
            Eta: s?.Eta is { } eta ? Clock(eta) : "-");
    }

    /// <summary>The program-stop banner of a job waiting at a stop ("Program stop (M00) at line n: Resume continues"), else empty.</summary>
    public static string Banner(HmiJobStatus? job, HmiLanguage language) =>
        job is { State: HmiJobState.Stopped, Stop: { } stop } ? StopText(TextId.ProgramStopBanner, stop, language) : string.Empty;

    /// <summary>"Program stop (M00) at line n" (<paramref name="id"/>: the state, or the banner), the code left out when the stop names none.</summary>
    public static string StopText(TextId id, JobStop stop, HmiLanguage language)
    {
        var text = HmiText.Format(id, language, stop.Code ?? string.Empty, stop.Line.ToString("N0", CultureInfo.InvariantCulture));
        return stop.Code is null ? text.Replace(" ()", string.Empty, StringComparison.Ordinal) : text;
    }

    /// <summary>The download window, and the lines of the executing chunk it spans while the chunk strategy runs.</summary>
    private static string Window(StatusFacts f, HmiLanguage language)
    {
        var start = f.Settings.WindowStart * 100;
        var end = f.Settings.WindowEnd * 100;
        if (!string.Equals(f.Strategy, "chunk", StringComparison.OrdinalIgnoreCase) && f.Strategy.Length > 0)
        {
            return HmiText.Format(TextId.WindowNotUsed, language, start, end, f.Strategy);
        }

        if (f.JobActive && f.Job is { CurrentChunk: >= 1 } s && f.Split is { } m && s.CurrentChunk < m.Chunks.Count)
        {
            // As the chunk strategy measures it: M0 at fraction (line - first + 1) / lines of the chunk.
            var chunk = m.Chunks[s.CurrentChunk - 1];
            var size = Math.Max(1, chunk.LastSourceLine - chunk.FirstSourceLine + 1);
            var from = chunk.FirstSourceLine - 1 + (int)Math.Ceiling(f.Settings.WindowStart * size);
            var to = chunk.FirstSourceLine - 1 + (int)Math.Floor(f.Settings.WindowEnd * size);
            return HmiText.Format(TextId.WindowLines, language, start, end, from, to, s.CurrentChunk + 1);
        }

        return HmiText.Format(TextId.WindowPercent, language, start, end);
    }

    private static string Clock(TimeSpan t) =>
        t.TotalHours >= 1
            ? string.Create(CultureInfo.InvariantCulture, $"{(int)t.TotalHours}:{t.Minutes:00}:{t.Seconds:00}")
            : string.Create(CultureInfo.InvariantCulture, $"{t.Minutes:00}:{t.Seconds:00}");
}
