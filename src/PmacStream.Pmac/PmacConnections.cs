using System.Globalization;

namespace PmacStream.Pmac;

/// <summary>Creates connections from one-line specs, for configuration files and command lines.</summary>
public static class PmacConnections
{
    /// <summary>
    /// Creates (does not open) a connection: <c>tcp://HOST[:PORT]</c> or <c>HOST:PORT</c> (Ethernet, port 1025 by
    /// default); <c>serial:PORT[@BAUD][,none|even|odd]</c> (RS-232, 38400 8N1 by default); <c>pcomm32:N</c>
    /// (PComm32 device N).
    /// </summary>
    /// <exception cref="FormatException">The spec is not one of these forms.</exception>
    public static IPmacConnection Create(string spec, TimeSpan? timeout = null)
    {
        ArgumentNullException.ThrowIfNull(spec);
        var t = timeout ?? TimeSpan.FromSeconds(2);
        if (spec.StartsWith("serial:", StringComparison.OrdinalIgnoreCase))
        {
            var rest = spec["serial:".Length..];
            var parity = SerialParity.None;
            var comma = rest.LastIndexOf(',');
            if (comma >= 0)
            {
                parity = rest[(comma + 1)..].ToLowerInvariant() switch
                {
                    "none" or "n" => SerialParity.None,
                    "even" or "e" => SerialParity.Even,
                    "odd" or "o" => SerialParity.Odd,
                    var p => throw new FormatException($"'{spec}': parity '{p}' is not none, even or odd"),
                };
                rest = rest[..comma];
            }

            var baud = 38400;
            var at = rest.LastIndexOf('@');
            if (at >= 0)
            {
                if (!int.TryParse(rest.AsSpan(at + 1), NumberStyles.None, CultureInfo.InvariantCulture, out baud))
                {
                    throw new FormatException($"'{spec}': baud rate '{rest[(at + 1)..]}' is not a number");
                }

                rest = rest[..at];
            }

            if (rest.Length == 0)
            {
                throw new FormatException($"'{spec}': no serial port named (serial:/dev/ttyS0@38400)");
            }

            return new SerialConnection(new SerialOptions { PortName = rest, Settings = new SerialSettings(baud, parity), Timeout = t });
        }

        if (spec.StartsWith("pcomm32:", StringComparison.OrdinalIgnoreCase))
        {
            return int.TryParse(spec.AsSpan("pcomm32:".Length), NumberStyles.None, CultureInfo.InvariantCulture, out var device)
                ? new PComm32Connection(device)
                : throw new FormatException($"'{spec}': expected pcomm32:N with N the PComm32 device number");
        }

        var host = spec.StartsWith("tcp://", StringComparison.OrdinalIgnoreCase) ? spec["tcp://".Length..] : spec;
        var port = 1025;
        var colon = host.LastIndexOf(':');
        if (colon >= 0 && !host.EndsWith(']'))
        {
            if (!int.TryParse(host.AsSpan(colon + 1), NumberStyles.None, CultureInfo.InvariantCulture, out port) || port is < 1 or > 65535)
            {
                throw new FormatException($"'{spec}': port '{host[(colon + 1)..]}' is not 1..65535");
            }

            host = host[..colon];
        }
        else if (!spec.StartsWith("tcp://", StringComparison.OrdinalIgnoreCase))
        {
            throw new FormatException($"'{spec}': expected tcp://HOST[:PORT], HOST:PORT, serial:PORT[@BAUD][,PARITY] or pcomm32:N");
        }

        if (host.Length == 0)
        {
            throw new FormatException($"'{spec}': no host");
        }

        return new EthernetConnection(new EthernetOptions { Host = host.Trim('[', ']'), Port = port, Timeout = t });
    }
}
