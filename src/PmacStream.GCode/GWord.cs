namespace PmacStream.GCode;

/// <summary>
/// One address word of a block (<c>X-2.5</c>): its letter (upper case), value and where its text lies in the line.
/// A value type so that reading a program allocates nothing per word.
/// </summary>
/// <param name="Letter">Upper-case address letter.</param>
/// <param name="Value">Numeric value.</param>
/// <param name="Column">1-based column of the letter.</param>
/// <param name="NumberStart">0-based offset of the number's text in <see cref="GBlock.Line"/>.</param>
/// <param name="NumberLength">Length of the number's text.</param>
/// <param name="WasLowercase">True when the letter was written in lower case.</param>
public readonly record struct GWord(char Letter, double Value, int Column, int NumberStart, int NumberLength, bool WasLowercase)
{
    /// <summary>True when the value is a whole number (G1, M30), as G/M/T/N codes must be unless the profile knows decimals.</summary>
    public bool IsInteger => Value == Math.Floor(Value);

    /// <summary>The code number scaled by 10 to an integer (G1 -> 10, G64.1 -> 641): how profiles key G/M codes.</summary>
    public int CodeTimesTen => (int)Math.Round(Value * 10.0);
}
