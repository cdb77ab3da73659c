namespace PmacStream.Sim.Tests.Engine;

/// <summary>A subscriber's bug must not stop the simulated controller or starve the other subscribers.</summary>
public class FaultBarrierTests
{
    [Fact]
    public void Throwing_subscriber_does_not_stop_the_clock_or_the_other_subscribers()
    {
        using var h = new SimHarness();
        var seen = new List<double>();
        h.Sim.MoveExecuted += _ => throw new InvalidOperationException("subscriber bug");
        h.Sim.MoveExecuted += m => seen.Add(m.X);
        h.Download("OPEN PROG 1 CLEAR", "LINEAR X10 F600", "X20", "X30", "CLOSE");
        h.Ok("&1 B1 R");

        var act = () => h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));

        act.Should().NotThrow();
        seen.Should().Equal(10, 20, 30);
        h.Sim.ExecutedMoves.Should().HaveCount(3);
    }

    [Fact]
    public void Background_clock_survives_a_throwing_subscriber()
    {
        using var h = new SimHarness(new SimOptions { Speed = SimSpeed.Instant });
        var seen = 0;
        h.Sim.MoveExecuted += _ => throw new InvalidOperationException("subscriber bug");
        h.Sim.MoveExecuted += _ => Interlocked.Increment(ref seen);
        h.Download("OPEN PROG 1 CLEAR", "LINEAR X10 F600", "X20", "CLOSE");
        h.Sim.StartClock();
        h.Ok("&1 B1 R");
        SpinWait.SpinUntil(() => Volatile.Read(ref seen) >= 2, TimeSpan.FromSeconds(30));
        h.Sim.StopClock();

        seen.Should().Be(2);
    }
}
