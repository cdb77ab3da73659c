using System.Diagnostics;
using System.Net;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>
/// What a hostile or careless client can no longer do to the simulator's Ethernet side: grow its memory with replies
/// it never fetches, or lock other clients out with connections it leaves open.
/// </summary>
public sealed class ServerLimitsTests
{
    private static byte[] A(string s) => Encoding.ASCII.GetBytes(s);

    private static PmacTcpServer Start(ScriptedController controller, PmacTcpServerOptions options)
    {
        var server = new PmacTcpServer(controller.OpenPort, options with { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        return server;
    }

    /// <summary>True when the server has closed the connection (readable with nothing to read), without blocking long.</summary>
    private static bool Closed(TcpWire w) => w.Socket.Poll(200_000, System.Net.Sockets.SelectMode.SelectRead) && w.Socket.Available == 0;

    private static void SendLine(TcpWire w, string command)
    {
        var data = A(command);
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.SendLine, 0, (ushort)data.Length, data));
        w.ReceiveExactly(1);
    }

    [Fact]
    public async Task Sendline_replies_never_fetched_are_capped_and_the_oldest_are_dropped()
    {
        var controller = new ScriptedController();
        await using var server = Start(controller, new PmacTcpServerOptions { MaxPendingReplyBytes = 1024 });
        using var w = new TcpWire(server.Port);
        for (var i = 1; i <= 3000; i++)
        {
            SendLine(w, $"P1={i}");
            SendLine(w, "P1");
        }

        // Fetch everything left: only the newest replies, within the cap, the last one last.
        var fetched = new List<string>();
        while (true)
        {
            w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.GetLine, 0, 1400, []));
            var reply = w.ReceiveReply();
            if (reply is [0])
            {
                break;
            }

            fetched.Add(Encoding.ASCII.GetString(reply));
        }

        fetched.Sum(r => r.Length).Should().BeLessThanOrEqualTo(1024);
        fetched[^1].Should().Be("3000\r\x06");
        var values = fetched.Where(r => r.Length > 1).Select(r => int.Parse(r.TrimEnd('\r', '\x06'))).ToList();
        values.Should().BeInAscendingOrder().And.OnlyContain(v => v > 2800, "the oldest replies were dropped, not the newest");
        server.DroppedReplies.Should().Be(6000 - fetched.Count);
    }

    [Fact]
    public void The_reply_buffer_drops_whole_replies_and_gives_its_memory_back()
    {
        var pending = new PendingReplies(100);
        for (var i = 0; i < 50; i++)
        {
            pending.Add(A($"{i:00}\r\x06"));
        }

        pending.Count.Should().Be(100, "25 replies of 4 bytes fill it");
        pending.DroppedReplies.Should().Be(25);
        var first = new byte[10];
        Encoding.ASCII.GetString(first, 0, pending.Take(first)).Should().Be("25\r\x06", "the 25 oldest went, whole");

        var big = new PendingReplies(1 << 20);
        big.Add(new byte[900_000]);
        big.StorageBytes.Should().BeGreaterThanOrEqualTo(900_000);
        var sink = new byte[VrPmac.MaxReply];
        while (big.Count > 0)
        {
            big.Take(sink);
        }

        big.StorageBytes.Should().BeLessThan(4096, "an emptied buffer is given back");
    }

    [Fact]
    public async Task An_idle_connection_is_closed_after_the_idle_timeout()
    {
        // A timeout well above the busy client's 100 ms pace, so a loaded machine's stalls do not make it look idle.
        await using var server = Start(new ScriptedController(), new PmacTcpServerOptions { IdleTimeout = TimeSpan.FromSeconds(3) });
        using var idle = new TcpWire(server.Port);
        using var busy = new TcpWire(server.Port);
        var sw = Stopwatch.StartNew();
        while (server.IdleClosed == 0 && sw.Elapsed < TimeSpan.FromSeconds(20))
        {
            busy.GetResponse("VER").Should().Equal(A("1.947\r\x06"));
            await Task.Delay(100);
        }

        sw.Elapsed.Should().BeGreaterThan(TimeSpan.FromSeconds(2.9), "not before the idle timeout");
        idle.IsClosedByServer().Should().BeTrue();
        busy.GetResponse("VER").Should().Equal(A("1.947\r\x06"), "a client that talks is never idle");
        server.IdleClosed.Should().Be(1);
    }

    [Fact]
    public async Task Idle_connections_filling_every_slot_do_not_lock_out_a_new_client()
    {
        await using var server = Start(new ScriptedController(), new PmacTcpServerOptions { MaxClients = 4, EvictIdleAfter = TimeSpan.FromMilliseconds(100) });
        var squatters = Enumerable.Range(0, 4).Select(_ => new TcpWire(server.Port)).ToList();
        foreach (var s in squatters)
        {
            s.GetResponse("VER");
        }

        await Task.Delay(300);
        for (var i = 0; i < 3; i++)
        {
            using var client = new TcpWire(server.Port);
            client.GetResponse("VER").Should().Equal(A("1.947\r\x06"), "client {0} is served", i);
        }

        server.Evicted.Should().BeGreaterThanOrEqualTo(1);
        server.Refused.Should().Be(0);
        squatters.Count(Closed).Should().BeInRange(1, 3, "the idlest squatters made room, one per new client at most");
        squatters.ForEach(s => s.Dispose());
    }

    [Fact]
    public async Task Every_slot_busy_within_the_eviction_time_refuses_a_new_client()
    {
        await using var server = Start(new ScriptedController(), new PmacTcpServerOptions { MaxClients = 2, EvictIdleAfter = TimeSpan.FromHours(1) });
        using var a = new TcpWire(server.Port);
        using var b = new TcpWire(server.Port);
        a.GetResponse("VER");
        b.GetResponse("VER");
        using var c = new TcpWire(server.Port);

        c.IsClosedByServer().Should().BeTrue();
        server.Refused.Should().Be(1);
        a.GetResponse("VER").Should().Equal(A("1.947\r\x06"));
    }

    [Fact]
    public void Only_loopback_addresses_count_as_not_exposed()
    {
        SimHost.IsExposed(new IPEndPoint(IPAddress.Loopback, 1025)).Should().BeFalse();
        SimHost.IsExposed(new IPEndPoint(IPAddress.IPv6Loopback, 1025)).Should().BeFalse();
        SimHost.IsExposed(new IPEndPoint(IPAddress.Any, 1025)).Should().BeTrue();
        SimHost.IsExposed(new IPEndPoint(IPAddress.Parse("10.0.0.5"), 1025)).Should().BeTrue();
    }
}
