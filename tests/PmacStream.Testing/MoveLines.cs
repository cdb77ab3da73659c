using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Testing;

/// <summary>What the executed-move logs of the simulator and the fake controller are compared by.</summary>
public static class MoveLines
{
    /// <summary>
    /// The source line of each block the moves executed, in execution order (<see cref="BlockStarts"/>): a block starts
    /// where the line changes or its synchronous tracking assignment fired again (once a block the host expands had
    /// each of its <paramref name="program"/>'s assignments), its further moves are not counted, and line 0 (a preamble
    /// move, no M0 yet) is left out. A one-move block run twice in a row shows twice.
    /// </summary>
    public static List<int> Blocks(IEnumerable<ExecutedMove> moves, ChunkedProgram? program = null) =>
        Blocks(moves.Select(m => (m.SourceLine, m.BlockStart)), program);

    /// <summary><see cref="Blocks(IEnumerable{ExecutedMove}, ChunkedProgram?)"/> of moves given as their line and block-start mark (the fake controller's).</summary>
    public static List<int> Blocks(IEnumerable<(int SourceLine, bool BlockStart)> moves, ChunkedProgram? program = null) =>
        Blocks(moves, program?.ExpandedBlocks());

    /// <summary>The blocks of <paramref name="moves"/> with the program's expanded blocks read before (<see cref="ChunkedProgram.ExpandedBlocks"/>).</summary>
    public static List<int> Blocks(IEnumerable<ExecutedMove> moves, IReadOnlyDictionary<int, int>? expandedBlocks) =>
        Blocks(moves.Select(m => (m.SourceLine, m.BlockStart)), expandedBlocks);

    /// <summary>The blocks of moves given as their line and block-start mark, with the program's expanded blocks read before.</summary>
    public static List<int> Blocks(IEnumerable<(int SourceLine, bool BlockStart)> moves, IReadOnlyDictionary<int, int>? expandedBlocks) =>
        ExecutedLineCheck.Blocks(moves, expandedBlocks).ToList();
}
