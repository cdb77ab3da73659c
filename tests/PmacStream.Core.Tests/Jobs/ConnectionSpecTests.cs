using PmacStream.Hmi;
using PmacStream.Pmac;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>One spelling of a controller link for the command line, the HMI's panel and job records.</summary>
public class ConnectionSpecTests
{
    [Theory]
    [InlineData("sim", LinkKind.Simulator, "sim")]
    [InlineData("tcp://10.0.0.5", LinkKind.Ethernet, "tcp://10.0.0.5:1025")]
    [InlineData("10.0.0.5:2000", LinkKind.Ethernet, "tcp://10.0.0.5:2000")]
    [InlineData("serial:/dev/ttyUSB0@115200,even", LinkKind.Serial, "serial:/dev/ttyUSB0@115200,even")]
    [InlineData("serial:COM3", LinkKind.Serial, "serial:COM3@38400")]
    [InlineData("pcomm32:1", LinkKind.Pcomm32, "pcomm32:1")]
    public void Specs_parse_and_spell_back_canonically(string spec, LinkKind kind, string canonical)
    {
        var parsed = ConnectionSpec.Parse(spec);
        parsed.Kind.Should().Be(kind);
        parsed.ToString().Should().Be(canonical);
        ConnectionSpec.Parse(canonical).Should().Be(parsed, "the canonical spelling reads back to the same link");
    }

    [Fact]
    public void The_hmi_panel_and_the_command_line_spell_a_link_the_same_way()
    {
        new ConnectionSettings(DeviceKind.Ethernet, EthernetAddress: "192.168.0.200").ToSpec().Should().Be(ConnectionSpec.Ethernet("192.168.0.200"));
        new ConnectionSettings(DeviceKind.Ethernet, EthernetAddress: " 10.1.1.1:1026 ").ToSpec().ToString().Should().Be("tcp://10.1.1.1:1026");
        new ConnectionSettings(DeviceKind.Serial, SerialPort: "COM4", Baud: 9600).ToSpec().Should().Be(ConnectionSpec.Parse("serial:COM4@9600"));
        new ConnectionSettings(DeviceKind.Pcomm32, PcommDevice: 2).ToSpec().Should().Be(ConnectionSpec.Parse("pcomm32:2"));
        new ConnectionSettings(DeviceKind.Simulator).ToSpec().IsSimulator.Should().BeTrue();
    }

    [Theory]
    [InlineData("44887", "tcp://127.0.0.1:44887")]
    [InlineData("tcp://44887", "tcp://127.0.0.1:44887")]
    public void A_bare_number_is_a_port_on_this_machine_never_an_address(string address, string canonical)
    {
        // Before, "44887" was a host the resolver read as 0.0.175.87: a stream went to whatever listened there.
        ConnectionSpec.Ethernet(address).ToString().Should().Be(canonical);
    }

    [Theory]
    [InlineData("44887:1025", "'44887' is a number, not a host")]
    [InlineData("99999", "port '99999' is not 1..65535")]
    public void A_number_with_a_port_or_beyond_the_ports_is_refused(string address, string why)
    {
        var act = () => ConnectionSpec.Ethernet(address);
        act.Should().Throw<FormatException>().Which.Message.Should().Contain(why);
    }

    [Fact]
    public void Only_the_host_opens_the_built_in_simulator()
    {
        var act = () => PmacConnections.Create("sim");
        act.Should().Throw<NotSupportedException>();
    }
}
