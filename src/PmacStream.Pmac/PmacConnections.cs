namespace PmacStream.Pmac;

/// <summary>Creates connections from one-line specs, for configuration files and command lines.</summary>
public static class PmacConnections
{
    /// <summary>
    /// Creates (does not open) a connection from a spec in one of the forms <see cref="ConnectionSpec.Parse"/> reads:
    /// <c>tcp://HOST[:PORT]</c> or <c>HOST:PORT</c> (Ethernet, port 1025 by default); <c>serial:PORT[@BAUD][,none|even|odd]</c>
    /// (RS-232, 38400 8N1 by default); <c>pcomm32:N</c> (PComm32 device N).
    /// </summary>
    /// <exception cref="FormatException">The spec is not one of these forms.</exception>
    /// <exception cref="NotSupportedException">The spec names the built-in simulator, which only its host can open.</exception>
    public static IPmacConnection Create(string spec, TimeSpan? timeout = null) => Create(ConnectionSpec.Parse(spec), timeout);

    /// <summary>Creates (does not open) the connection a parsed spec names.</summary>
    /// <exception cref="NotSupportedException">The spec names the built-in simulator, which only its host can open.</exception>
    public static IPmacConnection Create(ConnectionSpec spec, TimeSpan? timeout = null)
    {
        ArgumentNullException.ThrowIfNull(spec);
        var t = timeout ?? TimeSpan.FromSeconds(2);
        return spec.Kind switch
        {
            LinkKind.Serial => new SerialConnection(new SerialOptions { PortName = spec.SerialPort, Settings = spec.Serial, Timeout = t }),
            LinkKind.Pcomm32 => new PComm32Connection(spec.Device),
            LinkKind.Ethernet => new EthernetConnection(new EthernetOptions { Host = spec.Host, Port = spec.Port, Timeout = t }),
            _ => throw new NotSupportedException("the built-in simulator is opened by the application that hosts it (pmacstream stream --sim, the HMI's Simulator device)"),
        };
    }
}
