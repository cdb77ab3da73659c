using System.Runtime.CompilerServices;
using System.Runtime.InteropServices;

namespace PmacStream.GCode;

/// <summary>
/// The lexer's fast lane for the commonest CAM block: an optional leading N number, at most one G0/G1 and X/Y/Z
/// words (<c>N22 X3.5 Y0 Z-1.5623</c>, <c>G1X2.249Y0.1258</c>). <see cref="TryParse"/> checks that the full lexer
/// (<see cref="GCodeReader"/>) would read the line without a finding, and writes the block's text as the splitter
/// emits it: the words without N, one space apart. The axis values stay text until someone reads the position
/// (<see cref="Value"/> converts them as the lexer does, bit for bit). Anything else (comments, other letters,
/// <c>+</c> signs, blanks inside a word, lower case, more than 15 digits, a repeated letter) is a "no", and the line
/// takes the full path; so the lane changes speed, never results.
/// </summary>
public struct AxisLine
{
    /// <summary>Bit of <see cref="Axes"/> for X; Y and Z follow.</summary>
    public const int XBit = 1;

    /// <summary>The line has an N word (at its start).</summary>
    public bool HasN;

    /// <summary>The line has a G word (G0 or G1).</summary>
    public bool HasG;

    /// <summary>Its value: 0 or 1.</summary>
    public double G;

    /// <summary>Which axes the line sets: bit 0 X, bit 1 Y, bit 2 Z. Never 0 for a parsed line.</summary>
    public int Axes;

    /// <summary>Where each axis's number text starts in the text (from its start), X, Y, Z.</summary>
    public AxisTriple At;

    /// <summary>How long each axis's number text is, X, Y, Z.</summary>
    public AxisTriple Size;

    /// <summary>Words written to the text (every word but N).</summary>
    public int Words;

    /// <summary>Bytes written to the text.</summary>
    public int TextLength;

    /// <summary>Room <see cref="TryParse"/> needs in its text array for a line of <paramref name="lineLength"/> bytes.</summary>
    public static int TextRoom(int lineLength) => (2 * lineLength) + 32;

    /// <summary>
    /// Lexes the line of <paramref name="length"/> bytes at <paramref name="start"/> of <paramref name="data"/> when
    /// it has the lane's shape, writing its text at <paramref name="textStart"/> of <paramref name="text"/>.
    /// The line must be followed by its line end (CR or LF) and 16 more bytes, and the text must have
    /// <see cref="TextRoom"/> bytes (8-byte stores may write past the text's end); otherwise the answer is no.
    /// </summary>
    public static bool TryParse(byte[] data, int start, int length, byte[] text, int textStart, out AxisLine result)
    {
        if ((uint)start > (uint)data.Length || length < 0 || data.Length - start - 1 - 16 < length ||
            data[start + length] is not ((byte)'\n' or (byte)'\r') ||
            (uint)textStart > (uint)text.Length || text.Length - textStart < TextRoom(length))
        {
            result = default;
            return false;
        }

        return Scan(data, start, text, textStart, out result) == length;
    }

    /// <summary>
    /// <see cref="TryParse"/> for the next line of a read buffer, whose end the scan finds itself: the line starts
    /// at <paramref name="start"/>, the buffer's data end at <paramref name="end"/> with a 0 there and 16 more bytes.
    /// Returns the line's length (its CR or LF follows), or -1 when it is not lane-shaped, not whole in the buffer,
    /// or its text would not fit <paramref name="text"/> from <paramref name="textStart"/>.
    /// </summary>
    public static int TryParseNext(byte[] data, int start, int end, byte[] text, int textStart, out AxisLine result)
    {
        if ((uint)start > (uint)end || end > data.Length - 1 - 16 || data[end] != 0 || (uint)textStart > (uint)text.Length)
        {
            result = default;
            return -1;
        }

        return Scan(data, start, text, textStart, out result);
    }

    /// <summary>
    /// One pass over the line's bytes up to its CR or LF; returns the line's length, or -1. A 0 (the end of the data)
    /// or any byte the lane does not take stops it, so no byte is read with a bounds check, and the text is checked
    /// for room before each word. (Classifying 16 bytes at a time into bit masks first was measured slower: 36.6
    /// against 28.2 ns a line.)
    /// </summary>
    // Hot loop of a billion-byte program.
    [MethodImpl(MethodImplOptions.AggressiveOptimization)]
    private static int Scan(byte[] data, int start, byte[] text, int textStart, out AxisLine result)
    {
        result = default;
        var room = text.Length - textStart - 32;
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

            if (c is (byte)'\n' or (byte)'\r')
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

            var digitStart = i;
            while ((uint)(Unsafe.Add(ref p, i) - (byte)'0') <= 9)
            {
                i++;
            }

            var digits = i - digitStart;
            var point = false;
            if (Unsafe.Add(ref p, i) == (byte)'.')
            {
                point = true;
                var fractionStart = ++i;
                while ((uint)(Unsafe.Add(ref p, i) - (byte)'0') <= 9)
                {
                    i++;
                }

                digits += i - fractionStart;
            }

            // No digit, a second point, more digits than a double holds exactly: the full lexer decides.
            if (digits == 0 || digits > 15 || Unsafe.Add(ref p, i) == (byte)'.' || o > room)
            {
                return -1;
            }

            if (!Word(ref result, c, ref Unsafe.Add(ref p, numberStart), i - numberStart, negative || point, o))
            {
                return -1;
            }

            if (c != (byte)'N')
            {
                o = Write(ref t, o, c, ref Unsafe.Add(ref p, numberStart), i - numberStart, result.Words++ > 0);
            }
        }

