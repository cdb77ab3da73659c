using System.Net;
using PmacStream.Cli;
using PmacStream.Cli.Commands;
using PmacStream.Pmac;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>How `pmacstream sim` reads its address, and what it says when it is reachable from other machines.</summary>
public sealed class SimCliServerTests
{
    [Theory]
    [InlineData("44887", "127.0.0.1", 44887)]
    [InlineData("0", "127.0.0.1", 0)]
    [InlineData("127.0.0.1", "127.0.0.1", 1025)]
    [InlineData("localhost:5", "127.0.0.1", 5)]
    [InlineData(":7", "127.0.0.1", 7)]
    [InlineData("0.0.0.0:1025", "0.0.0.0", 1025)]
    [InlineData("[::1]:99", "::1", 99)]
    [InlineData("::1", "::1", 1025)]
    public void A_bare_number_is_a_port_on_loopback_never_an_address(string spec, string address, int port)
    {
        SimCommand.ParseEndPoint(spec).Should().Be(new IPEndPoint(IPAddress.Parse(address), port));
    }

    [Theory]
    [InlineData("1.2")]
    [InlineData("1.2:80")]
    [InlineData("example.org:1025")]
    [InlineData("127.0.0.1:99999")]
    [InlineData("127.0.0.1:-1")]
    public void Anything_else_is_refused_with_the_forms_it_takes(string spec)
    {
        var act = () => SimCommand.ParseEndPoint(spec);
        act.Should().Throw<CliException>().WithMessage($"--tcp '{spec}': *");
    }

    [Fact]
    public async Task A_port_alone_serves_loopback_without_a_warning()
    {
        using var sim = SimProcess.Start("--tcp", "0", "--speed", "instant");
        sim.Output.Should().ContainMatch("pmacstream sim: listening on tcp 127.0.0.1:*");
        await using (var eth = new EthernetConnection(new EthernetOptions { Port = sim.Port, Timeout = TimeSpan.FromSeconds(5) }))
        {
            (await eth.GetResponseAsync("VER")).Should().Be("1.947");
        }

        sim.Terminate().Should().Be(0);
        sim.Output.Should().NotContain(l => l.Contains("warning", StringComparison.Ordinal));
    }

    [Fact]
    public void Every_interface_is_served_only_with_a_warning_that_a_pmac_port_has_no_authentication()
    {
        using var sim = SimProcess.Start("--tcp", "0.0.0.0:0", "--speed", "instant");
        sim.Terminate().Should().Be(0);
        sim.Output.Should().Contain(l => l.StartsWith("pmacstream sim: warning: 0.0.0.0:0 is reachable from other machines and a PMAC port has no authentication", StringComparison.Ordinal));
    }
}
