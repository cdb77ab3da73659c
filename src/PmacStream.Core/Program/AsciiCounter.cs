using System.Buffers.Text;

namespace PmacStream.Program;

/// <summary>
/// Decimal text of a non-negative number that usually grows by one from call to call (the source line of the next
/// tracked block): the previous digits are incremented in place instead of formatted again.
/// </summary>
internal sealed class AsciiCounter
{
    private const int Capacity = 11; // int.MaxValue has 10 digits; one spare for the carry
    private readonly byte[] _digits = new byte[Capacity];
    private int _start = Capacity;
    private long _value = -2;

    /// <summary>The decimal digits of <paramref name="value"/> (valid until the next call).</summary>
    public ReadOnlySpan<byte> Text(int value)
    {
        if (value == _value + 1 && value > 0)
        {
            var i = Capacity - 1;
            while (i >= _start && _digits[i] == (byte)'9')
            {
                _digits[i--] = (byte)'0';
            }

            if (i >= _start)
            {
                _digits[i]++;
            }
            else
            {
                _digits[--_start] = (byte)'1';
            }
        }
        else
        {
            ArgumentOutOfRangeException.ThrowIfNegative(value);
            Span<byte> tmp = stackalloc byte[Capacity];
            Utf8Formatter.TryFormat(value, tmp, out var written);
            _start = Capacity - written;
            tmp[..written].CopyTo(_digits.AsSpan(_start));
        }

        _value = value;
        return _digits.AsSpan(_start);
    }
}
