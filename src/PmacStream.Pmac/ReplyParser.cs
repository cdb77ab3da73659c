using System.Text;

namespace PmacStream.Pmac;

/// <summary>
/// Parses the ASCII protocol's reply framing with I3=2, I6=1: <c>data&lt;CR&gt;...&lt;ACK&gt;</c> on success,
/// <c>&lt;BEL&gt;ERRnnn&lt;CR&gt;</c> on error. Shared by the serial and in-process transports.
/// </summary>
public static class ReplyParser
{
    /// <summary>ACK, the end of a successful reply.</summary>
    public const byte Ack = 0x06;

    /// <summary>BEL, the start of an error reply.</summary>
    public const byte Bel = 0x07;

    /// <summary>CR, ends each value.</summary>
    public const byte Cr = 0x0D;

    /// <summary>Returns true when <paramref name="bytes"/> holds a complete reply (ends in ACK, or BEL...CR).</summary>
    public static bool IsComplete(ReadOnlySpan<byte> bytes)
    {
        if (bytes.IsEmpty)
        {
            return false;
        }

        var bel = bytes.IndexOf(Bel);
        if (bel >= 0)
        {
            return bytes[bel..].IndexOf(Cr) >= 0;
        }

        return bytes[^1] == Ack;
    }

    /// <summary>
    /// Turns a complete reply into its text (CR-separated values, no trailing CR or ACK), or throws
    /// <see cref="PmacErrorException"/> for an ERR reply.
    /// </summary>
    public static string Parse(ReadOnlySpan<byte> bytes, string command)
    {
        var bel = bytes.IndexOf(Bel);
        if (bel >= 0)
        {
            var rest = bytes[(bel + 1)..];
            var cr = rest.IndexOf(Cr);
            var text = Encoding.ASCII.GetString(cr >= 0 ? rest[..cr] : rest);
            var number = text.StartsWith("ERR", StringComparison.Ordinal) && int.TryParse(text.AsSpan(3), out var n) ? n : PmacErrors.UnknownCommand;
            throw new PmacErrorException(number, command);
        }

        if (!bytes.IsEmpty && bytes[^1] == Ack)
        {
            bytes = bytes[..^1];
        }

        if (!bytes.IsEmpty && bytes[^1] == Cr)
        {
            bytes = bytes[..^1];
        }

        return Encoding.ASCII.GetString(bytes).Replace('\r', '\n');
    }

    /// <summary>The bytes of a reply made readable for logs: <c>&lt;ACK&gt;</c>, <c>&lt;BEL&gt;</c>, <c>&lt;CR&gt;</c>, other controls as hex.</summary>
    public static string Visible(ReadOnlySpan<byte> raw)
    {
        var sb = new StringBuilder(raw.Length + 8);
        foreach (var b in raw)
        {
            _ = b switch
            {
                Ack => sb.Append("<ACK>"),
                Bel => sb.Append("<BEL>"),
                Cr => sb.Append("<CR>"),
                _ when b < 0x20 || b > 0x7E => sb.Append($"<{b:X2}>"),
                _ => sb.Append((char)b),
            };
        }

        return sb.ToString();
    }
}
