using System.Buffers.Text;
using System.Runtime.CompilerServices;
using System.Runtime.InteropServices;

namespace PmacStream.Preparation;

/// <summary>
/// Decimal text of a non-negative number that usually grows by one from call to call (the source line of the next
/// tracked block): the previous digits are incremented in place instead of formatted again, and written out with two
/// 8-byte stores instead of a general copy.
/// </summary>
internal sealed class AsciiCounter
{
    private readonly byte[] _digits = new byte[16]; // left-aligned; int.MaxValue has 10 digits
    private int _length;
    private long _value = -2;

    /// <summary>
    /// Writes the decimal digits of <paramref name="value"/> at the start of <paramref name="o"/> and returns how
    /// many. When <paramref name="o"/> has 16 bytes or more, the bytes after the digits are overwritten too (the
    /// caller's reserved space, written over next).
    /// </summary>
    [MethodImpl(MethodImplOptions.AggressiveInlining)]
    public int Write(Span<byte> o, int value)
    {
        if (value != _value + 1 || value <= 0 || !Increment())
        {
            Format(value);
        }

        _value = value;
        if (o.Length >= 16)
        {
            MemoryMarshal.Write(o, MemoryMarshal.Read<ulong>(_digits));
            MemoryMarshal.Write(o[8..], MemoryMarshal.Read<ulong>(_digits.AsSpan(8)));
        }
        else
        {
            _digits.AsSpan(0, _length).CopyTo(o);
        }

        return _length;
    }

    /// <summary>Adds one in place; false when a carry would lengthen the number (then it is formatted afresh).</summary>
    private bool Increment()
    {
        var i = _length - 1;
        while (i >= 0 && _digits[i] == (byte)'9')
        {
            i--;
        }

        if (i < 0)
        {
            return false;
        }

        _digits[i]++;
        for (var k = i + 1; k < _length; k++)
        {
            _digits[k] = (byte)'0';
        }

        return true;
    }

    private void Format(int value)
    {
        ArgumentOutOfRangeException.ThrowIfNegative(value);
        Utf8Formatter.TryFormat(value, _digits, out _length);
    }
}
