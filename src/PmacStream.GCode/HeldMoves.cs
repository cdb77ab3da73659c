namespace PmacStream.GCode;

/// <summary>
/// The moves a consumer (the preview, the ETA, the program store, a position proof) holds under G41/G42 until they
/// are final, applying the interpreter's one decision for each block (<see cref="CanonBlock.Hold"/>,
/// <see cref="CanonBlock.AmendedEnd"/>) as rs274ngc applies its queue (<c>move_endpoint_and_flush</c>): the
/// compensated XY move held and the out-of-plane moves queued behind it (a plunge, a retract, a dwell) move to the
/// crossing of an inside corner together, the XY move by its end, the queued ones by both ends. Order is kept: what is
/// final is handed out in the order the blocks came.
/// </summary>
/// <typeparam name="T">What the consumer holds of a move (a segment, a motion, a record's place).</typeparam>
/// <param name="moveTo">
/// A move moved to the crossing: <c>(move, crossing, held)</c>, <c>held</c> true for the XY move (its end moves,
/// <see cref="AmendedMove"/> says what is left of it), false for a move queued behind it (it runs at the crossing:
/// its X and Y at both ends, <see cref="AmendedMove.MovedTo"/>).
/// </param>
public sealed class HeldMoves<T>(Func<T, Point3, bool, T> moveTo)
{
    private readonly List<T> _held = []; // the XY move first, then the moves queued behind it

    /// <summary>How many moves are held (0: everything handed out is final).</summary>
    public int Count => _held.Count;

    /// <summary>
    /// A block's moves (<paramref name="moves"/>, in order; none for a block that did not move) with the block's
    /// decision: adds to <paramref name="final"/> every move that is final now, in order. Call it for every block
    /// taken (a block without moves may let the held ones go).
    /// </summary>
    public void Take(in CanonBlock block, IReadOnlyList<T> moves, List<T> final) => Take(block.Hold, block.AmendedEnd, moves, final);

    /// <summary><see cref="Take(in CanonBlock, IReadOnlyList{T}, List{T})"/> with the block's <see cref="CanonBlock.Hold"/> and <see cref="CanonBlock.AmendedEnd"/>.</summary>
    public void Take(CompensationHold hold, Point3? amendedEnd, IReadOnlyList<T> moves, List<T> final)
    {
        ArgumentNullException.ThrowIfNull(moves);
        ArgumentNullException.ThrowIfNull(final);
        if (amendedEnd is { } crossing)
        {
            for (var i = 0; i < _held.Count; i++)
            {
                _held[i] = moveTo(_held[i], crossing, i == 0);
            }
        }

        if (hold == CompensationHold.Queued && _held.Count > 0)
        {
            _held.AddRange(moves);
            return;
        }

        final.AddRange(_held);
        _held.Clear();
        if (hold == CompensationHold.Held && moves.Count > 0)
        {
            // An outside corner's arc before the move is final at once; the move's end waits for the next XY move.
            for (var i = 0; i < moves.Count - 1; i++)
            {
                final.Add(moves[i]);
            }

            _held.Add(moves[^1]);
        }
        else
        {
            final.AddRange(moves);
        }
    }

    /// <summary>Forgets the moves held (the consumer let them go: an inside corner after this cannot move them).</summary>
    public void Clear() => _held.Clear();

    /// <summary>At the program's end: the moves still held are final as they are.</summary>
    public void Flush(List<T> final)
    {
        final.AddRange(_held);
        _held.Clear();
    }
}
