namespace PmacStream.Sim;

/// <summary>
/// The axis transformation matrices <c>DEFINE TBUF n</c> reserves (global on a Turbo PMAC); a coordinate system
/// selects one with <c>TSEL</c>. Each holds a displacement of X, Y, Z: a programmed position p is reached at the
/// base (machine) position p + displacement. <c>ADIS</c>/<c>IDIS</c> set or add to it and only rename the current
/// position: nothing moves. The rotation and scaling part (<c>AROT</c>, <c>IROT</c>) is not simulated: those
/// statements stop the program with an error, so nothing relies on them silently.
/// </summary>
internal sealed class AxisMatrices
{
    private double[][] _displacements = [];

    /// <summary>How many matrices are reserved.</summary>
    public int Count => _displacements.Length;

    /// <summary><c>DEFINE TBUF n</c>: n matrices, each the identity (no displacement).</summary>
    public void Define(int count)
    {
        // The matrices kept are reset in place: a coordinate system that selected one (TSEL) holds its array.
        var kept = Math.Min(count, _displacements.Length);
        var next = new double[count][];
        for (var i = 0; i < count; i++)
        {
            next[i] = i < kept ? _displacements[i] : new double[3];
            Array.Clear(next[i]);
        }

        _displacements = next;
    }

    /// <summary>The displacement of matrix <paramref name="number"/> (1-based); a number TBUF did not reserve is a run-time error.</summary>
    public double[] Displacement(int number) =>
        number >= 1 && number <= _displacements.Length ? _displacements[number - 1] : throw new SimRuntimeException(3);
}
