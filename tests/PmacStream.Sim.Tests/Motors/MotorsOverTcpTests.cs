using System.Globalization;
using System.Net;
using System.Text;
using PmacStream.Sim.Servers;
using PmacStream.Sim.Tests.Servers;

namespace PmacStream.Sim.Tests.Motors;

/// <summary>
/// The motor commands and reports through the real Ethernet server (VR_PMAC packets), as a console written against a
/// Turbo PMAC would drive them: home, jog, read <c>?</c>, <c>??</c>, <c>P</c>; a fault shows in the status words.
/// </summary>
public sealed class MotorsOverTcpTests : IAsyncLifetime
{
    private readonly PmacSimulator _sim = new(new SimOptions { StartHomed = false });
    private PmacTcpServer _server = null!;

    public Task InitializeAsync()
    {
        _server = new PmacTcpServer(() => _sim.OpenPort("tcp"), new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        _server.Start();
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _server.DisposeAsync();
        _sim.Dispose();
    }

    /// <summary>The values of a reply (CR-separated, ACK stripped); fails on an error reply.</summary>
    private static string[] Values(TcpWire w, string command)
    {
        var reply = Encoding.ASCII.GetString(w.GetResponse(command));
        reply.Should().EndWith("\x06", $"'{command}' should be accepted");
        return reply.TrimEnd('\x06').Split('\r', StringSplitOptions.RemoveEmptyEntries);
    }

    private static bool Bit(string status, int word, int bit) => StatusBits.Bit(status, word, bit);

    [Fact]
    public void Home_jog_and_read_status_and_positions_over_the_wire()
    {
        using var w = new TcpWire(_server.Port);
        Bit(Values(w, "#1?")[0], 2, 10).Should().BeFalse("pmacstream sim starts unhomed");
        Values(w, "I119=100 I121=1 I219=100 I221=1");
        Values(w, "#1HM#2HM");
        _sim.Advance(TimeSpan.FromSeconds(1));
        var status = Values(w, "#1?#2?");
        status.Should().HaveCount(2);
        status.Should().AllSatisfy(s => Bit(s, 2, 10).Should().BeTrue("Home Complete"));
        status.Should().AllSatisfy(s => Bit(s, 2, 0).Should().BeTrue("In Position"));

        Values(w, "#1J:3200 #2J:-1600");
        _sim.Advance(TimeSpan.FromSeconds(0.05));
        Bit(Values(w, "#1?")[0], 1, 13).Should().BeFalse("moving: desired velocity not zero");
        Bit(Values(w, "&1??")[0], 2, 17).Should().BeFalse("a motor of the C.S. is moving");
        _sim.Advance(TimeSpan.FromSeconds(1));
        Values(w, "#1P#2P").Should().Equal("3200", "-1600");
        Values(w, "#1V#2V#1F").Should().Equal("0", "0", "0");
        Bit(Values(w, "&1??")[0], 2, 17).Should().BeTrue("in position again");

        _sim.InjectFault(FaultKind.AmpFault, 2);
        var cs = Values(w, "&1??")[0];
        cs.Should().HaveLength(18, "three 24-bit words");
        Bit(cs, 2, 20).Should().BeTrue("Amplifier Fault Error");
        Bit(Values(w, "#2?")[0], 2, 3).Should().BeTrue();
        Values(w, "&1A");
        Bit(Values(w, "&1??")[0], 2, 20).Should().BeFalse("&1A re-enabled the motors");
        double.Parse(Values(w, "#2P")[0], CultureInfo.InvariantCulture).Should().Be(-1600);
    }
}
