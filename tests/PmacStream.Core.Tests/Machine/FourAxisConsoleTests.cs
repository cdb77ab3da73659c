using System.Globalization;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Machine;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Core.Tests.Machine;

/// <summary>
/// The machine's axes from the profile (<c>"axes"</c>): a 4-axis machine with a rotary A on motor 4 at 100 counts per
/// degree; the built-in profiles keep X Y Z on motors 1-3.
/// </summary>
public sealed class FourAxisConsoleTests : IAsyncLifetime
{
    private readonly TestFolder _temp = new("console-4axis");
    private readonly PmacSimulator _sim = new(new SimOptions { StartHomed = false });
    private ControllerLink _controller = null!;
    private MachineConsole _console = null!;

    /// <summary>The default profile with X Y Z on motors 1-3 and A (rotary, degrees) on motor 4.</summary>
    internal static MachineProfile FourAxis()
    {
        var json = JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["name"] = "four-axis";
        json["axes"] = JsonNode.Parse("""[{"name":"X","motor":1},{"name":"Y","motor":2},{"name":"Z","motor":3},{"name":"A","motor":4,"countsPerUnit":100,"rotary":true}]""");
        return MachineProfile.Parse(json.ToJsonString(), "four-axis.json");
    }

    public async Task InitializeAsync()
    {
        var profile = FourAxis();
        var service = new JobService(new JobServiceOptions
        {
            Simulator = SimRig.BuiltIn(_sim),
            JobDatabase = Path.Combine(_temp.Path, "jobs.db"),
            Rules = new MachineRules(MachineAxis.Of(profile)),
        });
        _controller = await service.ConnectAsync(ConnectionSpec.Simulator, profile);
        _console = new MachineConsole(service, _controller, new MachineConsoleOptions { Axes = MachineAxis.Of(profile), CoordinateSystem = profile.CoordinateSystem, Profile = profile });
    }

    public async Task DisposeAsync()
    {
        await _controller.DisposeAsync();
        _sim.Dispose();
        _temp.Dispose();
    }

    private async Task<double> MotorAsync(int motor)
    {
        var reply = await _controller.Connection.GetResponseAsync($"#{motor}P");
        return double.Parse(reply.Trim().TrimEnd('\u0006').Trim(), CultureInfo.InvariantCulture);
    }

    [Fact]
    public void The_profile_lists_the_axes_and_a_built_in_profile_keeps_X_Y_Z_on_motors_1_to_3()
    {
        var axes = MachineAxis.Of(FourAxis());
        axes.Select(a => (a.Name, a.Motor)).Should().Equal(("X", 1), ("Y", 2), ("Z", 3), ("A", 4));
        axes[3].Should().Be(new MachineAxis("A", 4, 100, Rotary: true));
        axes[3].Unit.Should().Be("deg");
        MachineAxis.Of(MachineProfile.Default).Should().Equal(MachineAxis.Default);
        MachineProfile.Default.ToJson().Should().NotContain("\"axes\"", "a built-in profile's JSON, and so its library identity, is unchanged");
        MachineProfile.Parse(FourAxis().ToJson()).Axes.Should().Equal(FourAxis().Axes);
    }

    [Fact]
    public void A_profile_naming_a_motor_twice_is_refused_with_the_reason()
    {
        var json = JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["axes"] = JsonNode.Parse("""[{"name":"X","motor":1},{"name":"A","motor":1}]""");
        var act = () => MachineProfile.Parse(json.ToJsonString(), "bad.json");
        act.Should().Throw<InvalidDataException>().WithMessage("*listed twice*");
    }

    [Fact]
    public async Task Status_home_and_jog_drive_the_rotary_A_axis_in_degrees()
    {
        var before = await _console.ReadStateAsync();
        before.Axes.Select(a => a.Name).Should().Equal("X", "Y", "Z", "A");
        before.Axes.Single(a => a.Name == "A").Homed.Should().BeFalse();

        (await _console.HomeAsync("A")).Done.Should().BeTrue();
        var homed = await _console.ReadStateAsync();
        homed.Axes.Single(a => a.Name == "A").Homed.Should().BeTrue();
        homed.Axes.Single(a => a.Name == "X").Homed.Should().BeFalse("only A was homed");

        (await _console.JogAsync("A", 90, feed: 3600)).Done.Should().BeTrue();
        var jogged = await _console.ReadStateAsync();
        jogged.Axes.Single(a => a.Name == "A").Machine.Should().BeApproximately(90, 0.001);
        (await MotorAsync(4)).Should().BeApproximately(9000, 0.1, "100 counts per degree");

        (await _console.JogAsync("B", 1)).Refusal.Should().Be(ConsoleRefusal.BadValue);
    }
}
