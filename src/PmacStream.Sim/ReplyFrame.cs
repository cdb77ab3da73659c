using System.Globalization;
using System.Text;
using PmacStream.Pmac;

namespace PmacStream.Sim;

/// <summary>
/// How a port frames the reply to one command line, by its I3 (handshake) and I6 (error reporting): each value ends
/// in CR (I3=3: led by LF), then ACK (I3=2/3) or LF (I3=1); an error is BEL, with <c>ERRnnn</c> CR unless I6=0.
/// The bytes are the protocol's (<see cref="ReplyParser"/> reads them on the host side).
/// </summary>
internal static class ReplyFrame
{
    private const byte Ack = ReplyParser.Ack;
    private const byte Bel = ReplyParser.Bel;
    private const byte Cr = ReplyParser.Cr;
    private const byte Lf = 0x0A;

    /// <summary>The reply bytes for <paramref name="outputs"/> and <paramref name="error"/> (0: none).</summary>
    public static byte[] Build(List<string> outputs, int error, int i3, int i6)
    {
        if (outputs.Count == 0 && error == 0)
        {
            // The common case (a stored program line, a setting): just the handshake.
            return i3 switch
            {
                2 or 3 => [Ack],
                1 => [Lf],
                _ => [],
            };
        }

        var bytes = new List<byte>(16);
        foreach (var o in outputs)
        {
            if (i3 == 3)
            {
                bytes.Add(Lf);
            }

            bytes.AddRange(Encoding.ASCII.GetBytes(o));
            bytes.Add(Cr);
        }

        if (error != 0)
        {
            bytes.Add(Bel);
            if (i6 != 0)
            {
                bytes.AddRange(Encoding.ASCII.GetBytes(string.Create(CultureInfo.InvariantCulture, $"ERR{error:000}")));
                bytes.Add(Cr);
            }
        }
        else if (i3 is 2 or 3)
        {
            bytes.Add(Ack);
        }
        else if (i3 == 1)
        {
            bytes.Add(Lf);
        }

        return [.. bytes];
    }

    /// <summary>A number as the controller prints it: up to 10 decimals, no trailing zeros, <c>0</c> for zero.</summary>
    public static string Number(double v) => v == 0 ? "0" : v.ToString("0.##########", CultureInfo.InvariantCulture);
}
