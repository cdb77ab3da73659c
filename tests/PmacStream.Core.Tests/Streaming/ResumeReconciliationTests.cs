using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>
/// The controller is the truth on resume: the record is read against M0, the running bit, PR and the line probe, and
/// the resume continues, drains, restarts at the controller's line or refuses with both positions (issue 20).
/// </summary>
public sealed class ResumeReconciliationTests : IDisposable
{
    private readonly TestFolder _folder = new("reconcile");

    // 300 source lines in 3 chunks of 100 body lines: a move on every line but each tenth, which is an M08. Body index
    // i of chunk c holds source line 100 (c - 1) + i + 1.
    private static readonly string[] Source = Enumerable.Range(1, 300).Select(i => i % 10 == 0 ? "M08" : $"G01 X{i} Y0").ToArray();

    private ChunkedProgram Program(string? probe = null)
    {
        var program = FakeSplit.Write(_folder.NewFolder("program"), Source, 100);
        program.UseLineProbe(probe);
        return program;
    }

    private static Checkpoint Record(int line, StreamPosition next, bool exact = true, int? chunk = null, bool started = true) =>
        new(line, chunk ?? (line > 200 ? 3 : line > 100 ? 2 : 1), next, exact, next.Chunk - 1, SessionState.Running, DateTimeOffset.UnixEpoch, started);

    private static ControllerReading Seen(int m, int linesAhead = 0, bool? running = true, long? probe = null) => new(m, running, linesAhead, probe);

    private static ResumeDecision Decide(ChunkedProgram program, Checkpoint record, ControllerReading seen, int bufferWords = 16_000) =>
        ResumeReconciliation.Decide(program, record, seen, bufferWords);

    [Fact]
    public void A_record_the_controller_agrees_with_continues_at_its_position_and_a_broken_send_drains()
    {
        var program = Program();
        var record = Record(50, new StreamPosition(2, 0));

        // M0 55: body lines 55..99 of chunk 1 (45 lines) were sent after it; 40 are still ahead of the calculation.
        Decide(program, record, Seen(55, linesAhead: 40)).Should().Be(new ResumeDecision(ResumeAction.Continue, null));
        Decide(program, record with { NextExact = false }, Seen(55, linesAhead: 40)).Should().Be(new ResumeDecision(ResumeAction.Drain, null));
    }

    [Fact]
    public void A_controller_ahead_of_the_record_is_drained_never_sent_the_lines_it_holds()
    {
        var program = Program("P501");

        // Rewound: the record says sending had reached line 20, the controller executes line 155.
        var rewound = Decide(program, Record(5, new StreamPosition(1, 20)), Seen(155, linesAhead: 30));
        rewound.Action.Should().Be(ResumeAction.Drain);
        rewound.ControllerAhead.Should().Be("it executes line 155, which the record says was never sent (sending had reached chunk 1 line 20, after line 19)");

        // A lost reply: M0 has not reached the stored lines, but PR counts more lines than the record left after M0.
        var lost = Decide(program, Record(50, new StreamPosition(2, 0)), Seen(95, linesAhead: 30));
        lost.Action.Should().Be(ResumeAction.Drain);
        lost.ControllerAhead.Should().Be("it holds 30 lines ahead (PR), but the record says only 5 were sent after line 95");

        // The line probe names a line past the record's position (the M08 of source line 110).
        var probe = ChunkedProgram.ProbeValue(new StreamPosition(2, 9));
        Decide(program, Record(50, new StreamPosition(2, 0)), Seen(55, linesAhead: 10, probe: probe)).ControllerAhead.Should()
            .Be($"its line probe P501={probe} names a line after chunk 2 line 0, where the record says sending stopped");
    }

