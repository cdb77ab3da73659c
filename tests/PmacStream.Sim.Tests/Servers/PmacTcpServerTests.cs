using System.Net;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Servers;

public sealed class PmacTcpServerTests : IAsyncLifetime
{
    private readonly ScriptedController _controller = new();
    private PmacTcpServer _server = null!;

    public Task InitializeAsync()
    {
        _server = new PmacTcpServer(_controller.OpenPort, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0), PacketTimeout = TimeSpan.FromMilliseconds(500) });
        _server.Start();
        return Task.CompletedTask;
    }

    public async Task DisposeAsync() => await _server.DisposeAsync();

    private static byte[] A(string s) => Encoding.ASCII.GetBytes(s);

    [Fact]
    public void Port_zero_binds_a_free_port()
    {
        _server.Port.Should().BeGreaterThan(0);
        _server.LocalEndPoint.Address.Should().Be(IPAddress.Loopback);
    }

    [Fact]
    public void Getresponse_returns_the_framed_reply_bytes()
    {
        using var w = new TcpWire(_server.Port);
        w.GetResponse("VER").Should().Equal(A("1.947\r\x06"));
        w.GetResponse("P500=80").Should().Equal([0x06]);
        w.GetResponse("P500").Should().Equal(A("80\r\x06"));
        w.GetResponse("BAD").Should().Equal(A("\aERR003\r"));
    }

    [Fact]
    public void Getresponse_ignores_a_trailing_cr_in_the_command()
    {
        using var w = new TcpWire(_server.Port);
        w.GetResponse("VER\r").Should().Equal(A("1.947\r\x06"));
    }

    [Fact]
    public void Long_replies_continue_through_readready_and_getbuffer()
    {
        using var w = new TcpWire(_server.Port);
        var first = w.GetResponse("LONG 3000");
        first.Should().HaveCount(VrPmac.MaxReply);
        var all = new List<byte>(first);
        while (true)
        {
            w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []));
            var ready = w.ReceiveExactly(2);
            if (ready[0] == 0)
            {
                break;
            }

            w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.GetBuffer, 0, VrPmac.MaxReply, []));
            all.AddRange(w.ReceiveReply());
        }

        all.Should().HaveCount(3002);
        all[^1].Should().Be(0x06);
        all[^2].Should().Be(0x0D);
        all[1400].Should().Be((byte)('A' + (1400 % 26)));
    }

    [Fact]
    public void Sendline_then_getline_returns_the_reply()
    {
        using var w = new TcpWire(_server.Port);
        var data = A("VER");
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.SendLine, 0, (ushort)data.Length, data));
        w.ReceiveExactly(1).Should().Equal([VrPmac.SendLine]);
        w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []));
        w.ReceiveExactly(2).Should().Equal([1, 0]);
        w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.GetLine, 0, VrPmac.MaxReply, []));
        w.ReceiveReply().Should().Equal(A("1.947\r\x06"));
        w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []));
        w.ReceiveExactly(2).Should().Equal([0, 0]);
    }

    [Fact]
    public void Flush_discards_pending_replies_and_tells_the_engine()
    {
        using var w = new TcpWire(_server.Port);
        var data = A("VER");
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.SendLine, 0, (ushort)data.Length, data));
        w.ReceiveExactly(1);
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.Flush, 0, 0, []));
        w.ReceiveExactly(1).Should().Equal([VrPmac.Flush]);
        _controller.Flushes.Should().Be(1);
        w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []));
        w.ReceiveExactly(2).Should().Equal([0, 0]);
    }

    [Theory]
    [InlineData((ushort)0x0200)]
    [InlineData((ushort)0x0002)]
    public void Ctrl_response_accepts_the_character_in_either_byte_of_wvalue(ushort wValue)
    {
        using var w = new TcpWire(_server.Port);
        w.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.CtrlResponse, wValue, 0, []));
        var reply = new byte[64];
        var n = w.Socket.Receive(reply);
        reply[..n].Should().Equal(A("812000804001\r"));
    }

    [Fact]
    public void Writebuffer_runs_every_line_and_answers_a_zero_status()
    {
        using var w = new TcpWire(_server.Port);
        var data = A("LINEAR\0X1\0X2\0");
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, (ushort)data.Length, data));
        w.ReceiveExactly(4).Should().Equal([0, 0, 0, 0]);
        _controller.Executed.Should().Equal("LINEAR", "X1", "X2");
    }

    [Fact]
    public void Writebuffer_stops_at_the_refused_line_and_names_it_in_the_status()
    {
        using var w = new TcpWire(_server.Port);
        var data = A("X1\0X2\0BAD LINE\0X4\0X5\0");
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, (ushort)data.Length, data));
        w.ReceiveExactly(4).Should().Equal([2, 0, 3, 0x80]);
        _controller.Executed.Should().Equal("X1", "X2");
    }

    [Fact]
    public void Writebuffer_over_1024_bytes_is_refused_without_running_anything()
    {
        using var w = new TcpWire(_server.Port);
        var data = A(string.Concat(Enumerable.Repeat("X1234567\0", 120)));
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, (ushort)data.Length, data));
        w.ReceiveExactly(4).Should().Equal([0, 0, 3, 0x80]);
        _controller.Executed.Should().BeEmpty();
    }

    [Fact]
    public void Unknown_request_type_closes_only_that_connection()
    {
        using var bad = new TcpWire(_server.Port);
        using var good = new TcpWire(_server.Port);
        bad.Send([0x55, 0xBF, 0, 0, 0, 0, 0, 0]);
        bad.IsClosedByServer().Should().BeTrue();
        good.GetResponse("VER").Should().Equal(A("1.947\r\x06"));
        _server.MalformedPackets.Should().Be(1);
    }

    [Fact]
    public void Truncated_packet_closes_the_connection_after_the_packet_timeout()
    {
        using var w = new TcpWire(_server.Port);
        w.Send([VrPmac.Download, VrPmac.GetResponse, 0, 0, 0, 0, 0, 10, (byte)'V']);
        w.IsClosedByServer().Should().BeTrue();
        _server.MalformedPackets.Should().Be(1);
    }

    [Fact]
    public void Oversized_wlength_closes_the_connection()
    {
        using var w = new TcpWire(_server.Port);
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.GetResponse, 0, 60000, []));
        w.IsClosedByServer().Should().BeTrue();
    }

    [Fact]
    public async Task Each_client_has_its_own_pending_replies()
    {
        using var a = new TcpWire(_server.Port);
        using var b = new TcpWire(_server.Port);
        var data = A("VER");
        a.Send(TcpWire.Packet(VrPmac.Download, VrPmac.SendLine, 0, (ushort)data.Length, data));
        a.ReceiveExactly(1);
        b.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []));
        b.ReceiveExactly(2).Should().Equal([0, 0]);
        a.Send(TcpWire.Packet(VrPmac.Upload, VrPmac.ReadReady, 0, 2, []));
        a.ReceiveExactly(2).Should().Equal([1, 0]);
        await Task.Yield();
        _server.ClientCount.Should().Be(2);
    }

    [Fact]
    public async Task Stop_closes_clients_and_the_listener()
    {
        using var w = new TcpWire(_server.Port);
        w.GetResponse("VER");
        var port = _server.Port;
        await _server.StopAsync();
        w.IsClosedByServer().Should().BeTrue();
        var connect = () => new TcpWire(port);
        connect.Should().Throw<System.Net.Sockets.SocketException>();
    }
}
