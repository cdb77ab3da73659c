using PmacStream.GCode;
using PmacStream.Sim;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The position proofs' comparison: the simulated controller's executed moves grouped by the source line they carry
/// (a line's last move is where its block ended), held against the interpreter's block ends. Every moving block once,
/// in order, each ending within the tolerance.
/// </summary>
internal static class BlockEndProof
{
    /// <summary>
    /// Asserts the comparison and returns the largest difference (millimetres); <paramref name="blocks"/> names what is
    /// compared in the order message, <paramref name="where"/> a block's place in the per-block message.
    /// </summary>
    public static double Check(IEnumerable<ExecutedMove> executed, IReadOnlyList<(int Line, Point3 End)> expected, double tolerance, string name,
        string blocks, Func<int, string> where)
    {
        var groups = new List<(int Line, ExecutedMove Last)>();
        foreach (var m in executed)
        {
            if (groups.Count > 0 && groups[^1].Line == m.SourceLine)
            {
                groups[^1] = (m.SourceLine, m);
            }
            else
            {
                groups.Add((m.SourceLine, m));
            }
        }

        groups.Select(g => g.Line).Should().Equal(expected.Select(e => e.Line), $"{name}: every {blocks} once, in order");
        var largest = 0.0;
        for (var i = 0; i < expected.Count; i++)
        {
            var (line, end) = expected[i];
            var got = groups[i].Last;
            var d = Math.Max(Math.Abs(got.X - end.X), Math.Max(Math.Abs(got.Y - end.Y), Math.Abs(got.Z - end.Z)));
            largest = Math.Max(largest, d);
            d.Should().BeLessThan(tolerance, $"{where(line)}: the controller ended at ({got.X}, {got.Y}, {got.Z}), the interpreter says ({end.X}, {end.Y}, {end.Z})");
        }

        return largest;
    }
}
