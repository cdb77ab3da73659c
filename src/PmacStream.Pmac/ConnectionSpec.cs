using System.Globalization;

namespace PmacStream.Pmac;

/// <summary>The kinds of controller link.</summary>
public enum LinkKind
{
    /// <summary>The built-in simulated Turbo PMAC (opened by the host application, not by <see cref="PmacConnections"/>).</summary>
    Simulator,

    /// <summary>Ethernet: VR_PMAC packets on TCP (port 1025 by default).</summary>
    Ethernet,

    /// <summary>RS-232 serial line (38400 8N1 by default).</summary>
    Serial,

    /// <summary>Delta Tau's PComm32 driver (Windows).</summary>
    Pcomm32,
}

/// <summary>
/// Where a controller is, in one line: <c>sim</c>; <c>tcp://HOST[:PORT]</c> or <c>HOST:PORT</c>;
/// <c>serial:PORT[@BAUD][,none|even|odd]</c>; <c>pcomm32:N</c>. The one parser of these forms for the command line,
/// the HMI's connection panel and job records; <see cref="ToString"/> gives the canonical spelling back.
/// </summary>
public sealed record ConnectionSpec
{
    /// <summary>Ethernet port of a Turbo PMAC.</summary>
    public const int DefaultPort = 1025;

    /// <summary>Baud rate when none is given.</summary>
    public const int DefaultBaud = 38400;

    private ConnectionSpec(LinkKind kind) => Kind = kind;

    /// <summary>The kind of link.</summary>
    public LinkKind Kind { get; }

    /// <summary>Ethernet host (empty for other kinds).</summary>
    public string Host { get; private init; } = string.Empty;

    /// <summary>Ethernet port.</summary>
    public int Port { get; private init; } = DefaultPort;

    /// <summary>Serial port name (<c>COM1</c>, <c>/dev/ttyS0</c>; empty for other kinds).</summary>
    public string SerialPort { get; private init; } = string.Empty;

    /// <summary>Serial line settings.</summary>
    public SerialSettings Serial { get; private init; } = new();

    /// <summary>PComm32 device number.</summary>
    public int Device { get; private init; }

    /// <summary>The built-in simulator.</summary>
    public static ConnectionSpec Simulator { get; } = new(LinkKind.Simulator);

    /// <summary>True for the built-in simulator.</summary>
    public bool IsSimulator => Kind == LinkKind.Simulator;

    /// <summary>
    /// An Ethernet link; <paramref name="address"/> is <c>HOST</c>, <c>HOST:PORT</c>, <c>tcp://HOST[:PORT]</c> or a port
    /// alone (on 127.0.0.1).
    /// </summary>
    /// <exception cref="FormatException">Not a host with an optional port 1..65535.</exception>
    public static ConnectionSpec Ethernet(string address)
    {
        ArgumentNullException.ThrowIfNull(address);
        var a = address.Trim();
        return Parse(a.StartsWith("tcp://", StringComparison.OrdinalIgnoreCase) ? a : "tcp://" + a);
    }

    /// <summary>A serial link on <paramref name="port"/>.</summary>
    public static ConnectionSpec SerialLine(string port, int baud = DefaultBaud, SerialParity parity = SerialParity.None)
    {
        ArgumentException.ThrowIfNullOrWhiteSpace(port);
        return new ConnectionSpec(LinkKind.Serial) { SerialPort = port.Trim(), Serial = new SerialSettings(baud, parity) };
    }

    /// <summary>PComm32 device <paramref name="device"/>.</summary>
    public static ConnectionSpec Pcomm(int device) => new(LinkKind.Pcomm32) { Device = device };

