using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>
/// Selected-block execution of a stored revision (lines A..B): checks the range against the stored blocks before
/// anything is prepared or sent. A and B must each hold a block, B a move the controller's line tracking reports (a
/// block without motion carries no <c>M0==</c>, so nothing could tell when it ran) and not one under cutter
/// compensation (G41/G42: its end is where the next move's corner puts it, so the range cannot stop there).
/// </summary>
public static class StoredRange
{
    /// <summary>What a checked range holds.</summary>
    /// <param name="FromLine">Its first line (A).</param>
    /// <param name="ToLine">Its last line (B).</param>
    /// <param name="Blocks">Its blocks that move or dwell (what the job counts as executed), from the first move at or after A.</param>
    /// <param name="Last">B's block as stored (its end is where the machine stands after the range).</param>
    public sealed record Range(int FromLine, int ToLine, long Blocks, DecodedBlock Last);

    /// <summary>Checks lines <paramref name="fromLine"/>..<paramref name="toLine"/> of revision <paramref name="programId"/> (A null: from the first line).</summary>
    /// <exception cref="ArgumentException">The range is refused; the message says why (for the operator).</exception>
    public static Range Check(IProgramRevisions store, long programId, int? fromLine, int toLine)
    {
        ArgumentNullException.ThrowIfNull(store);
        var info = store.GetProgram(programId) ?? throw new ArgumentException($"no program {programId} in the store");
        Basic(fromLine, toLine, info.Lines);
        var from = fromLine ?? 1;
        if (fromLine is { } a && BlockAt(store, programId, a) is null)
        {
            throw new ArgumentException($"line {a} holds no block (blank, a comment or a line the check dropped): start the range on a block");
        }

        var last = BlockAt(store, programId, toLine)
            ?? throw new ArgumentException($"line {toLine} holds no block (blank, a comment or a line the check dropped): end the range on a move");
        return Checked(store, programId, from, last);
    }

    /// <summary>The checks that need no store: B before A, B below 1, B beyond the program's <paramref name="lines"/> lines.</summary>
    /// <exception cref="ArgumentException">The range is refused.</exception>
    public static void Basic(int? fromLine, int toLine, int lines)
    {
        if (toLine < 1)
        {
            throw new ArgumentException("--to-line must be 1 or more");
        }

        if (fromLine is { } a && toLine < a)
        {
            throw new ArgumentException($"the range ends at line {toLine}, before its first line {a}");
        }

        if (toLine > lines)
        {
            throw new ArgumentException($"line {toLine} is beyond the program (its last line is {lines})");
        }
    }

    /// <summary>A range may not end on a move under cutter compensation: its end is the next move's corner's.</summary>
    /// <exception cref="ArgumentException">B is refused.</exception>
    public static void EnsureCanEndAfter(DecodedBlock last)
    {
        ArgumentNullException.ThrowIfNull(last);
        if (last.Motion == MotionKind.None)
        {
            throw new ArgumentException($"line {last.Line} is not a move (the controller's line tracking reports moves only, so nothing tells when it ran): end the range on a move");
        }

        if (last.Modal.RadiusCompensation is { } rc && Math.Floor(rc) is 41 or 42)
        {
            throw new ArgumentException(
                $"line {last.Line} is a move under cutter compensation (G{rc:0.#}): its end depends on the move after it, so the range cannot stop there; end it where compensation is off (after the G40 move)");
        }
    }

    private static Range Checked(IProgramRevisions store, long programId, int from, DecodedBlock last)
    {
        EnsureCanEndAfter(last);
        long blocks = 0;
        foreach (var b in store.ReadStoredBlocks(programId, from, last.Line))
        {
            blocks += b.Block.Motion != MotionKind.None ? 1 : 0;
        }

        if (blocks == 0)
        {
            throw new ArgumentException($"lines {from}..{last.Line} hold no move");
        }

        return new Range(from, last.Line, blocks, last);
    }

    private static DecodedBlock? BlockAt(IProgramRevisions store, long programId, int line) =>
        store.GetBlockAtOrAfterLine(programId, line) is { } b && b.Line == line ? b : null;
}
