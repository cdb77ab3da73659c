namespace PmacStream.Sim.Tests.Engine;

public class RotaryBufferTests
{
    [Fact]
    public void Assignment_sent_while_a_buffer_is_open_is_stored_not_executed()
    {
        using var h = new SimHarness();
        var other = h.Sim.OpenPort("hmi");
        h.Ok("&1 B0 OPEN ROT");
        h.Ok("P500=80");
        h.Sim.ReadVariable('P', 500).Should().Be(0, "stored in the rotary buffer");
        h.Send(other, "P500").Should().Be("0<CR><ACK>");
        h.Send(other, "P501=5").Should().Be("<ACK>", "another port executes assignments online");
        h.Sim.ReadVariable('P', 501).Should().Be(5);
        h.Ok("CLOSE R");
        h.Sim.ReadVariable('P', 500).Should().Be(80, "executed when calculated");
    }

    [Fact]
    public void B0_inside_an_open_buffer_is_a_B_axis_move()
    {
        using var h = new SimHarness();
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F600");
        h.Ok("B10");
        h.Ok("B0");
        h.Ok("CLOSE");
        h.Ok("PR").Should().Be("3");
        h.Ok("&1 B0 R");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Select(m => m.Rotary.B).Should().Equal(10, 0);
    }

    [Fact]
    public void Only_one_port_may_have_a_buffer_open()
    {
        using var h = new SimHarness();
        var other = h.Sim.OpenPort("other");
        h.Ok("OPEN ROT");
        h.Send(other, "OPEN PROG 1").Should().Be("<BEL>ERR007<CR>");
        h.Send(other, "OPEN ROT").Should().Be("<BEL>ERR007<CR>");
        h.Send(other, "CLOSE").Should().Be("<ACK>", "CLOSE from another port does not close this port's buffer");
        h.Send(other, "X10").Should().Be("<BEL>ERR005<CR>");
        h.Ok("CLOSE");
        h.Send(other, "OPEN PROG 1 CLEAR").Should().Be("<ACK>");
        h.Send("OPEN PLC 1").Should().Be("<BEL>ERR007<CR>");
        other.Dispose();
        h.Send("OPEN PLC 1").Should().Be("<ACK>", "closing a port closes its buffer");
    }

    [Fact]
    public void Writing_past_the_defined_size_answers_no_room()
    {
        using var h = new SimHarness(new SimOptions { DefaultRotWords = 0 });
        h.Send("&1 OPEN ROT X1").Should().Be("<BEL>ERR006<CR>", "no rotary buffer defined");
        h.Ok("CLOSE DELETE GATHER &1 DEFINE ROT 10 B0 OPEN ROT");
        // "X1 Y2" costs 2 words, so 5 lines fill 10 words.
        for (var i = 0; i < 5; i++)
        {
            h.Ok($"X{i} Y2");
        }

        h.Send("X9 Y9").Should().Be("<BEL>ERR006<CR>");
        h.Ok("PR").Should().Be("5");
        h.Sim.Counters.LinesReceived.Should().Be(5);

        // Executed lines are freed: after running, the same buffer takes more lines.
        h.Ok("CLOSE R");
        h.Sim.RunUntilIdle();
        h.Ok("OPEN ROT");
        h.Ok("X9 Y9");
        h.Ok("CLOSE");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Should().HaveCount(6);
        h.Sim.ExecutedMoves[^1].X.Should().Be(9);
    }

    [Fact]
    public void Refusing_at_the_full_bit_and_the_error_code_are_configurable()
    {
        using var h = new SimHarness(new SimOptions { RefuseWhileFullBitSet = true, RotaryFullErrorCode = 11, I17 = 3, I16 = 2 });
        h.Ok("&1 B0 OPEN ROT");
        h.Ok("X1");
        h.Ok("X2");
        h.Ok("X3");
        h.Send("X4").Should().Be("<BEL>ERR011<CR>");
        h.Ok("R");
        h.Ok("PR").Should().Be("0", "one move executing, two calculated ahead: all three lines taken");
        h.Ok("X4");
    }

    [Fact]
    public void An_open_rotary_buffer_that_runs_dry_counts_an_underrun_and_waits()
    {
        using var h = new SimHarness();
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F600 X10");
        h.Ok("R");
        h.Sim.RunUntilIdle();
        h.Sim.Counters.Underruns.Should().Be(1);
        h.Sim.IsRunning().Should().BeTrue("a rotary program waits for more lines");
        h.Ok("X20");
        h.Sim.RunUntilIdle();
        h.Sim.ExecutedMoves.Select(m => m.X).Should().Equal(10, 20);
        h.Sim.Counters.Underruns.Should().Be(2);
        h.Ok("CLOSE");
        h.Sim.Counters.Underruns.Should().Be(2);
    }

    [Fact]
    public void Running_dry_with_the_buffer_closed_is_the_end_unless_more_lines_come()
    {
        using var h = new SimHarness();
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F600 X10 CLOSE R");
        h.Sim.RunUntilIdle();
        h.Sim.Counters.Underruns.Should().Be(0);
        h.Sim.IsRunning().Should().BeTrue();
        h.Ok("OPEN ROT X20 CLOSE");
        h.Sim.RunUntilIdle();
        h.Sim.Counters.Underruns.Should().Be(1, "it was not the end after all: motion had stopped between the lines");
        h.Sim.ExecutedMoves.Should().HaveCount(2);
    }

    [Fact]
    public void End_when_closed_behaviour_ends_the_program()
    {
        using var h = new SimHarness(new SimOptions { RotaryEndBehaviour = RotaryEndBehaviour.EndWhenClosed });
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F600 X10 CLOSE R");
        h.Sim.RunUntilIdle();
        h.Sim.IsRunning().Should().BeFalse();
        h.Ok("??")[5].Should().Be('0');
        h.Sim.Counters.Underruns.Should().Be(0);
    }

    [Fact]
    public void Streaming_while_running_keeps_every_line_in_order()
    {
        using var h = new SimHarness(new SimOptions { DefaultRotWords = 200 });
        h.Ok("&1 B0 OPEN ROT LINEAR ABS F6000");
        var sent = 0;
        var rng = new Random(5);
        var started = false;
        while (sent < 2000)
        {
            if (sent > 0 && !started)
            {
                h.Ok("R");
                started = true;
            }

            // Host: send while fewer than I17 lines are ahead, like a BREQ-driven streamer.
            while (int.Parse(h.Ok("PR")) < 10 && sent < 2000)
            {
                sent++;
                h.Ok($"M0=={sent} X{sent % 7} Y{sent % 5}");
            }

            if (started)
            {
                h.Advance(rng.NextDouble() * 0.05);
            }
        }

        h.Ok("CLOSE");
        h.Sim.RunUntilIdle();
        var lines = h.Sim.ExecutedMoves.Select(m => m.SourceLine).Where(l => l > 0).ToList();
        lines.Should().Equal(Enumerable.Range(1, 2000));
        h.Sim.Counters.Underruns.Should().Be(0);
    }

    [Fact]
    public void Redefining_or_deleting_the_rotary_buffer_while_it_runs_is_refused()
    {
        using var h = new SimHarness();
        h.Ok("&1 B0 OPEN ROT LINEAR F600 X10 CLOSE R");
        h.Send("&1 DEFINE ROT 100").Should().Be("<BEL>ERR001<CR>");
        h.Send("&1 DELETE ROT").Should().Be("<BEL>ERR001<CR>");
        h.Ok("A");
        h.Ok("&1 DELETE ROT");
    }
}
