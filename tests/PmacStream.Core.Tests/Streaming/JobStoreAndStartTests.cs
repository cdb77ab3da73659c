using Microsoft.Data.Sqlite;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class JobStoreTests
{
    [Fact]
    public void Checkpoints_survive_reopening_and_the_latest_unfinished_job_is_found()
    {
        using var temp = new TestFolder("jobs");
        var db = Path.Combine(temp.Path, "jobs.db");
        long first, second;
        var cp = new Checkpoint(1234, 2, new StreamPosition(3, 17), false, 2, SessionState.Running, new DateTimeOffset(2026, 1, 2, 3, 4, 5, TimeSpan.Zero), Started: true);
        using (var store = JobStore.Open(db))
        {
            first = store.CreateJob("a.nc", "aa", "m1/manifest.json", StrategyKind.Chunk, "sim", null);
            second = store.CreateJob("b.nc", "bb", "m2/manifest.json", StrategyKind.Adaptive, "tcp://127.0.0.1:1025", 500);
            store.SaveCheckpoint(first, cp with { State = SessionState.Completed }, durable: true);
            store.SaveCheckpoint(second, cp, durable: false);
            store.SetMessage(second, "link lost");
            store.CheckpointWrites.Should().Be(2);
        }

        using (var store = JobStore.Open(db))
        {
            var job = store.LatestUnfinished()!;
            job.Id.Should().Be(second);
            job.Strategy.Should().Be(StrategyKind.Adaptive);
            job.Connection.Should().Be("tcp://127.0.0.1:1025");
            job.FromLine.Should().Be(500);
            job.Message.Should().Be("link lost");
            job.Checkpoint.Should().Be(cp);
            store.Get(first)!.Unfinished.Should().BeFalse();
            store.List().Select(j => j.Id).Should().Equal(second, first);
        }

        using var raw = new SqliteConnection($"Data Source={db}");
        raw.Open();
        using var cmd = raw.CreateCommand();
        cmd.CommandText = "PRAGMA journal_mode";
        ((string)cmd.ExecuteScalar()!).Should().Be("wal");
    }

    [Fact]
    public async Task A_session_writes_a_checkpoint_every_tick_and_durable_ones_at_chunk_boundaries()
    {
        using var temp = new TestFolder("jobsink");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(600, 3), 100);
        var rig = new FakeRig(program, new StreamingOptions { BufferWords = 20_000 }, capacityWords: 20_000);
        await rig.Session.StartAsync();
        (await rig.RunAsync()).Should().BeTrue();
        rig.Sink.Writes.Should().BeGreaterThan(50, "one per tick at least");
        rig.Sink.Durable.Should().BeGreaterThanOrEqualTo(program.TotalChunks, "each chunk boundary is committed synchronously");
        rig.Sink.Last!.State.Should().Be(SessionState.Completed);
        rig.Sink.Last.LastExecutedLine.Should().Be(program.FinalTrackedLine);
    }
}

