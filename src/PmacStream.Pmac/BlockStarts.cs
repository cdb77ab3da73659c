namespace PmacStream.Pmac;

/// <summary>
/// Tells, move by move in execution order, which executed move starts a block. A block starts where the tracked line
/// changes, or at a move its synchronous tracking assignment fired on (the executed move's block-start mark) once the
/// block has had all its assignments: a block the host expands into several controller lines (a canned cycle, a
/// reference return) carries one on each, so it may fire that many times (<c>expandedBlocks</c>: line, assignments;
/// every other block has one). So a one-move block run twice in a row starts two blocks, and a block's further moves
/// start none. Line 0 (a preamble move, before any assignment) neither starts nor ends a block.
/// </summary>
/// <param name="expandedBlocks">The blocks with more than one assignment, by source line; null: none.</param>
public sealed class BlockStarts(IReadOnlyDictionary<int, int>? expandedBlocks = null)
{
    private int _line;
    private int _fired;

    /// <summary>Takes the next executed move: true when it starts a block.</summary>
    public bool Next(int sourceLine, bool assignmentFired)
    {
        if (sourceLine <= 0)
        {
            return false;
        }

        if (sourceLine != _line)
        {
            _line = sourceLine;
            _fired = assignmentFired ? 1 : 0;
            return true;
        }

        if (!assignmentFired || ++_fired <= (expandedBlocks?.GetValueOrDefault(sourceLine, 1) ?? 1))
        {
            return false;
        }

        _fired = 1;
        return true;
    }
}
