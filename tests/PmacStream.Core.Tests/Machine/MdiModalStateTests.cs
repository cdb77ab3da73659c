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

    [Fact]
    public async Task A_canned_cycle_carries_so_an_X_Y_block_drills_until_G80()
    {
        await Mdi("G90 G0 X0 Y0 Z10");
        await Mdi("G99 G81 X10 Y10 R2 Z-5 F300");
        Console().CarriedModalState.Should().Contain("G81").And.Contain("R2").And.Contain("Z-5").And.Contain("G99");
        Clear();
        await Mdi("X20 Y10");
        (await MotorAsync(1)).Should().BeApproximately(20, 0.001);
        (await MotorAsync(3)).Should().BeApproximately(2, 0.001, "G99: back to the R level");
        Moves().Should().Contain(m => m.Kind == MoveKind.Linear && Math.Abs(m.X - 20) < 1e-6 && Math.Abs(m.Z + 5) < 1e-6, "the carried G81 drilled at X20 Y10 to Z-5");

        // G98 from here: the initial level is where the cycle found the tool (the R level it stands at, as on a control).
        await Mdi("G98 X30 Z-6");
        (await MotorAsync(1)).Should().BeApproximately(30, 0.001);
        Moves().Should().Contain(m => Math.Abs(m.X - 30) < 1e-6 && Math.Abs(m.Z + 6) < 1e-6, "a new depth in the block replaces the carried one");

        await Mdi("G80");
        Console().CarriedModalState.Should().NotContain("G81");
        Clear();
        await Mdi("G0 X40");
        Moves().Should().NotContain(m => m.Z < 0, "no cycle after G80");
    }

    [Fact]
    public async Task G92_and_G52_shifts_carry_and_are_computed_where_the_axes_stand()
    {
        await Mdi("G90 G0 X10 Y0 Z0");
        await Mdi("G92 X0 Y0");
        await Mdi("G0 X5 Y1");
        (await MotorAsync(1)).Should().BeApproximately(15, 0.001, "G92 X0 at X10 shifted X by 10, and the shift carried");
        (await MotorAsync(2)).Should().BeApproximately(1, 0.001);
        await Mdi("G92.1");
        await Mdi("G52 X100");
        await Mdi("G0 X1");
        (await MotorAsync(1)).Should().BeApproximately(101, 0.001, "the G52 shift carried");
        await Mdi("G52 X0", "G0 X2");
        (await MotorAsync(1)).Should().BeApproximately(2, 0.001);
    }

    [Fact]
    public async Task Subprogram_and_macro_calls_are_refused_in_MDI_with_the_reason_and_nothing_runs()
    {
        foreach (var block in new[] { "M98 P1000", "G65 P9100 A1", "#100=5" })
        {
            var r = await Console().MdiAsync([block]);
            r.Done.Should().BeFalse(block);
            r.Message.Should().Contain("not run in MDI").And.Contain("program file");
        }

        Moves().Should().BeEmpty();
    }

    private void Clear()
    {
        lock (_moves)
        {
            _moves.Clear();
        }
    }

    private List<ExecutedMove> Moves()
    {
        lock (_moves)
        {
            return [.. _moves];
        }
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
