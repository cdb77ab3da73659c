using System.Text;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

public sealed class AsciiCounterTests
{
    [Fact]
    public void Counting_up_by_one_carries_through_every_digit()
    {
        var counter = new AsciiCounter();
        for (var n = 0; n <= 100_000; n++)
        {
            Text(counter, n).Should().Be(n.ToString(System.Globalization.CultureInfo.InvariantCulture));
        }
    }

    [Theory]
    [InlineData(new[] { 5, 7, 8, 3, 4, 1000, 999, 1000, 1001 })]
    [InlineData(new[] { 9, 10, 99, 100, 101, 9999, 10000, 2147483646, 2147483647 })]
    [InlineData(new[] { 1, 1, 2, 2, 3 })]
    public void Jumps_repeats_and_going_back_are_formatted_afresh(int[] values)
    {
        var counter = new AsciiCounter();
        foreach (var n in values)
        {
            Text(counter, n).Should().Be(n.ToString(System.Globalization.CultureInfo.InvariantCulture));
        }
    }

    [Fact]
    public void Writes_into_short_destinations_without_touching_bytes_after_the_digits()
    {
        var counter = new AsciiCounter();
        var small = new byte[12];
        small.AsSpan().Fill((byte)'#');
        counter.Write(small.AsSpan(0, 7), 1234567).Should().Be(7);
        Encoding.ASCII.GetString(small).Should().Be("1234567#####");
        counter.Write(small.AsSpan(0, 7), 1234568).Should().Be(7);
        Encoding.ASCII.GetString(small).Should().Be("1234568#####");
    }

    // Through a 16-byte destination, the hot path (two 8-byte stores).
    private static string Text(AsciiCounter counter, int n)
    {
        var o = new byte[32];
        var length = counter.Write(o, n);
        return Encoding.ASCII.GetString(o, 0, length);
    }
}
