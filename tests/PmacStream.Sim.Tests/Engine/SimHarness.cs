namespace PmacStream.Sim.Tests.Engine;

/// <summary>A simulator with one port; Send returns the reply with control bytes spelled out.</summary>
internal sealed class SimHarness : IDisposable
{
    public SimHarness(SimOptions? options = null)
    {
        Sim = new PmacSimulator(options);
        Port = Sim.OpenPort("test");
    }

    public PmacSimulator Sim { get; }

    public SimPort Port { get; }

    public string Send(string command) => SimPort.Visible(Port.Execute(command));

    public string Send(SimPort port, string command) => SimPort.Visible(port.Execute(command));

    /// <summary>Sends and expects an ACK-terminated reply; returns the values (CR-separated, no ACK).</summary>
    public string Ok(string command)
    {
        var reply = Send(command);
        reply.Should().EndWith("<ACK>", $"'{command}' should be accepted");
        return reply[..^5].Replace("<CR>", "\n").TrimEnd('\n');
    }

    public void Download(params string[] lines)
    {
        foreach (var l in lines)
        {
            Send(l).Should().Be("<ACK>", $"line '{l}' should be stored");
        }
    }

    public double M(int n) => Sim.ReadVariable('M', n);

    public void Advance(double seconds) => Sim.Advance(TimeSpan.FromSeconds(seconds));

    public void Dispose() => Sim.Dispose();
}
