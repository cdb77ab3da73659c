using System.Globalization;

namespace PmacStream.Streaming;

/// <summary>What the controller says about a job when a host resumes it.</summary>
/// <param name="TrackedLine">The tracking variable (M0): the source line of the block executing.</param>
/// <param name="Running">The program-running bit of the coordinate system; null when the status was not understood.</param>
/// <param name="LinesAhead"><c>PR</c>: program lines in the rotary buffer not yet calculated.</param>
/// <param name="ProbeValue">The line probe (P501): the last line calculated that carried it; null without a probe.</param>
public readonly record struct ControllerReading(int TrackedLine, bool? Running, int LinesAhead, long? ProbeValue);

/// <summary>How a resume goes on once the record and the controller are reconciled.</summary>
internal enum ResumeAction
{
    /// <summary>The controller holds exactly what the record says was sent: sending continues at the record's position.</summary>
    Continue,

    /// <summary>
    /// Where the controller's lines end is not known from the record (a send was under way, or the controller holds more
    /// than the record says was sent): wait for the rotary buffer to drain, then go on after the last line it got.
    /// </summary>
    Drain,
}

/// <summary>The reconciled resume: what to do and, when the controller was ahead of the record, how.</summary>
internal readonly record struct ResumeDecision(ResumeAction Action, string? ControllerAhead);

/// <summary>
/// The controller is the truth on resume. A job record can lag the controller (a checkpoint lost with the power, a
/// reply lost after the controller stored the lines) or be wrong (rewound, advanced, damaged); resuming from it would
/// then send lines the controller already holds, or skip lines it never got. This reads the record against what the
/// controller reports (M0, program running, <c>PR</c>, the line probe) and decides: continue at the record's position
/// when they agree; drain and continue after the controller's last line when the controller holds more than the record
/// says (or a send was under way); restart at the controller's line when it stopped; refuse, with both positions and
/// the operator's choices, when they disagree in a way that cannot be resolved without risking a repeat or a skip.
/// </summary>
internal static class ResumeReconciliation
{
    /// <summary>
    /// Decides how the job of <paramref name="record"/> resumes on a controller that reported <paramref name="seen"/>.
    /// Throws <see cref="ResumeRefusedException"/> for a disagreement that cannot be resolved safely, and
    /// <see cref="ControllerLostJobException"/> when the controller stopped the job where the record allows a restart.
    /// </summary>
    public static ResumeDecision Decide(ChunkedProgram program, Checkpoint record, ControllerReading seen, int bufferWords)
    {
        ArgumentNullException.ThrowIfNull(program);
        ArgumentNullException.ThrowIfNull(record);
        var m = seen.TrackedLine;
        var l = record.LastExecutedLine;
        if (Contradiction(program, record, bufferWords) is { } damaged)
        {
            throw Refuse(program, record, seen, $"the job record contradicts itself ({damaged})", restartLine: null);
        }

        if (m < 0 || m > program.FinalTrackedLine || (m > 0 && program.PositionAfterBlock(m) is null))
        {
            throw Refuse(program, record, seen, $"{program.Sync.Variable}={m} is not a block of this program: the controller runs something else", restartLine: null);
        }

        if (record.Started && seen.Running == false && !AtProgramStop(program, record, seen))
        {
            if (m > 0 && m < l)
            {
                throw Refuse(program, record, seen, $"the controller stopped at line {m}, before line {l} that the record says had already executed", restartLine: m);
            }

            var from = m > 0 ? $"line {m}" : l > 0 ? $"line {l} (the record's: the controller names none)" : "the job's start";
            throw new ControllerLostJobException(
                $"the controller is not running the job (aborted, stopped or reset) at {program.Sync.Variable}={m}: restart from {from} with a preamble",
                m > 0 ? m : null);
        }

        if (m < l)
        {
            throw Refuse(program, record, seen, $"the controller executes line {m}, before line {l} that the record says had already executed", restartLine: null);
        }

        var ahead = Ahead(program, record, seen);
        return ahead is not null || !record.NextExact ? new ResumeDecision(ResumeAction.Drain, ahead) : new ResumeDecision(ResumeAction.Continue, null);
    }

    /// <summary>
    /// True when the controller stands at a program stop of this job (M00, an M01 honoured, a tool change): the record
    /// says so and M0 still names that block, or M0 (with paper placement, the line probe) names a stop block at or
    /// after the record's line (the program reached it after the host went away). It waits for the run command there;
    /// the job is not lost.
    /// </summary>
    internal static bool AtProgramStop(ChunkedProgram program, Checkpoint record, ControllerReading seen) =>
        JobRecovery.StillAtStop(record, seen.TrackedLine)
        || (seen.TrackedLine >= record.LastExecutedLine && program.StopAt(seen.TrackedLine, seen.ProbeValue).Code is not null);

