namespace PmacStream.GCode;

/// <summary>The interpreter's arcs that run although their end is off the circle (W008).</summary>
public sealed partial class Interpreter
{
    // The most decimals the program has written in the position and centre words of arcs off their circle so far: its last decimal.
    private int _arcDecimals;

    /// <summary>
    /// W008 for a centre-format arc inside the arc tolerance whose <paramref name="radii"/> (program units) differ
    /// by more than rounding start, end and centre to the program's last decimal can explain. Only arcs that are off
    /// by more than a micrometre get here (below it the controller does not tell the spiral from the circle), and
    /// only while checking: the decimals are counted in this block's own words.
    /// </summary>
    private void WarnOffCircle((double Start, double End) radii, GBlock block, ReadOnlySpan<GWord> words, List<Diagnostic> diags, int line, int column)
    {
        foreach (ref readonly var w in words)
        {
            if (w.Letter is 'X' or 'Y' or 'Z' or 'I' or 'J' or 'K')
            {
                var text = block.NumberText(w);
                var point = text.IndexOf((byte)'.');
                if (point >= 0 && text.Length - point - 1 > _arcDecimals)
                {
                    _arcDecimals = text.Length - point - 1;
                }
            }
        }

        // Never under a micrometre: programs written to six decimals are not warned for their last digits.
        var off = Math.Abs(radii.Start - radii.End);
        var bound = Math.Max(ArcTolerance.RoundingBound(_arcDecimals), 0.001 / _scale);
        if (off > bound)
        {
            var units = _scale != 1.0 ? "in" : "mm";
            Add(diags, DiagnosticCodes.ArcRoundedOffCircle, line, column, ArcGeometry.Length(off, units), ArcGeometry.Length(radii.Start, units),
                ArcGeometry.Length(radii.End, units), ArcGeometry.Length(bound, units));
        }
    }
}
