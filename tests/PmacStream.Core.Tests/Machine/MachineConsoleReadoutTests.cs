using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Machine;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Core.Tests.Machine;

/// <summary>
/// What the DRO reads from the controller beyond positions, on the in-process simulator: distance to go of a program's
/// move (target register less commanded), the programmed and actual spindle speed.
/// </summary>
public sealed class MachineConsoleReadoutTests : IAsyncLifetime
{
    private readonly TestFolder _temp = new("console-readout");
    private PmacSimulator _sim = null!;
    private ControllerLink _controller = null!;
    private MachineConsole _console = null!;

    public Task InitializeAsync() => OpenAsync(new SimOptions(), new MachineConsoleOptions());

    private async Task OpenAsync(SimOptions sim, MachineConsoleOptions options)
    {
        _sim = new PmacSimulator(sim);
        var service = new JobService(new JobServiceOptions
        {
            Simulator = SimRig.BuiltIn(_sim),
            JobDatabase = Path.Combine(_temp.Path, "jobs.db"),
            Rules = new MachineRules(options.Axes),
        });
        _controller = await service.ConnectAsync(ConnectionSpec.Simulator);
        _console = new MachineConsole(service, _controller, options);
    }

    public async Task DisposeAsync()
    {
        await CloseAsync();
        _temp.Dispose();
    }

    private async Task CloseAsync()
    {
        await _controller.DisposeAsync();
        _sim.Dispose();
    }

    private Task<string> SendAsync(string command) => _controller.Connection.GetResponseAsync(command);

    private async Task StartMoveAsync(string move)
    {
        foreach (var line in new[] { "OPEN PROG 7 CLEAR", move, "CLOSE", "&1 B7 R" })
        {
            await SendAsync(line);
        }
    }

    [Fact]
    public async Task Distance_to_go_of_a_programs_move_is_its_end_less_where_the_axes_are_and_0_in_position()
    {
        await StartMoveAsync("LINEAR ABS F600 X100 Y50");
        _sim.Advance(TimeSpan.FromSeconds(5));
        var mid = await _console.ReadStateAsync();
        var x = mid.Axes.Single(a => a.Name == "X");
        var y = mid.Axes.Single(a => a.Name == "Y");
        x.Machine.Should().BeInRange(1, 99);
        x.ToGo.Should().BeApproximately(100 - x.Machine, 0.001);
        y.ToGo.Should().BeApproximately(50 - y.Machine, 0.001);
        mid.Axes.Single(a => a.Name == "Z").ToGo.Should().Be(0);

        _sim.Advance(TimeSpan.FromSeconds(20));
        var done = await _console.ReadStateAsync();
        done.Axes.Select(a => a.ToGo).Should().AllBeEquivalentTo(0.0);
        done.Axes.Single(a => a.Name == "X").Machine.Should().BeApproximately(100, 0.001);
    }

    [Fact]
    public async Task Without_the_suggested_M_variables_distance_to_go_of_a_program_stays_0()
    {
        await CloseAsync();
        await OpenAsync(new SimOptions { SuggestedMVariables = false }, new MachineConsoleOptions());
        await StartMoveAsync("LINEAR ABS F600 X100");
        _sim.Advance(TimeSpan.FromSeconds(5));
        (await _console.ReadStateAsync()).Axes.Single(a => a.Name == "X").ToGo.Should().Be(0);
        (await SendAsync("M163->")).Trim().TrimEnd('\u0006').Trim().Should().Be("*");
    }

    [Fact]
    public async Task The_target_register_reads_in_the_manuals_units()
    {
        await StartMoveAsync("LINEAR ABS F600 X100");
        _sim.Advance(TimeSpan.FromSeconds(1));
        (await SendAsync("M163->")).Should().Contain("D:$0000C7");
        var target = double.Parse((await SendAsync("M163")).Trim().TrimEnd('\u0006').Trim(), CultureInfo.InvariantCulture);
        target.Should().Be(100 * 96 * 32); // 100 counts in 1/(Ixx08*32) counts, Ixx08 = 96
    }

    [Fact]
    public async Task The_programmed_S_and_the_spindle_output_give_the_programmed_and_actual_spindle_speed()
    {
        (await _console.ReadStateAsync()).Spindle.Should().Be(new SpindleReadout(0, 0, false, false));
        await StartMoveAsync("S1200 M902=1 M903=1 LINEAR ABS F600 X10");
        _sim.Advance(TimeSpan.FromSeconds(2));
        var on = await _console.ReadStateAsync();
        on.Spindle.Should().Be(new SpindleReadout(1200, 1200, true, true));
        on.SpindleSpeed.Should().Be(1200);

        await StartMoveAsync("M902=0 LINEAR ABS F600 X0");
        _sim.Advance(TimeSpan.FromSeconds(2));
        (await _console.ReadStateAsync()).Spindle.Should().Be(new SpindleReadout(1200, 0, false, true));
    }

    [Fact]
    public async Task A_continuous_jog_runs_at_the_speed_given_and_the_motor_gets_its_own_jog_speed_back()
    {
        (await _console.StartJogAsync("X", +1, feed: 600)).Done.Should().BeTrue();
        _sim.Advance(TimeSpan.FromSeconds(2));
        (await _console.ReadStateAsync()).Axes[0].Machine.Should().BeInRange(18, 20.1, "2 s at 10 mm/s (600 mm/min), less the acceleration");
        (await _console.StopJogAsync("X")).Done.Should().BeTrue();
        (await SendAsync("I122")).Trim().TrimEnd('\u0006').Trim().Should().Be("32", "the motor's own jog speed is back");
        (await _console.StartJogAsync("X", +1, feed: 0)).Refusal.Should().Be(ConsoleRefusal.BadValue);
    }

    [Fact]
    public async Task A_spindle_motor_gives_the_actual_speed_from_its_velocity()
    {
        await CloseAsync();
        await OpenAsync(new SimOptions(), new MachineConsoleOptions { SpindleMotor = 4, SpindleCountsPerRev = 1000 });
        await SendAsync("#4J+");
        _sim.Advance(TimeSpan.FromSeconds(1));
        var s = await _console.ReadStateAsync();
        // Ixx22 = 32 counts/ms is 1920 rpm; V is reported to 0.1 count per servo cycle (0.44 ms), so within 0.5 %.
        s.Spindle!.Actual.Should().BeApproximately(32 * 60_000 / 1000.0, 10);
        s.Spindle.Programmed.Should().Be(0);
    }
}
