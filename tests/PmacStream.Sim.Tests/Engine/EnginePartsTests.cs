using System.Text;
using PmacStream.Sim.Parsing;

namespace PmacStream.Sim.Tests.Engine;

/// <summary>The engine's parts on their own: segment timing and the override, move geometry, underruns, calls, PLCs, reply framing.</summary>
public class EnginePartsTests
{
    private static Segment Move(double seconds, bool blocks = false) => new() { Kind = MoveKind.Linear, Duration = seconds, BlocksCalculation = blocks };

    private static Stmt[] Statements(string line)
    {
        var p = new ExprParser(Lexer.Tokenize(line));
        return [.. ProgramParser.ParseRun(p)];
    }

    private static ProgramBuffer Buffer(params string[] lines)
    {
        var b = new ProgramBuffer(BufferKind.Prog, 1, 0);
        foreach (var l in lines)
        {
            b.Append(new ProgramLine(l, Statements(l)));
        }

        return b;
    }

    [Fact]
    public void A_segment_runs_its_duration_at_100_percent_and_twice_as_long_at_50()
    {
        var q = new MotionQueue(new SimOptions());
        q.Enqueue(Move(1.0));
        q.NextEventTime(0, holding: false).Should().Be(0, "a queued segment starts now");
        q.StartNext(0);
        q.NextEventTime(0, false).Should().BeApproximately(1.0, 1e-12);
        q.AdvanceTime(0, 0.5, false);
        q.CompleteIfDone().Should().BeNull();
        q.AdvanceTime(0.5, 1.0, false);
        q.CompleteIfDone().Should().NotBeNull();
        q.IsMoving.Should().BeFalse();

        var slow = new MotionQueue(new SimOptions()) { OverrideTarget = 50 };
        slow.Enqueue(Move(1.0));
        slow.StartNext(0);
        slow.Stop();
        slow.OverrideCurrent.Should().Be(50, "a stop leaves the override at its target");
        slow.Enqueue(Move(1.0));
        slow.StartNext(0);
        slow.NextEventTime(0, false).Should().BeApproximately(2.0, 1e-12);
    }

    [Fact]
    public void A_hold_slews_the_override_to_zero_and_motion_stands()
    {
        var q = new MotionQueue(new SimOptions { OverrideSlewPercentPerSecond = 50 });
        q.Enqueue(Move(10));
        q.StartNext(0);
        q.NextEventTime(0, holding: true).Should().BeApproximately(0.001, 1e-12, "the slew advances in 1 ms steps");
        q.AdvanceTime(0, 2.0, holding: true);
        q.OverrideCurrent.Should().Be(0);
        q.NextEventTime(2.0, holding: true).Should().Be(double.PositiveInfinity);
        q.Current!.Remaining.Should().BeApproximately(9.0, 1e-9, "the average override over the 2 s slew was 50 %");
    }

    [Fact]
    public void A_dwell_blocks_calculation_until_it_has_executed()
    {
        var q = new MotionQueue(new SimOptions());
        var dwell = Move(0.1, blocks: true);
        q.Enqueue(dwell);
        q.BlockedBy.Should().BeSameAs(dwell);
        q.StartNext(0);
        q.AdvanceTime(0, 0.1, false);
        q.CompleteIfDone().Should().BeSameAs(dwell);
        q.BlockedBy.Should().BeNull();
    }

    [Fact]
    public void The_position_is_interpolated_in_the_executing_segment()
    {
        var q = new MotionQueue(new SimOptions());
        var seg = Move(2.0);
        seg.End[0] = 10;
        q.Enqueue(seg);
        q.StartNext(0);
        q.AdvanceTime(0, 0.5, false);
        var at = new double[CoordinateSystem.AxisCount];
        q.Position(at, new double[CoordinateSystem.AxisCount]);
        at[0].Should().BeApproximately(2.5, 1e-9);
    }

