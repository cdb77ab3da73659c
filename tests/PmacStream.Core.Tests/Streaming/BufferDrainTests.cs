using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public sealed class BufferDrainTests : IDisposable
{
    private readonly TestFolder _folder = new("drain");

    // Body lines: 0 M0==1 move, 1 M08, 2 M0==3 move, 3 M09, 4 M05, 5 M0==6 move, 6 M08, 7 M0==8 move.
    private static readonly string[] Source = ["G01 X1", "M08", "G01 X2", "M09", "M05", "G01 X3", "M08", "G01 X4"];

    private ChunkedProgram Program(string? probe, TrackingPlacement placement = TrackingPlacement.Exact)
    {
        var program = FakeSplit.Write(_folder.NewFolder("program"), Source, 100, placement);
        program.UseLineProbe(probe);
        return program;
    }

    private static long Probe(int line) => ChunkedProgram.ProbeValue(new StreamPosition(1, line));

    [Fact]
    public void Only_a_broken_download_waits_for_the_drain()
    {
        var drain = new BufferDrain();
        drain.Begin(positionExact: true);
        drain.Draining.Should().BeFalse();
        drain.Begin(positionExact: false);
        drain.Draining.Should().BeTrue();
    }

    [Fact]
    public async Task A_drain_step_asks_for_motion_only_when_PR_is_0_and_for_the_probe_once_drained()
    {
        var program = Program("P501");
        var (queries, port) = ControllerQueriesTests.Rig(c => c switch
        {
            "&1??" => "A80001020000000000", // running, in position, nothing queued
            "P501" => Probe(4).ToString(System.Globalization.CultureInfo.InvariantCulture),
            _ => "0",
        });
        var drain = new BufferDrain();
        drain.Begin(positionExact: false);

        (await drain.StepAsync(queries, program, linesAhead: 2, trackedLine: 2, new StreamPosition(1, 0), default)).Should().BeNull();
        port.Executed.Should().BeEmpty("lines are still ahead");
        (await drain.StepAsync(queries, program, 0, 3, new StreamPosition(1, 0), default)).Should().BeNull("M0 moved");
        (await drain.StepAsync(queries, program, 0, 3, new StreamPosition(1, 0), default)).Should().Be(new StreamPosition(1, 5));
        port.Executed.Should().Equal("&1??", "&1??", "P501");
        drain.Draining.Should().BeFalse();
    }

    [Fact]
    public void Drained_is_a_still_reading_with_M0_where_the_reading_before_left_it()
    {
        var drain = new BufferDrain();
        drain.Begin(false);
        drain.Observe(still: true, trackedLine: 5, statusUnknown: false).Should().BeFalse("nothing to compare M0 with");
        drain.Observe(true, 6, false).Should().BeFalse("M0 still moved");
        drain.Observe(false, 6, false).Should().BeFalse("lines ahead or motion");
        drain.Observe(true, 7, false).Should().BeFalse("M0 moved");
        drain.Observe(true, 7, false).Should().BeTrue();
    }

    [Fact]
    public void Without_the_status_word_six_still_readings_with_M0_standing_are_needed()
    {
        var drain = new BufferDrain();
        drain.Begin(false);
        Enumerable.Range(0, 5).Select(_ => drain.Observe(true, 6, statusUnknown: true)).ToList().Should().AllBeEquivalentTo(false);
        drain.Observe(true, 6, statusUnknown: true).Should().BeTrue();
    }

    [Fact]
    public void Without_a_probe_sending_resumes_after_the_block_M0_names()
    {
        BufferDrain.ResumePosition(Program(null), trackedLine: 3, next: new StreamPosition(1, 0), probeValue: null)
            .Should().Be(new StreamPosition(1, 3));
    }

    [Fact]
    public void The_probe_moves_the_resume_past_non_motion_lines_that_arrived_after_M0s_move()
    {
        // M09 and M05 arrived (the probe names M05): sending them again would run them twice.
        BufferDrain.ResumePosition(Program("P501"), 3, new StreamPosition(1, 0), Probe(4))
            .Should().Be(new StreamPosition(1, 5));
    }

    [Fact]
    public void A_probe_value_past_a_move_M0_did_not_reach_is_not_trusted()
    {
        // A move between M0's block and the probe's line would have moved M0: the value is not this job's.
        BufferDrain.ResumePosition(Program("P501"), 3, new StreamPosition(1, 0), Probe(6))
            .Should().Be(new StreamPosition(1, 3));
    }

    [Fact]
    public void Sending_never_resumes_before_the_position_known_sent()
    {
        var program = Program("P501");
        BufferDrain.ResumePosition(program, 1, new StreamPosition(1, 4), Probe(1)).Should().Be(new StreamPosition(1, 4));
        BufferDrain.ResumePosition(program, 1, new StreamPosition(1, 4), 0).Should().Be(new StreamPosition(1, 4));
    }

    [Fact]
    public void When_M0_lags_one_move_the_probe_may_name_the_move_after_it()
    {
        // Paper placement: M0 names the move before the last one that arrived; the probe on every line tells.
        var program = Program("P501", TrackingPlacement.Paper);
        program.ProbesEveryLine.Should().BeTrue();
        var afterMove3 = program.PositionAfterBlock(3)!.Value;

        BufferDrain.ResumePosition(program, 3, new StreamPosition(1, 0), Probe(5)).Should().Be(new StreamPosition(1, 6));
        BufferDrain.ResumePosition(program, 3, new StreamPosition(1, 0), Probe(7)).Should().Be(afterMove3, "two moves past M0 cannot have arrived unseen");
    }

    [Fact]
    public void Positions_order_by_chunk_then_line()
    {
        BufferDrain.Compare(new StreamPosition(1, 9), new StreamPosition(2, 0)).Should().BeNegative();
        BufferDrain.Compare(new StreamPosition(2, 3), new StreamPosition(2, 1)).Should().BePositive();
        BufferDrain.Compare(new StreamPosition(2, 3), new StreamPosition(2, 3)).Should().Be(0);
    }

    public void Dispose() => _folder.Dispose();
}
