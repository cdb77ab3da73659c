using System.Net;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>
/// The server's one read deadline per connection, re-armed for every packet: the packet timeout applies inside a packet
/// only, never to the pause between packets, however many packets came before; a packet that stops half-way still
/// closes the connection.
/// </summary>
public sealed class ReadDeadlineTests
{
    private static byte[] A(string s) => Encoding.ASCII.GetBytes(s);

    [Fact]
    public async Task The_packet_timeout_applies_inside_a_packet_and_never_to_the_pause_between_packets()
    {
        await using var server = new PmacTcpServer(new ScriptedController().OpenPort, new PmacTcpServerOptions
        {
            EndPoint = new IPEndPoint(IPAddress.Loopback, 0), PacketTimeout = TimeSpan.FromSeconds(1), IdleTimeout = TimeSpan.FromSeconds(60),
        });
        server.Start();
        using var w = new TcpWire(server.Port);
        for (var round = 0; round < 3; round++)
        {
            for (var i = 0; i < 300; i++)
            {
                w.GetResponse("VER").Should().Equal(A("1.947\r\x06"));
            }

            // A packet whose data comes a little after its header: well within the packet timeout (a loaded CI machine
            // can delay the sender's continuation by hundreds of milliseconds), served.
            var data = A("VER");
            var packet = TcpWire.Packet(VrPmac.Download, VrPmac.GetResponse, 0, (ushort)data.Length, data);
            w.Send(packet[..VrPmac.HeaderSize]);
            await Task.Delay(50);
            w.Send(packet[VrPmac.HeaderSize..]);
            w.ReceiveReply().Should().Equal(A("1.947\r\x06"));

            // Then a pause of one and a half packet timeouts: the connection is idle, not inside a packet.
            await Task.Delay(1500);
            w.GetResponse("VER").Should().Equal(A("1.947\r\x06"), $"round {round}: the pause after a packet is not a broken packet");
        }

        server.MalformedPackets.Should().Be(0);
        server.IdleClosed.Should().Be(0);

        // A header whose data never comes: closed once the packet timeout has passed.
        var half = TcpWire.Packet(VrPmac.Download, VrPmac.GetResponse, 0, 3, A("VER"));
        w.Send(half[..VrPmac.HeaderSize]);
        await Task.Delay(2500);
        w.IsClosedByServer().Should().BeTrue();
        server.MalformedPackets.Should().Be(1);
    }
}
