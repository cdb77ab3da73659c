using PmacStream.Sim;

namespace PmacStream.Testing;

/// <summary>What the executed-move logs of the simulator and the fake controller are compared by.</summary>
public static class MoveLines
{
    /// <summary>
    /// The source line of each block the moves executed, in execution order: a block starts at the move its
    /// synchronous tracking assignment fired on (or where the line changes), its further moves are not counted, and
    /// line 0 (a preamble move, no M0 yet) is left out. A one-move block run twice in a row shows twice.
    /// </summary>
    public static List<int> Blocks(IEnumerable<ExecutedMove> moves) => ExecutedLineCheck.Blocks(moves).ToList();

    /// <summary><see cref="Blocks(IEnumerable{ExecutedMove})"/> of moves given as their line and block-start mark (the fake controller's).</summary>
    public static List<int> Blocks(IEnumerable<(int SourceLine, bool BlockStart)> moves) => ExecutedLineCheck.Blocks(moves).ToList();
}
