using System.Net;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>The host that <c>pmacstream sim</c> runs: options in, a served simulator with its clock out, a log on stop.</summary>
public sealed class SimHostTests : IDisposable
{
    private readonly TestFolder _temp = new("simhost");

    public void Dispose() => _temp.Dispose();

    private SimHostOptions Tcp(string? log = null) => new()
    {
        Simulator = new SimOptions { Speed = SimSpeed.Instant },
        TcpEndPoint = new IPEndPoint(IPAddress.Loopback, 0),
        ExecutedLogPath = log,
    };

    [Fact]
    public void Nothing_to_serve_is_refused()
    {
        var act = () => new SimHost(new SimHostOptions { TcpEndPoint = null, SerialPath = null });
        act.Should().Throw<ArgumentException>().WithMessage("nothing to serve*");
    }

    [Fact]
    public async Task Serves_ethernet_on_the_chosen_port_runs_moves_on_its_clock_and_writes_the_log_on_stop()
    {
        var log = Path.Combine(_temp.Path, "executed.csv");
        await using var host = new SimHost(Tcp(log));
        host.TcpEndPoint.Should().BeNull("nothing is bound before Start");
        host.Start();
        host.TcpEndPoint!.Port.Should().BeGreaterThan(0, "port 0 picks a free port");

        await using (var eth = new EthernetConnection(new EthernetOptions { Port = host.TcpEndPoint.Port, Timeout = TimeSpan.FromSeconds(5) }))
        {
            (await eth.GetResponseAsync("VER")).Should().Be("1.947");
            await eth.DownloadAsync(["&1 B0", "OPEN ROT", "M0==7 LINEAR X10 F600", "M0==8 X20", "CLOSE"]);
            (await eth.GetResponseAsync("&1 R")).Should().BeEmpty();

            // The host's clock runs the moves without the test stepping it.
            for (var i = 0; i < 500 && host.Simulator.Counters.MovesExecuted < 2; i++)
            {
                await Task.Delay(10);
            }
        }

        var counters = await host.StopAsync();
        counters.MovesExecuted.Should().Be(2);
        File.ReadAllLines(log).Skip(1).Select(l => l.Split(',')[1]).Should().Equal("7", "8");
        (await host.StopAsync()).Should().Be(counters, "a second stop changes nothing");
    }

    [Fact]
    public async Task Ethernet_is_one_controller_port_shared_by_every_connection()
    {
        await using var host = new SimHost(Tcp());
        host.Start();
        var options = new EthernetOptions { Port = host.TcpEndPoint!.Port, Timeout = TimeSpan.FromSeconds(5) };
        await using var first = new EthernetConnection(options);
        (await first.GetResponseAsync("OPEN PROG 5 CLEAR")).Should().BeEmpty();
        await first.DisposeAsync();

        // A host that reconnects after a crash can close the buffer the old connection left open.
        await using var second = new EthernetConnection(options);
        (await second.GetResponseAsync("CLOSE")).Should().BeEmpty();
        (await second.GetResponseAsync("OPEN PROG 6 CLEAR")).Should().BeEmpty();
        (await second.GetResponseAsync("CLOSE")).Should().BeEmpty();
    }

    [SkippableFact]
    public async Task A_serial_line_and_ethernet_reach_the_same_controller()
    {
        using var pair = SocatPair.Start();
        await using var host = new SimHost(Tcp() with { SerialPath = pair.A, Serial = new SerialSettings(115200) });
        host.Start();
        await using var eth = new EthernetConnection(new EthernetOptions { Port = host.TcpEndPoint!.Port, Timeout = TimeSpan.FromSeconds(5) });
        await using var serial = new SerialConnection(new SerialOptions { PortName = pair.B, Settings = new SerialSettings(115200), Timeout = TimeSpan.FromSeconds(5) });
        (await eth.GetResponseAsync("P500=80")).Should().BeEmpty();
        (await serial.GetResponseAsync("P500")).Should().Be("80");
        (await serial.GetResponseAsync("OPEN PROG 7 CLEAR")).Should().BeEmpty();
        var act = () => eth.GetResponseAsync("OPEN PROG 8 CLEAR");
        (await act.Should().ThrowAsync<PmacErrorException>()).Which.Number.Should().Be(7, "the serial line has its own port, with a buffer open");
        (await serial.GetResponseAsync("CLOSE")).Should().BeEmpty();
    }

    [Fact]
    public async Task A_busy_port_is_a_socket_error_and_the_host_still_stops_cleanly()
    {
        await using var first = new SimHost(Tcp());
        first.Start();
        await using var second = new SimHost(Tcp() with { TcpEndPoint = first.TcpEndPoint });
        var act = second.Start;
        act.Should().Throw<System.Net.Sockets.SocketException>();
        (await second.StopAsync()).MovesExecuted.Should().Be(0);
        act.Should().Throw<InvalidOperationException>("a stopped host is not started again");
    }
}
