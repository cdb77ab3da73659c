using System.Globalization;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Machine;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Machine;

/// <summary>
/// MDI's modal state carries on as on a control: from one MDI call to the next (distance mode, work offset including
/// G54.1 Pn, arc mode) and from the job that ran before it on the controller; cutter compensation is refused in MDI.
/// Each call is a separate <see cref="MachineConsole"/>, as separate <c>pmacstream mdi</c> processes are.
/// </summary>
public sealed class MdiModalStateTests : IAsyncLifetime
{
    private readonly TestFolder _temp = new("mdi-modal");
    private readonly PmacSimulator _sim = new(new SimOptions { StartHomed = true });
    private readonly List<ExecutedMove> _moves = [];
    private JobService _service = null!;
    private ControllerLink _controller = null!;

    public async Task InitializeAsync()
    {
        _service = new JobService(new JobServiceOptions
        {
            Simulator = SimRig.BuiltIn(_sim),
            JobDatabase = Path.Combine(_temp.Path, "jobs.db"),
            Rules = new MachineRules(MachineAxis.Default),
        });
        _controller = await _service.ConnectAsync(ConnectionSpec.Simulator, MachineProfile.Default);
        _sim.MoveExecuted += m =>
        {
            lock (_moves)
            {
                _moves.Add(m);
            }
        };
    }

    public async Task DisposeAsync()
    {
        await _controller.DisposeAsync();
        _sim.Dispose();
        _temp.Dispose();
    }

    /// <summary>A console as one <c>pmacstream</c> invocation makes it: the state file beside the job store.</summary>
    private MachineConsole Console() => new(_service, _controller, new MachineConsoleOptions
    {
        Profile = MachineProfile.Default, StatePath = Path.Combine(_temp.Path, "console-state.json"), TablesPath = Path.Combine(_temp.Path, "tables.json"),
    });

    private async Task Mdi(params string[] blocks)
    {
        var r = await Console().MdiAsync(blocks);
        r.Done.Should().BeTrue(r.Message);
    }

    private async Task<double> MotorAsync(int motor)
    {
        var reply = await _controller.Connection.GetResponseAsync($"#{motor}P");
        return double.Parse(reply.Trim().TrimEnd('\u0006').Trim(), CultureInfo.InvariantCulture);
    }

    [Fact]
    public async Task G91_carries_so_two_G0_X1_calls_move_2_mm()
    {
        await Mdi("G90 G0 X5 Y0");
        await Mdi("G91");
        await Mdi("G0 X1");
        await Mdi("G0 X1");
        (await MotorAsync(1)).Should().BeApproximately(7, 0.001, "G91 from the second call is still in force in the third and fourth");
        Console().CarriedModalState.Should().Contain("G91");
    }

    [Fact]
    public async Task G55_and_G54_1_P3_carry_so_G0_X0_lands_at_their_zero()
    {
        (await Console().SetWorkOffsetAsync("G55", 100, 50, 0)).Done.Should().BeTrue();
        (await Console().SetWorkOffsetAsync("G54.1P3", -20, 30, 0)).Done.Should().BeTrue();
        await Mdi("G55");
        await Mdi("G0 X0 Y0");
        (await MotorAsync(1)).Should().BeApproximately(100, 0.001);
        (await MotorAsync(2)).Should().BeApproximately(50, 0.001);
        await Mdi("G54.1 P3");
        Console().CarriedModalState.Should().Contain("G54.1 P3");
        await Mdi("G0 X0 Y0");
        (await MotorAsync(1)).Should().BeApproximately(-20, 0.001, "G54.1 P3 carried, not G54");
        (await MotorAsync(2)).Should().BeApproximately(30, 0.001);
    }

    [Fact]
    public async Task An_arc_mode_carries_to_the_next_call_and_runs_as_an_arc()
    {
        await Mdi("G90 G0 X0 Y0", "G02 X10 Y0 I5 J0 F600");
        Console().CarriedModalState.Should().EndWith("G02");
        lock (_moves)
        {
            _moves.Clear();
        }

        await Mdi("X0 Y0 I-5 J0");
        (await MotorAsync(1)).Should().BeApproximately(0, 0.001);
        lock (_moves)
        {
            _moves.Should().Contain(m => m.Kind == MoveKind.Circle1, "the carried G02 makes the block a clockwise arc");
        }
    }

    [Fact]
    public async Task The_job_before_leaves_its_modal_state_and_its_program_end_resets_as_the_library_does()
    {
        (await Console().SetWorkOffsetAsync("G55", 100, 50, 0)).Done.Should().BeTrue();
        await RunProgramAsync("g55.nc", "G21 G90 G55\nG0 X1 Y1\nG91\n");
        Console().CarriedModalState.Should().Contain("G91").And.Contain("G55");
        await Mdi("G90 G0 X0 Y0");
        (await MotorAsync(1)).Should().BeApproximately(100, 0.001, "the job left G55 in force");

        await RunProgramAsync("m30.nc", "G21 G90 G55\nG0 X2 Y2\nG91\nM30\n");
        Console().CarriedModalState.Should().Contain("G90").And.Contain("G54");
        await Mdi("G0 X0 Y0");
        (await MotorAsync(1)).Should().BeApproximately(0, 0.001, "M30 put the library back in G54 and G90");
    }

    [Fact]
    public async Task Cutter_compensation_is_refused_in_MDI_with_the_reason_and_nothing_runs()
    {
        var r = await Console().MdiAsync(["G0 X0 Y0", "G41 D1 G1 X10 F600"]);
        r.Done.Should().BeFalse();
        r.Refusal.Should().Be(ConsoleRefusal.BadValue);
        r.Message.Should().Contain("mdi:2").And.Contain("G41").And.Contain("not run in MDI");
        _moves.Should().BeEmpty();
    }

    private async Task RunProgramAsync(string name, string text)
    {
        var file = Path.Combine(_temp.Path, name);
        await File.WriteAllTextAsync(file, text);
        var prepared = await _service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Profile = MachineProfile.Default }, null);
        await using var job = await _service.CreateJobAsync(_controller, new JobRequest(prepared.Program, StrategyKind.Chunk)
        {
            Settings = RunSettings.Default, Profile = prepared.Profile, Library = LibraryPolicy.Verify,
        });
        await job.StartAsync();
        (await job.RunAsync(null)).Should().Be(JobOutcome.Completed);
    }
}
