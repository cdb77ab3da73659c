using System.Net;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>Transcripts over TCP with the real simulator engine behind the server: command in, exact bytes out.</summary>
public sealed class SimulatorOverTcpTests : IAsyncLifetime
{
    private readonly PmacSimulator _sim = new(new SimOptions { Speed = SimSpeed.Instant });
    private PmacTcpServer _server = null!;
    private int _ports;

    public Task InitializeAsync()
    {
        _server = new PmacTcpServer(() => _sim.OpenPort($"tcp{Interlocked.Increment(ref _ports)}"), new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        _server.Start();
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _server.DisposeAsync();
        _sim.Dispose();
    }

    private static byte[] A(string s) => Encoding.ASCII.GetBytes(s);

    [Fact]
    public void Online_commands_answer_with_the_controller_framing()
    {
        using var w = new TcpWire(_server.Port);
        w.GetResponse("VER").Should().Equal(A("1.947\r\x06"));
        w.GetResponse("p500=80").Should().Equal(A("\x06"));
        w.GetResponse("P500").Should().Equal(A("80\r\x06"));
        w.GetResponse("P500 VER").Should().Equal(A("80\r1.947\r\x06"));
        w.GetResponse("FOO").Should().Equal(A("\aERR003\r"));
    }

    [Fact]
    public void Each_connection_is_its_own_port_so_a_second_open_buffer_is_err007()
    {
        using var a = new TcpWire(_server.Port);
        using var b = new TcpWire(_server.Port);
        a.GetResponse("OPEN PROG 5 CLEAR").Should().Equal(A("\x06"));
        b.GetResponse("OPEN PROG 6 CLEAR").Should().Equal(A("\aERR007\r"));
        a.GetResponse("CLOSE").Should().Equal(A("\x06"));
        b.GetResponse("OPEN PROG 6 CLEAR").Should().Equal(A("\x06"));
        b.GetResponse("CLOSE").Should().Equal(A("\x06"));
    }

    [Fact]
    public void Writebuffer_into_an_open_program_stops_at_the_refused_line()
    {
        using var w = new TcpWire(_server.Port);
        w.GetResponse("OPEN PROG 7 CLEAR").Should().Equal(A("\x06"));
        var data = A("LINEAR\0X10 Y5\0FOO BAR\0X20\0");
        w.Send(TcpWire.Packet(VrPmac.Download, VrPmac.WriteBuffer, 0, (ushort)data.Length, data));
        w.ReceiveExactly(4).Should().Equal([2, 0, 3, 0x80]);
        w.GetResponse("CLOSE").Should().Equal(A("\x06"));
        var listing = Encoding.ASCII.GetString(w.GetResponse("LIST PROG 7"));
        listing.Should().NotContain("X20", "nothing after the refused line is stored");
        listing.Should().EndWith("\x06");
        listing.Split('\r', StringSplitOptions.RemoveEmptyEntries).Should().HaveCount(3, "two lines and the ACK");
    }
}
