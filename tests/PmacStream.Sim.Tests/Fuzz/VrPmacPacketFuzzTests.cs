using System.Buffers.Binary;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;
using Xunit.Abstractions;

namespace PmacStream.Sim.Tests.Fuzz;

/// <summary>
/// Fuzz target of the simulator's VR_PMAC packet parser (<see cref="VrPmacSession"/>), in process and without
/// sockets: seeded streams of valid, mutated, cut and random packets, read in random pieces. The only outcomes
/// allowed are the documented ones (served until the client closes, or the connection closed as malformed); any
/// exception, an engine fault, reply bytes kept beyond the cap, or an input that does not finish fails, naming the
/// seed and the input.
/// </summary>
public sealed class VrPmacPacketFuzzTests(ITestOutputHelper output)
{
    private static readonly byte[][] Valid =
    [
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "VER"),
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "I3=2 I6=1 ??"),
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "&1 B0 OPEN ROT"),
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "M0==12 LINEAR X10 Y5 F(P500)"),
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "CLOSE"),
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "LIST PROG 1000"),
        Packet(VrPmac.Download, VrPmac.GetResponse, 0, "P1..20"),
        Packet(VrPmac.Download, VrPmac.SendLine, 0, "P500=80"),
        Packet(VrPmac.Download, VrPmac.SendLine, 0, "M0"),
        Packet(VrPmac.Upload, VrPmac.GetLine, 0, string.Empty),
        Packet(VrPmac.Upload, VrPmac.ReadReady, 0, string.Empty),
        Packet(VrPmac.Upload, VrPmac.GetBuffer, 0, string.Empty),
        Packet(VrPmac.Download, VrPmac.Flush, 0, string.Empty),
        Packet(VrPmac.Upload, VrPmac.CtrlResponse, 0x0200, string.Empty),
        Packet(VrPmac.Upload, VrPmac.CtrlResponse, 0x0006, string.Empty),
        Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, "OPEN PROG 7 CLEAR\0X1\0Y2\0BAD\0CLOSE\0"),
        Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, "&1 B0\0OPEN ROT\0M0==1 X1\0CLOSE\0"),
    ];

    private static readonly byte[] Special = [0x00, 0xFF, VrPmac.Download, VrPmac.Upload, 0x0D, 0x06, 0x07, 0x0A, 0x18, 0x80, 0x7F, (byte)'&'];

    [Fact]
    public void The_packet_parser_survives_seeded_mutated_streams_with_the_real_engine_behind()
    {
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Instant, RetainExecutedMoves = false });
        var ports = new List<SimPort>();
        var report = Run(new FuzzBudget(2026), () =>
        {
            var port = sim.OpenPort("fuzz");
            ports.Add(port);
            return port;
        });
        foreach (var p in ports)
        {
            p.Dispose();
        }

        sim.InternalFaults.Should().Be(0, "no input may reach a bug in the engine");
        output.WriteLine(report);
    }

    [Fact]
    public void The_packet_parser_survives_seeded_mutated_streams_with_a_scripted_controller()
    {
        var controller = new ScriptedController();
        output.WriteLine(Run(new FuzzBudget(2027), controller.OpenPort));
    }

    private static string Run(FuzzBudget budget, Func<IPmacPortEndpoint> ports)
    {
        var random = new Random(budget.Seed);
        var options = new PmacTcpServerOptions { MaxPendingReplyBytes = 2048, PacketTimeout = TimeSpan.FromSeconds(1), IdleTimeout = TimeSpan.FromSeconds(1) };
        var counters = new VrPmacCounters();
        var ends = new Dictionary<SessionEnd, long>();
        long inputs = 0, bytes = 0;
        while (budget.Left)
        {
            var input = NextInput(random);
            var stream = new ByteStreamScript(input, new Random(random.Next()));
            var session = new VrPmacSession(stream, ports(), new object(), options, counters, (int)(inputs % 1000));
            var run = Task.Run(() => session.RunAsync(CancellationToken.None));
            var what = $"seed {budget.Seed}, input {inputs}: {Convert.ToHexString(input)}";
            try
            {
                run.Wait(FuzzBudget.HangLimit).Should().BeTrue($"the input must finish ({what})");
            }
            catch (AggregateException e)
            {
                throw new Xunit.Sdk.XunitException($"{e.InnerException?.GetType().Name}: {e.InnerException?.Message} ({what})");
            }

            session.PendingBytes.Should().BeLessThanOrEqualTo(options.MaxPendingReplyBytes + VrPmac.MaxData * 64, what);
            ends[run.Result] = ends.GetValueOrDefault(run.Result) + 1;
            inputs++;
            bytes += input.Length;
        }

        inputs.Should().BeGreaterThan(100, "the budget must try a useful number of inputs");
        ends.GetValueOrDefault(SessionEnd.Malformed).Should().BeGreaterThan(0, "mutations must reach the malformed-packet path");
        ends.GetValueOrDefault(SessionEnd.ClientClosed).Should().BeGreaterThan(0, "valid streams must be served to their end");
        return $"seed {budget.Seed}: {inputs} inputs ({bytes} bytes, {counters.Packets} packets answered) in {budget.Elapsed.TotalSeconds:0.0} s; "
            + string.Join(", ", ends.OrderBy(e => e.Key).Select(e => $"{e.Key} {e.Value}")) + "; 0 exceptions, 0 hangs";
    }

    private static byte[] NextInput(Random random)
    {
        var packets = new List<byte[]>();
        for (var n = random.Next(1, 12); n > 0; n--)
        {
            packets.Add(random.Next(10) switch
            {
                < 4 => Valid[random.Next(Valid.Length)],
                < 8 => Mutate(Valid[random.Next(Valid.Length)], random),
                8 => Junk(random),
                _ => Mutate(Mutate(Valid[random.Next(Valid.Length)], random), random),
            });
        }

        var all = packets.SelectMany(p => p).ToArray();
        return random.Next(8) == 0 && all.Length > 1 ? all[..random.Next(1, all.Length)] : all;
    }

    private static byte[] Mutate(byte[] packet, Random random)
    {
        if (packet.Length < VrPmac.HeaderSize)
        {
            return [.. packet, .. Junk(random)]; // already cut: grow it instead
        }

        var p = new List<byte>(packet);
        switch (random.Next(7))
        {
            case 0:
                p[random.Next(p.Count)] ^= (byte)(1 << random.Next(8));
                break;
            case 1:
                p[random.Next(p.Count)] = Special[random.Next(Special.Length)];
                break;
            case 2:
                {
                    // wLength that lies: too long, too short, zero, the limit and one past it.
                    var lengths = new ushort[] { 0, 1, 7, VrPmac.MaxWriteBuffer, VrPmac.MaxWriteBuffer + 1, VrPmac.MaxData, VrPmac.MaxData + 1, ushort.MaxValue, (ushort)random.Next(65536) };
                    var bytes = p.ToArray();
                    BinaryPrimitives.WriteUInt16BigEndian(bytes.AsSpan(6), lengths[random.Next(lengths.Length)]);
                    return bytes;
                }

            case 3:
                p.RemoveRange(random.Next(p.Count), 1);
                break;
            case 4:
                p.InsertRange(random.Next(p.Count + 1), Junk(random));
                break;
            case 5:
                {
                    // A data part of random bytes (high bits, control characters, NULs) with its true length.
                    var data = new byte[random.Next(0, VrPmac.MaxData + 1)];
                    random.NextBytes(data);
                    var bytes = new byte[VrPmac.HeaderSize + data.Length];
                    packet.AsSpan(0, VrPmac.HeaderSize).CopyTo(bytes);
                    BinaryPrimitives.WriteUInt16BigEndian(bytes.AsSpan(6), (ushort)data.Length);
                    data.CopyTo(bytes.AsSpan(VrPmac.HeaderSize));
                    return bytes;
                }

            default:
                p[1] = (byte)random.Next(256); // any request code under a valid type
                break;
        }

        return [.. p];
    }

    private static byte[] Junk(Random random)
    {
        var junk = new byte[random.Next(1, 64)];
        random.NextBytes(junk);
        return junk;
    }

    private static byte[] Packet(byte type, byte request, ushort wValue, string data)
    {
        var bytes = Encoding.ASCII.GetBytes(data);
        var p = new byte[VrPmac.HeaderSize + bytes.Length];
        VrPmac.WriteHeader(p, type, request, wValue, 0, (ushort)(type == VrPmac.Upload ? 1400 : bytes.Length));
        bytes.CopyTo(p.AsSpan(VrPmac.HeaderSize));
        return p;
    }
}
