using PmacStream.Sim;

namespace PmacStream.Testing;

/// <summary>
/// The rig's bottom layer: the real simulator and one port on it, no socket, no splitter, no session. The
/// simulator's own tests drive its engine through this (Send returns the reply with control bytes spelled out);
/// <see cref="SimRig"/> stands on it to stream a split program.
/// </summary>
public sealed class SimHarness : IDisposable
{
    /// <summary>A simulator with <paramref name="options"/> and one port named <paramref name="port"/>.</summary>
    public SimHarness(SimOptions? options = null, string port = "test")
    {
        Sim = new PmacSimulator(options);
        Port = Sim.OpenPort(port);
    }

    public PmacSimulator Sim { get; }

    public SimPort Port { get; }

    public string Send(string command) => SimPort.Visible(Port.Execute(command));

    public string Send(SimPort port, string command) => SimPort.Visible(port.Execute(command));

    /// <summary>Sends and expects an ACK-terminated reply; returns the values (CR-separated, no ACK).</summary>
    /// <exception cref="InvalidOperationException">The reply is not an ACK: the test fails with the command and the reply.</exception>
    public string Ok(string command)
    {
        var reply = Send(command);
        if (!reply.EndsWith("<ACK>", StringComparison.Ordinal))
        {
            throw new InvalidOperationException($"'{command}' should be accepted, but the reply was {reply}");
        }

        return reply[..^5].Replace("<CR>", "\n", StringComparison.Ordinal).TrimEnd('\n');
    }

    /// <summary>Downloads program lines; each must be stored (a bare ACK).</summary>
    /// <exception cref="InvalidOperationException">A line was not stored: the test fails naming it and the reply.</exception>
    public void Download(params string[] lines)
    {
        foreach (var l in lines)
        {
            var reply = Send(l);
            if (reply != "<ACK>")
            {
                throw new InvalidOperationException($"line '{l}' should be stored, but the reply was {reply}");
            }
        }
    }

    public double M(int n) => Sim.ReadVariable('M', n);

    public void Advance(double seconds) => Sim.Advance(TimeSpan.FromSeconds(seconds));

    public void Dispose() => Sim.Dispose();
}