    /// <summary>Parses one of the forms above.</summary>
    /// <exception cref="FormatException">The spec is not one of them (the message names the forms that work).</exception>
    public static ConnectionSpec Parse(string spec)
    {
        ArgumentNullException.ThrowIfNull(spec);
        var s = spec.Trim();
        if (s.Equals("sim", StringComparison.OrdinalIgnoreCase))
        {
            return Simulator;
        }

        if (s.StartsWith("serial:", StringComparison.OrdinalIgnoreCase))
        {
            return ParseSerial(spec, s["serial:".Length..]);
        }

        if (s.StartsWith("pcomm32:", StringComparison.OrdinalIgnoreCase))
        {
            return int.TryParse(s.AsSpan("pcomm32:".Length), NumberStyles.None, CultureInfo.InvariantCulture, out var device)
                ? Pcomm(device)
                : throw new FormatException($"'{spec}': expected pcomm32:N with N the PComm32 device number");
        }

        var tcp = s.StartsWith("tcp://", StringComparison.OrdinalIgnoreCase);
        var host = tcp ? s["tcp://".Length..] : s;
        var port = DefaultPort;
        var colon = host.LastIndexOf(':');

        // A bare number is a port on this machine, as `pmacstream sim --tcp PORT` serves it: the resolver would
        // read "44887" as the address 0.0.175.87 and connect to whatever listens there.
        if (host.Length > 0 && host.All(char.IsAsciiDigit))
        {
            return int.TryParse(host, NumberStyles.None, CultureInfo.InvariantCulture, out port) && port is >= 1 and <= 65535
                ? new ConnectionSpec(LinkKind.Ethernet) { Host = "127.0.0.1", Port = port }
                : throw new FormatException($"'{spec}': port '{host}' is not 1..65535");
        }

        if (colon >= 0 && !host.EndsWith(']'))
        {
            if (!int.TryParse(host.AsSpan(colon + 1), NumberStyles.None, CultureInfo.InvariantCulture, out port) || port is < 1 or > 65535)
            {
                throw new FormatException($"'{spec}': port '{host[(colon + 1)..]}' is not 1..65535");
            }

            host = host[..colon];
        }
        else if (!tcp)
        {
            throw new FormatException($"'{spec}': expected sim, tcp://HOST[:PORT], HOST:PORT, serial:PORT[@BAUD][,PARITY] or pcomm32:N");
        }

        if (host.Length == 0)
        {
            throw new FormatException($"'{spec}': no host");
        }

        return host.All(char.IsAsciiDigit)
            ? throw new FormatException($"'{spec}': '{host}' is a number, not a host: give HOST:PORT, or the port alone for 127.0.0.1")
            : new ConnectionSpec(LinkKind.Ethernet) { Host = host.Trim('[', ']'), Port = port };
    }

    /// <summary>The canonical spelling (<c>sim</c>, <c>tcp://host:port</c>, <c>serial:port@baud[,parity]</c>, <c>pcomm32:n</c>).</summary>
    public override string ToString() => Kind switch
    {
        LinkKind.Ethernet => string.Create(CultureInfo.InvariantCulture, $"tcp://{(Host.Contains(':', StringComparison.Ordinal) ? $"[{Host}]" : Host)}:{Port}"),
        LinkKind.Serial => string.Create(CultureInfo.InvariantCulture, $"serial:{SerialPort}@{Serial.BaudRate}")
            + (Serial.Parity == SerialParity.None ? string.Empty : "," + Serial.Parity.ToString().ToLowerInvariant()),
        LinkKind.Pcomm32 => string.Create(CultureInfo.InvariantCulture, $"pcomm32:{Device}"),
        _ => "sim",
    };

    private static ConnectionSpec ParseSerial(string spec, string rest)
    {
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

        var baud = DefaultBaud;
        var at = rest.LastIndexOf('@');
        if (at >= 0)
        {
            if (!int.TryParse(rest.AsSpan(at + 1), NumberStyles.None, CultureInfo.InvariantCulture, out baud))
            {
                throw new FormatException($"'{spec}': baud rate '{rest[(at + 1)..]}' is not a number");
            }

            rest = rest[..at];
        }

        return rest.Length == 0
            ? throw new FormatException($"'{spec}': no serial port named (serial:/dev/ttyS0@38400)")
            : SerialLine(rest, baud, parity);
    }
}
