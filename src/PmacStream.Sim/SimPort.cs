using System.Text;
using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// One communication port of the simulator (a serial line, a TCP client, an in-process client). It has its own
/// I3/I6 reply framing, addressed coordinate system (<c>&amp;n</c>) and motor (<c>#n</c>), and may own the one open
/// program buffer. Thread-safe.
/// </summary>
public sealed class SimPort : IPmacPortEndpoint, IDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<SimPort>();
    private readonly PmacSimulator _sim;
    private bool _closed;

    internal SimPort(PmacSimulator sim, string name, int i3, int i6)
    {
        _sim = sim;
        Name = name;
        I3 = i3;
        I6 = i6;
    }

    /// <summary>The name given at <see cref="PmacSimulator.OpenPort"/> (for logs).</summary>
    public string Name { get; }

    /// <summary>This port's I3 (reply handshake): 0 none, 1 LF, 2 ACK (host programs), 3 LF-framed lines + ACK.</summary>
    public int I3 { get; internal set; }

    /// <summary>This port's I6 (error reporting): 0 BEL only, otherwise <c>&lt;BEL&gt;ERRnnn&lt;CR&gt;</c>.</summary>
    public int I6 { get; internal set; }

    /// <summary>Coordinate system addressed with <c>&amp;n</c> (1..16).</summary>
    public int CoordinateSystem { get; internal set; } = 1;

    /// <summary>Motor addressed with <c>#n</c> (1..32).</summary>
    public int Motor { get; internal set; } = 1;

    /// <summary>The simulator this port belongs to.</summary>
    public PmacSimulator Simulator => _sim;

    /// <inheritdoc />
    public byte[] Execute(string commandLine)
    {
        ArgumentNullException.ThrowIfNull(commandLine);
        ObjectDisposedException.ThrowIf(_closed, this);
        var reply = _sim.ExecuteLine(this, commandLine);
        if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
        {
            Log.Debug("sim {Port} > {Command} < {Reply}", Name, commandLine, Visible(reply));
        }

        return reply;
    }

    /// <summary>Runs a command and returns its reply as text (control characters as in the raw bytes).</summary>
    public string ExecuteText(string commandLine) => Encoding.ASCII.GetString(Execute(commandLine));

    /// <inheritdoc />
    public void Flush()
    {
        // Replies are produced synchronously per command: nothing is ever pending on an in-process port.
    }

    /// <inheritdoc />
    public byte[] Control(char control) => _sim.ExecuteControl(this, control);

    /// <summary>Closes the port; a buffer it had open is closed.</summary>
    public void Dispose()
    {
        if (!_closed)
        {
            _closed = true;
            _sim.PortClosed(this);
        }
    }

    internal void ResetFraming(int i3, int i6)
    {
        I3 = i3;
        I6 = i6;
    }

    /// <summary>Shows control bytes as &lt;ACK&gt;, &lt;BEL&gt;, &lt;CR&gt; (logs and test messages).</summary>
    public static string Visible(ReadOnlySpan<byte> raw)
    {
        var sb = new StringBuilder(raw.Length + 8);
        foreach (var b in raw)
        {
            _ = b switch
            {
                0x06 => sb.Append("<ACK>"),
                0x07 => sb.Append("<BEL>"),
                0x0D => sb.Append("<CR>"),
                0x0A => sb.Append("<LF>"),
                _ when b < 0x20 || b > 0x7E => sb.Append($"<{b:X2}>"),
                _ => sb.Append((char)b),
            };
        }

        return sb.ToString();
    }
}