        result.TextLength = o;
        return result.Axes != 0 ? i - start : -1;
    }

    /// <summary>
    /// The value of a number's text, as the lexer computes it: digits and fraction digits as one integer mantissa
    /// scaled once by a power of ten (exact for at most 15 digits, so the one division is correctly rounded).
    /// </summary>
    public static double Value(ReadOnlySpan<byte> number)
    {
        var i = 0;
        var negative = number.Length > 0 && number[0] == (byte)'-';
        if (negative)
        {
            i++;
        }

        long mantissa = 0;
        var scale = -1;
        for (; i < number.Length; i++)
        {
            var c = number[i];
            if (c == (byte)'.')
            {
                scale = 0;
                continue;
            }

            mantissa = (mantissa * 10) + (c - (byte)'0');
            if (scale >= 0)
            {
                scale++;
            }
        }

        double value = scale <= 0 ? mantissa : mantissa / Pow10[scale];
        return negative ? -value : value;
    }

    /// <summary>Takes one word whose number (checked: digits, at most one point, a sign only first) is at <paramref name="number"/>.</summary>
    [MethodImpl(MethodImplOptions.AggressiveInlining)]
    private static bool Word(ref AxisLine result, byte letter, ref byte number, int size, bool signOrPoint, int textAt)
    {
        switch (letter)
        {
            case (byte)'N':
                // Only as the first word, a plain integer.
                if (result.HasN || result.Words > 0 || signOrPoint)
                {
                    return false;
                }

                result.HasN = true;
                return true;
            case (byte)'G':
                // G0/G1 only (G00, G01): whether it is the mode in force is the interpreter's question.
                if (result.HasG || signOrPoint)
                {
                    return false;
                }

                for (var i = 0; i < size - 1; i++)
                {
                    if (Unsafe.Add(ref number, i) != (byte)'0')
                    {
                        return false;
                    }
                }

                var last = Unsafe.Add(ref number, size - 1);
                if (last > (byte)'1')
                {
                    return false;
                }

                result.HasG = true;
                result.G = last - (byte)'0';
                return true;
            case (byte)'X':
            case (byte)'Y':
            case (byte)'Z':
                var axis = letter - (byte)'X';
                var bit = XBit << axis;
                if ((result.Axes & bit) != 0)
                {
                    return false;
                }

                result.Axes |= bit;
                // The number follows its letter in the text (and, after the first word, a space).
                result.At[axis] = textAt + (result.Words > 0 ? 2 : 1);
                result.Size[axis] = size;
                return true;
            default:
                return false;
        }
    }

    /// <summary>Writes " " (unless first), the letter and the number; returns the new text length.</summary>
    [MethodImpl(MethodImplOptions.AggressiveInlining)]
    private static int Write(ref byte t, int o, byte letter, ref byte number, int size, bool space)
    {
        if (space)
        {
            Unsafe.Add(ref t, o++) = (byte)' ';
        }

        Unsafe.Add(ref t, o++) = letter;
        // Two 8-byte loads and stores whatever the size (a third for the longest): the bytes past the number are
        // overwritten next, or are slack.
        ref var to = ref Unsafe.Add(ref t, o);
        Unsafe.WriteUnaligned(ref to, Unsafe.ReadUnaligned<ulong>(ref number));
        Unsafe.WriteUnaligned(ref Unsafe.Add(ref to, 8), Unsafe.ReadUnaligned<ulong>(ref Unsafe.Add(ref number, 8)));
        if (size > 16)
        {
            Unsafe.WriteUnaligned(ref Unsafe.Add(ref to, 16), Unsafe.ReadUnaligned<ulong>(ref Unsafe.Add(ref number, 16)));
        }

        return o + size;
    }

    private static readonly double[] Pow10 = [1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];
}

/// <summary>Three numbers, X Y Z, held inline (an <see cref="AxisLine"/> is a value copied per line).</summary>
[InlineArray(3)]
public struct AxisTriple
{
    private int _first;
}
