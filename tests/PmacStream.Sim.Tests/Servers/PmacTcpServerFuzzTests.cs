using System.Diagnostics;
using System.Net;
using System.Net.Sockets;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>
/// Seeded random and mutated packets thrown at the server: after each burst the server still answers a clean
/// client correctly, the fuzzing client's connection is either still usable or closed (never stuck), and all of it
/// ends within a bounded number of packets.
/// </summary>
public sealed class PmacTcpServerFuzzTests
{
    private static readonly byte[][] ValidPackets =
    [
        TcpWire.Packet(VrPmac.Download, VrPmac.GetResponse, 0, 3, "VER"u8),
        TcpWire.Packet(VrPmac.Download, VrPmac.GetResponse, 0, 9, "LONG 2000"u8),
        TcpWire.Packet(VrPmac.Download, VrPmac.SendLine, 0, 7, "P1=12.5"u8),
        TcpWire.Packet(VrPmac.Upload, VrPmac.GetLine, 0, 1400, []),
        TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []),
        TcpWire.Packet(VrPmac.Upload, VrPmac.GetBuffer, 0, 1400, []),
        TcpWire.Packet(VrPmac.Download, VrPmac.Flush, 0, 0, []),
        TcpWire.Packet(VrPmac.Upload, VrPmac.CtrlResponse, 2, 0, []),
        TcpWire.Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, 9, "X1\0BAD\0\0"u8),
    ];

    [Theory]
    [InlineData(1)]
    [InlineData(2)]
    [InlineData(3)]
    public async Task Random_and_mutated_packets_never_stop_the_server(int seed)
    {
        var controller = new ScriptedController();
        await FuzzAsync(controller.OpenPort, seed);
    }

    [Theory]
    [InlineData(11)]
    [InlineData(12)]
    public async Task Random_and_mutated_packets_with_the_real_engine_behind(int seed)
    {
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Instant });
        await FuzzAsync(() => sim.OpenPort("fuzz"), seed);
    }

    private static async Task FuzzAsync(Func<PmacStream.Pmac.IPmacPortEndpoint> ports, int seed)
    {
        await using var server = new PmacTcpServer(ports, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0), PacketTimeout = TimeSpan.FromMilliseconds(100) });
        server.Start();
        using var witness = new TcpWire(server.Port);
        var random = new Random(seed);
        var sw = Stopwatch.StartNew();
        var closed = 0;
        for (var round = 0; round < 40; round++)
        {
            using var fuzz = new Socket(SocketType.Stream, ProtocolType.Tcp) { NoDelay = true };
            await fuzz.ConnectAsync(new IPEndPoint(IPAddress.Loopback, server.Port));
            for (var i = 0; i < 25; i++)
            {
                var packet = Next(random);
                try
                {
                    fuzz.Send(packet);
                }
                catch (SocketException)
                {
                    closed++;
                    break;
                }

                // Drain whatever comes back without waiting for it.
                await Task.Delay(random.Next(2) == 0 ? 0 : 1);
                while (fuzz.Available > 0)
                {
                    fuzz.Receive(new byte[4096]);
                }
            }

            witness.GetResponse("VER").Should().Equal(Encoding.ASCII.GetBytes("1.947\r\x06"), "round {0} of seed {1}", round, seed);
        }

        sw.Elapsed.Should().BeLessThan(TimeSpan.FromSeconds(30), "the fuzz must not hang the server");
        server.PacketsServed.Should().BeGreaterThan(40);
        (server.MalformedPackets + closed).Should().BeGreaterThan(0, "random bytes must have hit the malformed-packet path");
    }

    private static byte[] Next(Random random)
    {
        switch (random.Next(4))
        {
            case 0:
                {
                    var junk = new byte[random.Next(1, 40)];
                    random.NextBytes(junk);
                    return junk;
                }

            case 1:
                {
                    // A valid packet with a few bytes flipped (header included).
                    var p = (byte[])ValidPackets[random.Next(ValidPackets.Length)].Clone();
                    for (var k = random.Next(1, 3); k > 0; k--)
                    {
                        p[random.Next(p.Length)] ^= (byte)(1 << random.Next(8));
                    }

                    return p;
                }

            case 2:
                {
                    // A valid packet cut short.
                    var p = ValidPackets[random.Next(ValidPackets.Length)];
                    return p[..random.Next(1, p.Length)];
                }

            default:
                return ValidPackets[random.Next(ValidPackets.Length)];
        }
    }
}
