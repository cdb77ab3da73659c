using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Program stops on the simulator with the real library: at M00 (and M01 with optional stop on) the controller stops
/// the program, the session reports a program stop with its line and code (not an underrun, a fault or the end), the
/// strategy keeps the buffer fed meanwhile, and the run command continues with every block executed once, in order.
/// </summary>
public sealed class ProgramStopTests : IDisposable
{
    private readonly TestFolder _temp = new("stops");

    public void Dispose() => _temp.Dispose();

    /// <summary>200 moves; M00 alone at line 64, M01 at line 132 (after M05), then more moves; 40 lines per chunk.</summary>
    private string Program() => TestPrograms.Write(Path.Combine(_temp.Path, "stops.nc"), TestPrograms.Text("G21 G90 G17\nG00 X0 Y0\nG01 F2400\n", 200, TestPrograms.Grid(25, 2), after: i => i switch
    {
        60 => "M00",        // line 64
        126 => "M05\nM01",  // lines 131, 132
        _ => null,
    }));

    [Theory]
    [InlineData(StrategyKind.Chunk)]
    [InlineData(StrategyKind.Pr)]
    [InlineData(StrategyKind.Adaptive)]
    public async Task M00_and_M01_stop_the_program_the_session_waits_without_underruns_and_resume_runs_every_block_once(StrategyKind strategy)
    {
        using var rig = new SimRig(Program(), 40, new StreamingOptions { Strategy = strategy, BufferWords = 20_000 });
        var events = new List<StreamingEvent>();
        rig.Session.EventRaised += (_, e) => events.Add(e);
        await rig.Session.StartAsync();

        foreach (var (line, code) in new[] { (64, "M00"), (132, "M01") })
        {
            (await RunUntilStoppedAsync(rig)).Should().BeTrue($"the program stops at line {line} ({rig.Session.Status.Message})");
            var status = rig.Session.Status;
            status.Stop.Should().Be(new ProgramStop(line, code));
            status.CurrentLine.Should().Be(line, "the tracking variable names the stop block");
            status.Message.Should().Be($"program stop ({code}) at line {line}");
            rig.Sim.IsRunning().Should().BeFalse("the controller stopped the program");

            // Stopped for a long while (many ticks, much virtual time): nothing moves, nothing is counted as dry.
            var linesBefore = rig.Sim.ExecutedMoves.Count;
            for (var i = 0; i < 200; i++)
            {
                await rig.Session.TickAsync();
                rig.Sim.Advance(TimeSpan.FromSeconds(0.5));
            }

            rig.Session.State.Should().Be(SessionState.Stopped);
            rig.Sim.ExecutedMoves.Count.Should().Be(linesBefore, "nothing runs at a stop");
            rig.Session.Status.Underruns.Should().Be(0, "a stop is not an underrun");
            rig.Sim.Counters.Underruns.Should().Be(0);
            rig.Sink.Last!.State.Should().Be(SessionState.Stopped, "the checkpoint knows the job waits at a stop");

            await rig.Session.ResumeMotionAsync();
            rig.Session.State.Should().Be(SessionState.Running);
        }

        (await rig.RunAsync(0.5)).Should().BeTrue(rig.Session.Status.Message);
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines(), "every block once, in order, the stop blocks among them");
        rig.ExecutedLines().Should().Contain([64, 132]);
        events.Where(e => e.Kind == StreamingEventKind.ProgramStop).Select(e => e.Message)
            .Should().Equal("program stop (M00) at line 64", "program stop (M01) at line 132");
        events.Should().NotContain(e => e.Kind == StreamingEventKind.Underrun || e.Kind == StreamingEventKind.Fault);
        events.Should().Contain(e => e.Kind == StreamingEventKind.Command && e.Message == "resume after the program stop (M00) at line 64");
    }

    [Fact]
    public async Task With_optional_stop_off_M01_runs_through_and_the_switch_changes_live()
    {
        using var rig = new SimRig(Program(), 40, new StreamingOptions { BufferWords = 20_000, OptionalStop = false });
        await rig.Session.StartAsync();
        rig.Sim.ReadVariable('P', 502).Should().Be(0, "the start sets the switch the M01 routine reads");

        (await RunUntilStoppedAsync(rig)).Should().BeTrue();
        rig.Session.Status.Stop!.Code.Should().Be("M00", "M00 stops whatever the switch");
        await rig.Session.SetOptionalStopAsync(true);
        rig.Sim.ReadVariable('P', 502).Should().Be(1);
        await rig.Session.SetOptionalStopAsync(false);
        rig.Sim.ReadVariable('P', 502).Should().Be(0);
        await rig.Session.ResumeMotionAsync();

        (await rig.RunAsync(0.5)).Should().BeTrue("M01 does not stop with the switch off");
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines());
    }

    [Fact]
    public async Task With_paper_placement_the_probe_names_the_stop_block_the_lagging_variable_does_not()
    {
        using var rig = new SimRig(Program(), 40, new StreamingOptions { BufferWords = 20_000 }, PmacStream.Preparation.TrackingPlacement.Paper);
        await rig.Session.StartAsync();
        (await RunUntilStoppedAsync(rig)).Should().BeTrue();
        rig.Session.Status.Stop.Should().Be(new ProgramStop(64, "M00"));
        rig.Session.Status.CurrentLine.Should().BeLessThan(64, "with paper placement M0 names the block before");
    }

    [Fact]
    public async Task A_stop_the_controller_is_continued_from_elsewhere_is_followed()
    {
        using var rig = new SimRig(Program(), 40, new StreamingOptions { BufferWords = 20_000 });
        await rig.Session.StartAsync();
        (await RunUntilStoppedAsync(rig)).Should().BeTrue();

        // The operator presses cycle start at the controller: the session sees the program run again.
        rig.Port.Execute("&1 R");
        rig.Sim.Advance(TimeSpan.FromSeconds(0.5));
        await rig.Session.TickAsync();
        rig.Session.State.Should().Be(SessionState.Running);
        rig.Session.Status.Stop.Should().BeNull();
    }

    [Fact]
    public async Task A_host_that_left_its_job_at_a_stop_resumes_it_still_stopped_and_exact()
    {
        using var rig = new SimRig(Program(), 40, new StreamingOptions { BufferWords = 20_000 });
        await rig.Session.StartAsync();
        (await RunUntilStoppedAsync(rig)).Should().BeTrue();

        // The host is gone; a new one takes the record: the controller still waits at the stop, the job is not lost.
        await ResumeAtTheM00AndRunToTheEndAsync(rig);
    }

    [Fact]
    public async Task A_stop_the_program_reached_after_the_host_died_is_resumed_as_a_stop_not_as_a_lost_job()
    {
        using var rig = new SimRig(Program(), 40, new StreamingOptions { BufferWords = 20_000 });
        await rig.Session.StartAsync();
        for (var i = 0; i < 5000 && rig.Session.Status.CurrentLine < 48; i++)
        {
            await rig.Session.TickAsync();
            rig.Sim.Advance(TimeSpan.FromSeconds(0.05));
        }

        rig.Session.Status.CurrentLine.Should().BeInRange(48, 63, "the host dies while the program runs before its M00");

        // The host is gone; the controller runs on through the lines it holds and stops at the M00 of line 64. The
        // record says running at an earlier line, the controller is not running: a stop block, not a lost job.
        rig.Sim.Advance(TimeSpan.FromSeconds(60));
        rig.Sim.IsRunning().Should().BeFalse();
        await ResumeAtTheM00AndRunToTheEndAsync(rig);
    }

    /// <summary>A new host resumes the job from its record: it stands at the M00 of line 64; then M01, then the end, every block once.</summary>
    private static async Task ResumeAtTheM00AndRunToTheEndAsync(SimRig rig)
    {
        rig.Session = new StreamingSession(rig.Connection, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        await rig.Session.ResumeAsync(rig.Sink.Record());
        (await RunUntilStoppedAsync(rig)).Should().BeTrue(rig.Session.Status.Message);
        rig.Session.Status.Stop.Should().Be(new ProgramStop(64, "M00"));
        await rig.Session.ResumeMotionAsync();
        (await RunUntilStoppedAsync(rig)).Should().BeTrue("M01 stops next");
        await rig.Session.ResumeMotionAsync();
        (await rig.RunAsync(0.5)).Should().BeTrue(rig.Session.Status.Message);
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines());
    }

    private static async Task<bool> RunUntilStoppedAsync(SimRig rig)
    {
        for (var i = 0; i < 5000; i++)
        {
            await rig.Session.TickAsync();
            if (rig.Session.State == SessionState.Stopped)
            {
                return true;
            }

            if (rig.Session.State is SessionState.Completed or SessionState.Faulted or SessionState.Aborted)
            {
                return false;
            }

            rig.Sim.Advance(TimeSpan.FromSeconds(0.5));
        }

        return false;
    }
}