    /// <summary>
    /// Why the controller holds lines the record says were never sent, or null: M0 past the last move sent, the line
    /// probe past the record's position, or more lines ahead (<c>PR</c>) than the record left between M0 and its
    /// position. While M0 is 0 the buffer may still hold a start's preamble, whose lines are not program positions, so
    /// <c>PR</c> is not compared then.
    /// </summary>
    internal static string? Ahead(ChunkedProgram program, Checkpoint record, ControllerReading seen)
    {
        var next = program.Normalize(record.Next);
        var m = seen.TrackedLine;
        var lastSent = program.LastTrackedBefore(next);
        if (m > lastSent)
        {
            return $"it executes line {m}, which the record says was never sent (sending had reached {next}, after line {lastSent})";
        }

        if (seen.ProbeValue is { } probe && program.PositionAfterProbe(probe) is { } afterProbe && BufferDrain.Compare(afterProbe, next) > 0)
        {
            return string.Create(CultureInfo.InvariantCulture, $"its line probe {program.LineProbeVariable}={probe} names a line after {next}, where the record says sending stopped");
        }

        if (m > 0 && program.PositionAfterBlock(m) is { } afterM)
        {
            var between = LinesBetween(program, afterM, next, seen.LinesAhead);
            if (seen.LinesAhead > between)
            {
                return $"it holds {seen.LinesAhead} lines ahead (PR), but the record says only {between} were sent after line {m}";
            }
        }

        return null;
    }

    /// <summary>
    /// What makes a record impossible on its own, or null: a last executed line past what an exact position says was
    /// sent, a current chunk that is not the chunk of that line, or an exact position more than twice the rotary
    /// buffer's words ahead of that line (the host never has more than one buffer in flight).
    /// </summary>
    internal static string? Contradiction(ChunkedProgram program, Checkpoint record, int bufferWords)
    {
        var next = program.Normalize(record.Next);
        var l = record.LastExecutedLine;
        if (l <= 0)
        {
            return null;
        }

        if (record.NextExact && l > program.LastTrackedBefore(next))
        {
            return $"line {l} executed, but sending had only reached {next}, before that line";
        }

        if (record.CurrentChunk != program.ChunkOfTracked(l))
        {
            return $"its current chunk {record.CurrentChunk} is not chunk {program.ChunkOfTracked(l)} of its last executed line {l}";
        }

        if (record.NextExact && program.PositionAfterBlock(l) is { } afterL)
        {
            var limit = 2L * bufferWords;
            if (WordsBetween(program, afterL, next, limit) > limit)
            {
                return $"sending had reached {next}, more than twice the rotary buffer's {bufferWords} words after line {l}";
            }
        }

        return null;
    }

    /// <summary>Program lines from <paramref name="from"/> up to, not including, <paramref name="to"/>; stops counting past <paramref name="limit"/>.</summary>
    internal static int LinesBetween(ChunkedProgram program, StreamPosition from, StreamPosition to, int limit)
    {
        var n = 0;
        for (var p = program.Normalize(from); n <= limit && BufferDrain.Compare(p, to) < 0 && p.Chunk <= program.TotalChunks; p = program.Normalize(new StreamPosition(p.Chunk, p.Line + 1)))
        {
            n++;
        }

        return n;
    }

    /// <summary>Estimated words of the lines from <paramref name="from"/> up to <paramref name="to"/>; stops counting past <paramref name="limit"/>.</summary>
    private static long WordsBetween(ChunkedProgram program, StreamPosition from, StreamPosition to, long limit)
    {
        long words = 0;
        for (var p = program.Normalize(from); words <= limit && BufferDrain.Compare(p, to) < 0 && p.Chunk <= program.TotalChunks; p = program.Normalize(new StreamPosition(p.Chunk, p.Line + 1)))
        {
            words += program.Body(p.Chunk)[p.Line].Words;
        }

        return words;
    }

    private static ResumeRefusedException Refuse(ChunkedProgram program, Checkpoint record, ControllerReading seen, string disagreement, int? restartLine)
    {
        var running = seen.Running switch { true => "running", false => "not running", null => "running state unknown" };
        var controller = string.Create(CultureInfo.InvariantCulture,
            $"{program.Sync.Variable}={seen.TrackedLine}, {running}, {seen.LinesAhead} lines ahead in its rotary buffer (PR){(seen.ProbeValue is { } p ? $", {program.LineProbeVariable}={p}" : string.Empty)}");
        var job = $"line {record.LastExecutedLine} executed, sending had reached {record.Next}{(record.NextExact ? string.Empty : " (a send was under way)")}";
        var choices = restartLine is { } line
            ? $"check where the machine is, then start the program again from line {line}, where the controller stopped, with the preamble (start from a line)"
            : "let the controller run the lines it holds (it waits when they run out; abort it with &1 A to stop it now), check where the machine stopped, "
              + "then start the program again from that line with the preamble (start from a line)";
        return new ResumeRefusedException(
            $"{disagreement}. The controller: {controller}. The job record: {job}. Resuming from either could run a block twice or skip one, so nothing was sent. Choices: {choices}.",
            seen, record, restartLine);
    }
}
