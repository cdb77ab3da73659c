namespace PmacStream.Sim.Tests.Engine;

public class SmokeTests
{
    [Fact]
    public void Basic()
    {
        using var h = new SimHarness();
        h.Send("P500=80").Should().Be("<ACK>");
        h.Send("P500").Should().Be("80<CR><ACK>");
        h.Send("i3 i6 ver").Should().Be("2<CR>1<CR>1.947<CR><ACK>");
        h.Send("FOO").Should().Be("<BEL>ERR003<CR>");
        h.Send("LINEAR").Should().Be("<BEL>ERR005<CR>");
        h.Send("&1B0").Should().Be("<ACK>");
        h.Send("OPEN ROT").Should().Be("<ACK>");
        h.Send("LINEAR ABS F600").Should().Be("<ACK>");
        h.Send("M0==1 X10").Should().Be("<ACK>");
        h.Send("M0==2 X20").Should().Be("<ACK>");
        h.Send("CLOSE").Should().Be("<ACK>");
        h.Send("PR").Should().Be("3<CR><ACK>");
        h.Send("&1R").Should().Be("<ACK>");
        h.M(0).Should().Be(1);
        h.Advance(0.5);
        h.M(0).Should().Be(1);
        h.Advance(1.0);
        h.M(0).Should().Be(2);
        h.Advance(10);
        var moves = h.Sim.ExecutedMoves;
        moves.Should().HaveCount(2);
        moves[0].SourceLine.Should().Be(1);
        moves[0].EndTime.Should().BeApproximately(1.0, 1e-9);
        moves[1].X.Should().Be(20);
        moves[1].EndTime.Should().BeApproximately(2.0, 1e-9);
        h.Sim.Counters.Underruns.Should().Be(0);
    }
}
