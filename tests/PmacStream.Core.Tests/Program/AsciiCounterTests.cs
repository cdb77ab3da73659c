using System.Text;
using PmacStream.Program;

namespace PmacStream.Core.Tests.Program;

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

    private static string Text(AsciiCounter counter, int n) => Encoding.ASCII.GetString(counter.Text(n));
}
