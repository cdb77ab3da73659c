using System.Runtime.CompilerServices;
using System.Runtime.InteropServices;

namespace PmacStream.GCode;

/// <summary>
/// The lexer's fast lane for the commonest CAM block: an optional leading N number, at most one G0/G1 and X/Y/Z
/// words (<c>N22 X3.5 Y0 Z-1.5623</c>, <c>G1X2.249Y0.1258</c>). <see cref="TryParse"/> gives the values the full
/// lexer (<see cref="GCodeReader"/>) would give, bit for bit, and the block's text as the splitter writes it: the
/// words without N, one space apart. Anything else (comments, other letters, <c>+</c> signs, blanks inside a word,
/// lower case, more than 15 digits, a repeated letter) is a "no", and the line takes the full path; so the lane
/// changes speed, never results.
/// </summary>
internal struct AxisLine
{
    /// <summary>Bit of <see cref="Axes"/> for X; Y and Z follow.</summary>
    public const int XBit = 1;

    /// <summary>The line has an N word (at its start).</summary>
    public bool HasN;

    /// <summary>The N number.</summary>
    public double N;

    /// <summary>The line has a G word (G0 or G1).</summary>
    public bool HasG;

    /// <summary>Its value: 0 or 1.</summary>
    public double G;

    /// <summary>Which axes the line sets: bit 0 X, bit 1 Y, bit 2 Z. Never 0 for a parsed line.</summary>
    public int Axes;

    /// <summary>Axis values as written (work coordinates).</summary>
    public double X;

    /// <summary>Axis values as written (work coordinates).</summary>
    public double Y;

    /// <summary>Axis values as written (work coordinates).</summary>
    public double Z;

    /// <summary>Words written to the text (every word but N).</summary>
    public int Words;

    /// <summary>Bytes written to the text.</summary>
    public int TextLength;

    /// <summary>Room <see cref="TryParse"/> needs in its text array for a line of <paramref name="lineLength"/> bytes.</summary>
    public static int TextRoom(int lineLength) => (2 * lineLength) + 16;

    /// <summary>
    /// Lexes the line of <paramref name="length"/> bytes at <paramref name="start"/> of <paramref name="data"/> when
    /// it has the lane's shape, writing its text at <paramref name="textStart"/> of <paramref name="text"/>.
    /// The line must be followed by a line end (CR, LF) or a 0 and 16 more bytes, and the text must have
    /// <see cref="TextRoom"/> bytes (8-byte stores may write past the text's end); otherwise the answer is no.
    /// </summary>
    // Hot loop of a billion-byte program: the terminator ends every scan, so no byte is read with a bounds check.
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveOptimization)]
    public static bool TryParse(byte[] data, int start, int length, byte[] text, int textStart, out AxisLine result)
    {
        result = default;
        var end = start + length;
        if ((uint)start > (uint)data.Length || length < 0 || data.Length - start - 1 - 16 < length ||
            data[end] is not ((byte)'\n' or (byte)'\r' or 0) ||
            (uint)textStart > (uint)text.Length || text.Length - textStart < TextRoom(length))
        {
            return false;
        }

        ref var p = ref MemoryMarshal.GetArrayDataReference(data);
        ref var t = ref Unsafe.Add(ref MemoryMarshal.GetArrayDataReference(text), textStart);
        var i = start;
        var o = 0;
        while (true)
        {
            byte c;
            while ((c = Unsafe.Add(ref p, i)) == (byte)' ' || c == (byte)'\t')
            {
                i++;
            }

            if (i >= end)
            {
                break;
            }

            var numberStart = ++i;
            var negative = false;
            if (Unsafe.Add(ref p, i) == (byte)'-')
            {
                negative = true;
                i++;
            }

            // Integer digits, then fraction digits, as one integer mantissa scaled once by a power of ten: the
            // lexer's own conversion, so the values are the same doubles.
            var digitStart = i;
            long mantissa = 0;
            uint digit;
            while ((digit = (uint)(Unsafe.Add(ref p, i) - (byte)'0')) <= 9)
            {
                mantissa = (mantissa * 10) + digit;
                i++;
            }

            var integerDigits = i - digitStart;
            var scale = 0;
            if (Unsafe.Add(ref p, i) == (byte)'.')
            {
                var fractionStart = ++i;
                while ((digit = (uint)(Unsafe.Add(ref p, i) - (byte)'0')) <= 9)
                {
                    mantissa = (mantissa * 10) + digit;
                    i++;
                }

                scale = i - fractionStart;
            }

            // No digit, a second point, more digits than a double holds exactly: the full lexer decides.
            var digits = integerDigits + scale;
            if (digits == 0 || digits > 15 || Unsafe.Add(ref p, i) == (byte)'.')
            {
                return false;
            }

            double value = scale == 0 ? mantissa : mantissa / Pow10[scale];
            if (negative)
            {
                value = -value;
            }

            switch (c)
            {
                case (byte)'N':
                    // Only as the first word, a plain integer.
                    if (result.HasN || result.Words > 0 || negative || i - digitStart != digits)
                    {
                        return false;
                    }

                    result.HasN = true;
                    result.N = value;
                    continue;
                case (byte)'G':
                    // G0/G1 only (G00, G01): whether it is the mode in force is the interpreter's question.
                    if (result.HasG || negative || i - digitStart != digits || mantissa > 1)
                    {
                        return false;
                    }

                    result.HasG = true;
                    result.G = value;
                    break;
                case (byte)'X':
                    if ((result.Axes & XBit) != 0)
                    {
                        return false;
                    }

                    result.Axes |= XBit;
                    result.X = value;
                    break;
                case (byte)'Y':
                    if ((result.Axes & (XBit << 1)) != 0)
                    {
                        return false;
                    }

                    result.Axes |= XBit << 1;
                    result.Y = value;
                    break;
                case (byte)'Z':
                    if ((result.Axes & (XBit << 2)) != 0)
                    {
                        return false;
                    }

                    result.Axes |= XBit << 2;
                    result.Z = value;
                    break;
                default:
                    return false;
            }

            if (result.Words > 0)
            {
                Unsafe.Add(ref t, o++) = (byte)' ';
            }

            Unsafe.Add(ref t, o++) = c;
            // Two 8-byte loads and stores whatever the size (a third for a sign, 15 digits and a point): the bytes past
            // the number are overwritten next, or are slack.
            var size = i - numberStart;
            ref var from = ref Unsafe.Add(ref p, numberStart);
            ref var to = ref Unsafe.Add(ref t, o);
            Unsafe.WriteUnaligned(ref to, Unsafe.ReadUnaligned<ulong>(ref from));
            Unsafe.WriteUnaligned(ref Unsafe.Add(ref to, 8), Unsafe.ReadUnaligned<ulong>(ref Unsafe.Add(ref from, 8)));
            if (size > 16)
            {
                Unsafe.WriteUnaligned(ref Unsafe.Add(ref to, 16), Unsafe.ReadUnaligned<ulong>(ref Unsafe.Add(ref from, 16)));
            }

            o += size;
            result.Words++;
        }

        result.TextLength = o;
        return result.Axes != 0;
    }

    private static readonly double[] Pow10 = [1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];
}