    [Fact]
    public void A_record_ahead_of_a_running_controller_is_refused_with_both_positions_and_the_choices()
    {
        var program = Program();
        var act = () => Decide(program, Record(250, new StreamPosition(3, 70)), Seen(155, linesAhead: 45));
        var refused = act.Should().Throw<ResumeRefusedException>().Which;
        refused.Message.Should().StartWith("the controller executes line 155, before line 250 that the record says had already executed. ")
            .And.Contain("The controller: M0=155, running, 45 lines ahead in its rotary buffer (PR).")
            .And.Contain("The job record: line 250 executed, sending had reached chunk 3 line 70.")
            .And.Contain("so nothing was sent")
            .And.Contain("Choices: let the controller run the lines it holds");
        refused.RestartLine.Should().BeNull("it has not stopped yet");
        refused.Controller.TrackedLine.Should().Be(155);
        refused.Record.LastExecutedLine.Should().Be(250);
    }

    [Fact]
    public void A_stopped_controller_restarts_at_its_own_line_and_is_refused_when_it_stopped_behind_the_record()
    {
        var program = Program();
        var record = Record(50, new StreamPosition(2, 0));

        var lost = FluentActions.Invoking(() => Decide(program, record, Seen(57, running: false))).Should().Throw<ControllerLostJobException>().Which;
        lost.RestartLine.Should().Be(57, "the record lags: the controller got to line 57");
        lost.Message.Should().Contain("restart from line 57");
        FluentActions.Invoking(() => Decide(program, record, Seen(0, running: false))).Should().Throw<ControllerLostJobException>()
            .Which.RestartLine.Should().BeNull("a reset controller names no line: the record's is all there is");

        var behind = FluentActions.Invoking(() => Decide(program, record, Seen(33, running: false))).Should().Throw<ResumeRefusedException>().Which;
        behind.RestartLine.Should().Be(33);
        behind.Message.Should().StartWith("the controller stopped at line 33, before line 50").And.Contain("start the program again from line 33, where the controller stopped");
    }

    [Fact]
    public void An_M0_that_is_no_block_of_the_program_is_refused()
    {
        var program = Program();
        var record = Record(50, new StreamPosition(2, 0));
        FluentActions.Invoking(() => Decide(program, record, Seen(60))).Should().Throw<ResumeRefusedException>()
            .WithMessage("M0=60 is not a block of this program: the controller runs something else.*");
        FluentActions.Invoking(() => Decide(program, record, Seen(9999))).Should().Throw<ResumeRefusedException>();
    }

    [Fact]
    public void A_record_that_contradicts_itself_is_refused_before_the_controller_is_believed()
    {
        var program = Program();
        FluentActions.Invoking(() => Decide(program, Record(150, new StreamPosition(1, 40)), Seen(155))).Should().Throw<ResumeRefusedException>()
            .WithMessage("the job record contradicts itself (line 150 executed, but sending had only reached chunk 1 line 40, before that line)*");
        FluentActions.Invoking(() => Decide(program, Record(50, new StreamPosition(2, 0), chunk: 3), Seen(55))).Should().Throw<ResumeRefusedException>()
            .WithMessage("the job record contradicts itself (its current chunk 3 is not chunk 1 of its last executed line 50)*");
        FluentActions.Invoking(() => Decide(program, Record(5, new StreamPosition(3, 50)), Seen(55), bufferWords: 100)).Should().Throw<ResumeRefusedException>()
            .WithMessage("the job record contradicts itself (sending had reached chunk 3 line 50, more than twice the rotary buffer's 100 words after line 5)*");

        // Not exact: lines of a broken send may have run past the position, so the first rule does not apply.
        Decide(program, Record(150, new StreamPosition(1, 40), exact: false), Seen(155)).Action.Should().Be(ResumeAction.Drain);
    }

    [Fact]
    public void A_start_that_loaded_but_never_ran_continues_without_a_running_controller()
    {
        var program = Program();
        var record = Record(0, new StreamPosition(2, 0), started: false);

        // The buffer holds the first chunk (and maybe a preamble): PR is not compared while M0 is 0.
        Decide(program, record, Seen(0, linesAhead: 130, running: false)).Should().Be(new ResumeDecision(ResumeAction.Continue, null));
    }

    public void Dispose() => _folder.Dispose();
}