    [Fact]
    public void A_linear_move_takes_its_length_over_the_feed_and_moves_the_calculated_position()
    {
        var calc = new MoveCalculator(new SimOptions { FeedTimeUnitMs = 60000 }, new AxisMatrices());
        calc.Reset();
        calc.Apply(new ParamStmt(ParamKind.Feed, new ConstExpr(600)), null!).Should().BeTrue();
        calc.ClearWords();
        calc.SetWord('X', 30);
        calc.SetWord('Y', 40);
        var seg = calc.Move()!;
        seg.Length.Should().Be(50);
        seg.Duration.Should().BeApproximately(5.0, 1e-12, "50 units at 600 per minute");
        calc.Position[0].Should().Be(30);

        calc.Apply(new AbsIncStmt(true, string.Empty), null!);
        calc.ClearWords();
        calc.SetWord('X', 5);
        calc.Move()!.End[0].Should().Be(35, "incremental");
    }

    [Fact]
    public void A_quarter_circle_by_centre_or_by_radius_is_a_quarter_of_its_circumference()
    {
        var calc = new MoveCalculator(new SimOptions(), new AxisMatrices());
        calc.Reset();
        calc.ClearWords();
        calc.SetWord('X', 10);
        calc.Move();
        calc.Apply(new ModeStmt(MotionMode.Circle2), null!);

        calc.ClearWords();
        calc.SetWord('X', 0);
        calc.SetWord('Y', 10);
        calc.SetWord('I', -10);
        var byCentre = calc.Move()!;
        byCentre.Length.Should().BeApproximately(Math.PI * 5, 1e-9);
        (byCentre.C1, byCentre.C2).Should().Be((0.0, 0.0));

        calc.ClearWords();
        calc.SetWord('X', -10);
        calc.SetWord('Y', 0);
        calc.SetWord('R', 10);
        calc.Move()!.Length.Should().BeApproximately(Math.PI * 5, 1e-9);
    }

    [Fact]
    public void Words_that_move_nothing_give_no_segment_and_a_dwell_stands_still()
    {
        var calc = new MoveCalculator(new SimOptions(), new AxisMatrices());
        calc.Reset();
        calc.ClearWords();
        calc.SetWord('I', 5);
        calc.Move().Should().BeNull("a centre vector without a circle mode is an argument nobody read");
        calc.Apply(new StopStmt(), null!).Should().BeFalse();

        var dwell = calc.Dwell(250, delay: false);
        dwell.Duration.Should().Be(0.25);
        dwell.BlocksCalculation.Should().BeTrue();
        calc.Dwell(250, delay: true).BlocksCalculation.Should().BeFalse();
    }

    [Fact]
    public void Running_dry_with_the_buffer_open_is_an_underrun_once()
    {
        var w = new UnderrunWatch();
        w.Started();
        w.OutOfLines(bufferOpen: true, RotaryEndBehaviour.Wait).Should().Be(Starvation.None, "nothing moved since the start");
        w.MoveStarted().Should().BeFalse();
        w.OutOfLines(true, RotaryEndBehaviour.Wait).Should().Be(Starvation.Underrun);
        w.OutOfLines(true, RotaryEndBehaviour.Wait).Should().Be(Starvation.None, "the same dry spell");
        w.MoveStarted().Should().BeFalse("it was counted when it happened");
        w.OutOfLines(true, RotaryEndBehaviour.Wait).Should().Be(Starvation.Underrun);
    }

    [Fact]
    public void Running_dry_with_the_buffer_closed_is_the_end_unless_motion_comes_back()
    {
        var w = new UnderrunWatch();
        w.Started();
        w.MoveStarted();
        w.OutOfLines(bufferOpen: false, RotaryEndBehaviour.Wait).Should().Be(Starvation.None);
        w.MoveStarted().Should().BeTrue("lines came after all: an underrun");

        w.OutOfLines(false, RotaryEndBehaviour.EndWhenClosed).Should().Be(Starvation.End);
        w.Stopped();
        w.MoveStarted().Should().BeFalse();
    }

