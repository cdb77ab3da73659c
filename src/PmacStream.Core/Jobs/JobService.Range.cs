using PmacStream.GCode;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Jobs;

/// <summary>Selected-block execution (lines A..B): the range checked, then run as a program of its own (<see cref="ProgramRange"/>).</summary>
public sealed partial class JobService
{
    /// <summary>
    /// Checks a selected-block range before anything is leased or sent: B not before A and within the program, A and B
    /// blocks (a stored revision's blocks say it; a file's split tracks moves only), B a move the line tracking reports
    /// and not one under cutter compensation (its end is the next move's corner's). Returns the motion blocks the range
    /// runs (a stored revision's count; null for a file, whose count the cut split gives).
    /// </summary>
    /// <exception cref="JobException">The range is refused, with why (<see cref="JobErrorKind.BadRequest"/>).</exception>
    public long? CheckRange(long? programId, ChunkedProgram program, int? fromLine, int toLine, RunSettings settings, MachineProfile? profile = null, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(program);
        if (SourceLocations.MapOf(program.Folder) is not null)
        {
            // Its lines are expanded lines: a source line of a subprogram or loop runs many times, and a range of
            // expanded lines would cut a call or an iteration wherever it fell.
            throw new JobException("selected-block execution (--to-line) runs lines of one program in order; this program calls subprograms, macros or loops, whose lines run more than once: run it whole, or start from a line with --from-line (--call)", JobErrorKind.BadRequest);
        }

        long? blocks = null;
        try
        {
            if (programId is { } id)
            {
                using var store = ProgramStores.Open(Store);
                blocks = StoredRange.Check(store, id, fromLine, toLine).Blocks;
            }
            else
            {
                CheckFileRange(program, fromLine, toLine, settings, profile, cancellationToken);
            }
        }
        catch (ArgumentException e)
        {
            throw new JobException(e.Message, JobErrorKind.BadRequest, e);
        }

        return ProgramRange.EndOfBlock(program, toLine) is null
            ? throw new JobException($"line {toLine} is not a move the split tracks (no M0=={toLine} in its chunks): end the range on a move", JobErrorKind.BadRequest)
            : blocks;
    }

    /// <summary>A file's range (no stored blocks): B must start a planned move, and neither B's state nor the next block's may compensate the cutter.</summary>
    private void CheckFileRange(ChunkedProgram program, int? fromLine, int toLine, RunSettings settings, MachineProfile? profile, CancellationToken cancellationToken)
    {
        var last = program.Manifest.Chunks.Count > 0 ? program.Manifest.Chunks[^1].LastSourceLine : 0;
        StoredRange.Basic(fromLine, toLine, last);
        var at = PlanStart(program, toLine, settings, profile, cancellationToken);
        if (at.Line != toLine)
        {
            throw new ArgumentException($"line {toLine} is not a move (the controller's line tracking reports moves only): end the range on a move");
        }

        // The state before B and after it: conservative (a G40 move after G41 moves is refused too), as a file is not decoded block by block.
        var states = new List<ModalState> { at.State };
        try
        {
            states.Add(PlanStart(program, toLine + 1, settings, profile, cancellationToken).State);
        }
        catch (JobException)
        {
            // No move after B: nothing moves its end.
        }

        if (states.Any(s => s.RadiusCompensation is { } rc && Math.Floor(rc) is 41 or 42))
        {
            throw new ArgumentException($"line {toLine} is a move under cutter compensation: its end depends on the move after it, so the range cannot stop there; end it where compensation is off");
        }
    }

    /// <summary>The range's own program (<see cref="ProgramRange.Cut"/>) beside the split: <c>FOLDER.lines-A-B</c>.</summary>
    private static ChunkedProgram CutRange(ChunkedProgram program, int? fromLine, int toLine, MachineProfile profile)
    {
        var folder = Path.TrimEndingDirectorySeparator(Path.GetFullPath(program.Folder)) + $".lines-{fromLine ?? 1}-{toLine}";
        var end = profile.Find('M', 30) is not null ? "M30" : profile.Find('M', 2) is not null ? "M02" : null;
        try
        {
            var range = ProgramRange.Cut(program, fromLine, toLine, folder, ProgramRange.EndLines(program.Manifest, end));
            Log.Information("Selected blocks: lines {From}..{To} of {Source:l} as {Chunks} chunks, {Blocks} blocks, in {Folder:l}",
                fromLine ?? 1, toLine, program.Manifest.SourcePath, range.TotalChunks, range.Manifest.TotalMotionBlocks, folder);
            return range;
        }
        catch (ArgumentException e)
        {
            throw new JobException(e.Message, JobErrorKind.BadRequest, e);
        }
    }
}
