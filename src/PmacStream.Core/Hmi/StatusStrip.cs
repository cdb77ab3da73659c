using System.Globalization;
using PmacStream.Program;

namespace PmacStream.Hmi;

/// <summary>The status strip's texts (files, lines, current file and line, progress, feed, elapsed, remaining) in the chosen language.</summary>
internal static class StatusStrip
{
    /// <summary>What the strip shows for a job's last status (null before the first job) and the open program.</summary>
    public static StatusDisplay Show(HmiJobStatus? s, ChunkManifest? manifest, ProgramLineSource? program, double feed, FeedScale scale, HmiLanguage language)
    {
        string programLines;
        if (program is null)
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

        var state = HmiText.Get(s?.State switch
        {
            HmiJobState.Running => TextId.StateRunning,
            HmiJobState.Held => TextId.StateHeld,
            HmiJobState.Completed => TextId.StateCompleted,
            HmiJobState.Aborted => TextId.StateAborted,
            HmiJobState.Failed => TextId.StateFailed,
            _ => TextId.StateIdle,
        }, language);

        var percent = s is null ? 0 : Math.Clamp(s.Percent, 0, 100);
        return new StatusDisplay(
            State: state,
            TotalFiles: manifest is null ? "-" : manifest.Chunks.Count.ToString(CultureInfo.InvariantCulture),
            ProgramLines: programLines,
            CurrentFile: currentFile,
            CurrentLine: s is null || s.CurrentLine == 0 ? "-" : s.CurrentLine.ToString("N0", CultureInfo.InvariantCulture),
            ProgressPercent: (int)Math.Round(percent),
            Progress: percent.ToString("0.0", CultureInfo.InvariantCulture) + " %",
            Feed: feed.ToString("0.#", CultureInfo.InvariantCulture) + " " + scale.Unit,
            Elapsed: s is null ? "-" : Clock(s.Elapsed),
            Eta: s?.Eta is { } eta ? Clock(eta) : "-");
    }

    private static string Clock(TimeSpan t) =>
        t.TotalHours >= 1
            ? string.Create(CultureInfo.InvariantCulture, $"{(int)t.TotalHours}:{t.Minutes:00}:{t.Seconds:00}")
            : string.Create(CultureInfo.InvariantCulture, $"{t.Minutes:00}:{t.Seconds:00}");
}
