namespace PmacStream.Streaming;

/// <summary>
/// The rotary-buffer words a program line takes as the controller counts them, from above: about one word per value
/// (pmac-facts.md), and a statement with its own value (an assignment <c>M0==12</c>, a feed <c>F100</c>, <c>DWELL0</c>,
/// <c>TA10</c>) one word more than its values; an axis or a G/M/T/D code word one. The splitter's estimate counts a
/// value a word and so runs low (the bench block <c>M0==n G01 X.. Y.. F(P500)</c>: 5 against 7), which a strategy
/// that learns the real size from <c>ERR006</c> can afford with one request in flight; with several packets in flight a
/// refused line would leave the next packets' lines behind a gap, so the credit must never run low.
/// </summary>
public static class ControllerWords
{
    private const string SingleWordLetters = "XYZABCUVWIJKRGMTDN";

    /// <summary>Words <paramref name="line"/> takes in the rotary buffer by this count (at least 1).</summary>
    public static int Of(string line)
    {
        ArgumentNullException.ThrowIfNull(line);
        var words = 0;
        var depth = 0;
        var i = 0;
        while (i < line.Length)
        {
            var c = line[i];
            if (c == ';')
            {
                break;
            }

            if (char.IsAsciiLetter(c))
            {
                words += Statement(line, ref i, depth);
                continue;
            }

            if (depth > 0 && (char.IsAsciiDigit(c) || c == '.'))
            {
                // A constant inside an expression is an operand of its own.
                SkipNumber(line, ref i);
                words++;
                continue;
            }

            depth += c == '(' ? 1 : c == ')' && depth > 0 ? -1 : 0;
            i++;
        }

        return Math.Max(1, words);
    }

    /// <summary>Reads one letter word at <paramref name="i"/> (letters, index or value, an assignment sign) and returns its words.</summary>
    private static int Statement(string line, ref int i, int depth)
    {
        var start = i;
        while (i < line.Length && char.IsAsciiLetter(line[i]))
        {
            i++;
        }

        var letters = i - start;
        var single = letters == 1 && SingleWordLetters.Contains(char.ToUpperInvariant(line[start]), StringComparison.Ordinal);
        SkipSpaces(line, ref i);
        var hasNumber = i < line.Length && (char.IsAsciiDigit(line[i]) || line[i] is '.' or '-' or '+');
        SkipNumber(line, ref i);
        SkipSpaces(line, ref i);
        var assignment = i < line.Length && line[i] == '=';
        while (i < line.Length && line[i] == '=')
        {
            i++;
        }

        if (depth > 0)
        {
            return 1; // an operand: P500 in F(P500)
        }

        if (assignment)
        {
            // The statement and its first value; further operands of an expression count on their own.
            SkipSpaces(line, ref i);
            SkipNumber(line, ref i);
            return 2;
        }

        if (single)
        {
            return 1;
        }

        // A keyword: with a constant value (F100, DWELL0, TA10) two words; with an expression (F(P500)) one plus its
        // operands, counted inside the parentheses; bare (LINEAR, ABS) one.
        return hasNumber ? 2 : 1;
    }

    private static void SkipSpaces(string line, ref int i)
    {
        while (i < line.Length && line[i] == ' ')
        {
            i++;
        }
    }

    private static void SkipNumber(string line, ref int i)
    {
        if (i < line.Length && line[i] is '-' or '+')
        {
            i++;
        }

        while (i < line.Length && (char.IsAsciiDigit(line[i]) || line[i] == '.'))
        {
            i++;
        }
    }
}