public class StartFromLineTests
{
    [Fact]
    public void The_plan_restores_modal_state_and_approaches_the_blocks_start_safely()
    {
        var src = RepoRoot.DemoProgram;
        var plan = StartFromLine.Plan(src, 500, safeZ: 10);

        // Independent replay: the state and position after the last block before the plan's line.
        var interp = new Interpreter(MachineProfile.Default);
        foreach (var b in GCodeReader.ReadAll(src))
        {
            if (b.LineNumber >= plan.Line)
            {
                break;
            }

            interp.Execute(b);
        }

        plan.Line.Should().BeGreaterThanOrEqualTo(500);
        plan.Start.Should().Be(interp.Position);
        plan.State.Should().Be(interp.State);
        plan.GCode.Should().Contain(l => l.StartsWith("G17 G54", StringComparison.Ordinal), "the controller preamble is in millimetres: no units code");
        plan.GCode.Should().Contain("M08").And.Contain(l => l.Contains("M03", StringComparison.Ordinal));
        var z = plan.GCode.ToList().FindIndex(l => l.StartsWith("G90 G00 Z10", StringComparison.Ordinal));
        var xy = plan.GCode.ToList().FindIndex(l => l.StartsWith("G00 X", StringComparison.Ordinal));
        var down = plan.GCode.ToList().FindIndex(l => l.StartsWith("G01 Z", StringComparison.Ordinal));
        z.Should().BeGreaterThan(0);
        xy.Should().Be(z + 1, "retract first, then rapid in XY");
        down.Should().Be(xy + 1, "then feed down");
        plan.PmacLines.Should().Contain(l => l.StartsWith("P500=", StringComparison.Ordinal));
        plan.PmacLines.Where(l => l.Contains('X') || l.Contains('Z')).Should().OnlyContain(l => l.EndsWith("F(P500)", StringComparison.Ordinal));
        plan.PmacLines.Should().NotContain(l => System.Text.RegularExpressions.Regex.IsMatch(l, @"(?<![A-Z])F\d"));
    }

    [Fact]
    public void The_plan_restores_what_the_program_set_on_the_controller_before_the_block()
    {
        // The blocks a start skips set tables, shifts and an extended offset: the controller must hold them all.
        using var dir = new TestFolder("start-tables");
        var src = Path.Combine(dir.Path, "tables.nc");
        File.WriteAllText(src, "G21 G90 G17\nG10 L2 P0 X1.5\nG10 L2 P2 X30. Y-20. Z5.\nG10 L10 P2 R55.\nG54.1 P3\nG52 X10. Y10.\n"
            + "G00 X0 Y0 Z10.\nG92 X5. Y10.\nG01 X5. F300.\nX10.\nM30\n");
        var plan = StartFromLine.Plan(src, 10, new StartPlanOptions { Profile = MachineProfile.Named("fanuc-mill") });

        plan.PmacLines.Take(6).Should().Equal(
            "G99.9", "G10 L2 P0 X1.5 Y0 Z0", "G10 L2 P2 X30 Y-20 Z5", "G10 L1 P2 Z55", "G52 X10 Y10 Z0", "G92 X-5 Y-10 Z0");
        plan.GCode[7].Should().Be("G54.1 P3", "the selection the plane and G54..G59 line cannot name comes right after it");
        plan.GCode.Skip(1).Take(5).Should().Equal(plan.PmacLines.Skip(1).Take(5), "the operator sees the tables and shifts as they go, without a feed word");
        plan.GCode[0].Should().StartWith("G99.9 (the library's power-on state");

        // Without such blocks only the power-on state comes first.
        var plain = StartFromLine.Plan(RepoRoot.DemoProgram, 500, new StartPlanOptions { Profile = MachineProfile.Named("fanuc-mill") }).GCode;
        (plain[0][..5], plain[1]).Should().Be(("G99.9", "G17 G54"));
    }

    [Fact]
    public void The_machine_tables_zero_the_external_offset_where_the_profile_has_one()
    {
        ControllerLibrary.TableLines(MachineProfile.Named("fanuc-mill")!)[0].Should().Be("P7100=0 P7101=0 P7102=0", "the host's interpreter starts FANUC's external offset at zero");
        ControllerLibrary.TableLines(MachineProfile.Named("linuxcnc-mill")!)[0].Should().StartWith("P7103=", "LinuxCNC has no external offset: G54 is index 1");
    }

    [Fact]
    public void Move_times_cover_every_motion_block()
    {
        var src = RepoRoot.DemoProgram;
        var t = MoveTimeTable.FromProgram(src)!;
        t.Count.Should().BeGreaterThan(3000);
        t.TotalSeconds.Should().BeGreaterThan(60);
        t.SecondsBetween(0, int.MaxValue).Should().BeApproximately(t.TotalSeconds, 1e-6);
        t.SecondsBetween(100, 50).Should().Be(0);
    }
}
