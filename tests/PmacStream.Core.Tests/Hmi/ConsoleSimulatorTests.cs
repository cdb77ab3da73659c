using System.Globalization;
using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Machine;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// The console presenter over the real <see cref="CoreHmiBackend"/> and <see cref="MachineConsole"/>, on the simulated
/// Turbo PMAC started unhomed (a machine with incremental encoders); its clock is stepped by the console's waits.
/// </summary>
public sealed class ConsoleSimulatorTests : IAsyncLifetime
{
    private readonly TestFolder _temp = new("hmi-console");
    private readonly PmacSimulator _sim = new(new SimOptions { StartHomed = false });
    private readonly FakeConsoleView _view = new();
    private CoreHmiBackend _backend = null!;
    private ConsolePresenter _p = null!;

    public async Task InitializeAsync()
    {
        var service = new JobService(new JobServiceOptions
        {
            Simulator = SimRig.BuiltIn(_sim, "hmi"),
            JobDatabase = Path.Combine(_temp.Path, "jobs.db"),
            Rules = new MachineRules(MachineAxis.Default),
        });
        _backend = new CoreHmiBackend(service)
        {
            ConsoleOptions = new MachineConsoleOptions
            {
                History = AlarmHistoryFile.Beside(service.JobDatabase),
                TablesPath = Path.Combine(_temp.Path, "tables.json"),
                StatePath = Path.Combine(_temp.Path, "console-state.json"),
            },
        };
        _p = new ConsolePresenter(_view, _backend, _backend, () => MachineProfile.Default) { PollPeriod = TimeSpan.Zero };
        await _backend.ConnectAsync(new ConnectionSettings(DeviceKind.Simulator), MachineProfile.Default);
        await TickAsync();
    }

    public async Task DisposeAsync()
    {
        await _p.DisposeAsync();
        await _backend.DisposeAsync();
        _sim.Dispose();
        _temp.Dispose();
    }

    private async Task TickAsync()
    {
        await _p.WhenIdleAsync();
        await _p.TickAsync();
        await _p.WhenIdleAsync();
    }

    private async Task Do(Action a)
    {
        a();
        await TickAsync();
        _view.ConsoleMessage.Should().StartWith("Done: ");
    }

    /// <summary>The simulator's actual position of a motor, mm (scale 1: the power-on axis definition), read on a port of its own.</summary>
    private async Task<double> MotorAsync(int motor)
    {
        await using var port = new InProcessConnection(_sim.OpenPort("check"), "check");
        var reply = await port.GetResponseAsync($"#{motor}P");
        return double.Parse(reply.Trim().TrimEnd('\u0006').Trim(), CultureInfo.InvariantCulture);
    }

    [Fact]
    public async Task Home_all_then_X_jogged_by_1_mm_steps_and_the_DRO_follows_within_a_micron()
    {
        _view.Dro.Should().HaveCount(3).And.OnlyContain(r => !r.Homed, "the simulator starts unhomed");

        await Do(_view.HomeAll);
        _view.Dro.Should().OnlyContain(r => r.Homed);

        _view.JogAxis = "X";
        _view.JogIncrement = 1;
        _view.JogFeed = 3000;
        for (var step = 1; step <= 3; step++)
        {
            await Do(() => _view.PressJog(+1));
            var dro = double.Parse(_view.Dro[0].Machine, CultureInfo.InvariantCulture);
            var motor = await MotorAsync(1);
            dro.Should().BeApproximately(motor, 0.001, $"the DRO follows the motor after step {step}");
            motor.Should().BeApproximately(_p.State!.Axes[0].Machine, 0.001);
        }

        (await MotorAsync(1) - await MotorAsync(2)).Should().BeApproximately(3, 0.001, "X went 3 mm from where homing left it, Y stayed");
    }

    [Fact]
    public async Task Touch_off_X_sets_the_active_offset_so_the_work_position_reads_zero()
    {
        await Do(_view.HomeAll);
        _view.JogIncrement = 1;
        await Do(() => _view.PressJog(+1));
        await Do(() => _view.TouchOff("X"));
        await TickAsync();

        _view.Dro[0].Work.Should().Be("0.000");
        double.Parse(_view.OffsetRows.Single(r => r[0] == _p.State!.WorkOffset)[1], CultureInfo.InvariantCulture)
            .Should().BeApproximately(double.Parse(_view.Dro[0].Machine, CultureInfo.InvariantCulture), 0.001, "the offset is where X stands");
    }

    [Fact]
    public async Task MDI_G0_X10_Y10_lands_and_goes_into_the_history()
    {
        await Do(_view.HomeAll);
        await Do(() => _view.SendMdi("G0 X10 Y10"));

        _view.MdiHistory.Should().Equal("G0 X10 Y10");
        (await MotorAsync(1)).Should().BeApproximately(10, 0.001);
        (await MotorAsync(2)).Should().BeApproximately(10, 0.001);
        _view.Dro.Take(2).Select(r => r.Work).Should().Equal("10.000", "10.000");
    }
}
