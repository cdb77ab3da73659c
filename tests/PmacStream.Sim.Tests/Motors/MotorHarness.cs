using System.Globalization;

namespace PmacStream.Sim.Tests.Motors;

/// <summary>Reading the status words the way a host does: bit n of word w of a <c>?</c>/<c>??</c> answer.</summary>
internal static class StatusBits
{
    /// <summary>Word <paramref name="word"/> (1-based) of a hex status answer: 6 hex digits each.</summary>
    public static int Word(string status, int word) => int.Parse(status.Substring((word - 1) * 6, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture);

    public static bool Bit(string status, int word, int bit) => ((Word(status, word) >> bit) & 1) == 1;

    public static bool MotorBit(this SimHarness h, int motor, int word, int bit) => Bit(h.Ok($"#{motor}?"), word, bit);

    public static bool CsBit(this SimHarness h, int word, int bit) => Bit(h.Ok("&1??"), word, bit);

    public static double Number(this SimHarness h, string command) => double.Parse(h.Ok(command), NumberStyles.Float, CultureInfo.InvariantCulture);
}
