namespace PmacStream.Testing;

/// <summary>What the executed-move logs of the simulator and the fake controller are compared by.</summary>
public static class MoveLines
{
    /// <summary>
    /// The source lines of executed moves in execution order, consecutive repeats folded (one block can be several
    /// moves) and line 0 (a preamble move, no M0 yet) left out: the list a demo counts as "executed N of N".
    /// </summary>
    public static List<int> Fold(IEnumerable<int> sourceLines) => PmacStream.Sim.ExecutedLineCheck.Fold(sourceLines).ToList();
}