    [Fact]
    public void A_call_returns_after_itself_and_READ_takes_the_callers_arguments()
    {
        var main = Buffer("CALL 1000 X5 Y7 Z9");
        var sub = Buffer("READ(X,Y)");
        var calls = new CallStack();
        var pc = new Cursor(main, 0, 1); // after the CALL statement

        calls.Call(ref pc, sub, (0, 0));
        pc.Buffer.Should().BeSameAs(sub);
        calls.Depth.Should().Be(1);

        var q = new Dictionary<int, double>();
        calls.Read("XY", new QVariables(q));
        q[124].Should().Be(5);
        q[125].Should().Be(7);
        q[100].Should().Be((1L << 23) | (1L << 24));
        q.Should().NotContainKey(126, "Z is not read");

        calls.Return(ref pc);
        pc.Buffer.Should().BeSameAs(main);
        pc.Stmt.Should().Be(3, "the caller goes on after the arguments READ took");
        calls.Depth.Should().Be(0);
    }

    [Fact]
    public void Calls_nest_at_most_255_deep()
    {
        var b = Buffer("X1");
        var calls = new CallStack();
        var pc = new Cursor(b, 0, 0);
        for (var i = 0; i < 255; i++)
        {
            calls.Call(ref pc, b, (0, 0));
        }

        FluentActions.Invoking(() =>
        {
            var top = new Cursor(b, 0, 0);
            calls.Call(ref top, b, (0, 0));
        }).Should().Throw<SimRuntimeException>().Which.Error.Should().Be(16);
        calls.Depth.Should().Be(255);
    }

    [Fact]
    public void PLCs_scan_as_I5_allows_and_a_run_time_error_disables_one()
    {
        var plcs = new PlcTable();
        plcs.Open(0).Append(new ProgramLine("P1=P1+1", Statements("P1=P1+1")));
        plcs.Open(3).Append(new ProgramLine("P2=P2+1", Statements("P2=P2+1")));
        plcs[0]!.Buffer.IsOpen.Should().BeFalse("the table only hands the buffer over; opening is the caller's");
        plcs.AnyEnabled.Should().BeFalse("opening a PLC buffer stops it");
        plcs.Enable([0, 3], enable: true);

        var p = new Dictionary<int, double>();
        var v = new PVariables(p);
        plcs.Scan(v, i5: 1, 100, (_, _) => { });
        p.GetValueOrDefault(1).Should().Be(1);
        p.GetValueOrDefault(2).Should().Be(0, "I5 bit 1 is off: PLCs 1..31 do not run");
        plcs.Scan(v, i5: 3, 100, (_, _) => { });
        p[2].Should().Be(1);

        plcs.Open(5).Append(new ProgramLine("ENDWHILE", Statements("ENDWHILE"))); // no WHILE to go back to: ERR016
        plcs.Enable([5], true);
        var errors = new List<(int Plc, int Error)>();
        plcs.Scan(v, 3, 100, (n, e) => errors.Add((n, e)));
        errors.Should().Equal((5, 16));
        plcs[5]!.Enabled.Should().BeFalse();
    }

    [Theory]
    [InlineData(0, 1, "", "")]
    [InlineData(1, 1, "", "<LF>")]
    [InlineData(2, 1, "", "<ACK>")]
    [InlineData(2, 1, "7", "7<CR><ACK>")]
    [InlineData(3, 1, "7", "<LF>7<CR><ACK>")]
    [InlineData(2, 1, "7;E", "7<CR><BEL>ERR003<CR>")]
    [InlineData(2, 0, "E", "<BEL>")]
    public void Replies_are_framed_by_I3_and_I6(int i3, int i6, string outputs, string framed)
    {
        var values = outputs.Split(';', StringSplitOptions.RemoveEmptyEntries).ToList();
        var error = values.Remove("E") ? 3 : 0;
        SimPort.Visible(ReplyFrame.Build(values, error, i3, i6)).Should().Be(framed);
        Encoding.ASCII.GetString(ReplyFrame.Build(["1"], 0, 2, 1)).Should().Be("1\r\x06");
    }

    private sealed class QVariables(Dictionary<int, double> q) : IVariableAccess
    {
        public double Get(char kind, int index) => kind == 'Q' ? q.GetValueOrDefault(index) : 0;

        public void Set(char kind, int index, double value) => q[index] = value;
    }

    private sealed class PVariables(Dictionary<int, double> p) : IVariableAccess
    {
        public double Get(char kind, int index) => kind == 'P' ? p.GetValueOrDefault(index) : 0;

        public void Set(char kind, int index, double value) => p[index] = value;
    }
}
