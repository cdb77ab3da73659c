using System.Text;
using PmacStream.Pmac;

namespace PmacStream.Core.Tests.Pmac;

public class ReplyParserTests
{
    [Fact]
    public void Values_are_separated_and_ack_removed()
    {
        var raw = Encoding.ASCII.GetBytes("1.947\r80\r\x06");
        ReplyParser.IsComplete(raw).Should().BeTrue();
        ReplyParser.Parse(raw, "VER P500").Should().Be("1.947\n80");
    }

    [Fact]
    public void Error_reply_becomes_typed_exception_with_manual_text()
    {
        var raw = Encoding.ASCII.GetBytes("\aERR003\r");
        var act = () => ReplyParser.Parse(raw, "FOO");
        act.Should().Throw<PmacErrorException>().Which.Number.Should().Be(3);
        act.Should().Throw<PmacErrorException>().WithMessage("*unrecognized command*");
    }

    [Fact]
    public void Incomplete_replies_are_detected()
    {
        ReplyParser.IsComplete(Encoding.ASCII.GetBytes("12\r")).Should().BeFalse();
        ReplyParser.IsComplete(Encoding.ASCII.GetBytes("\aERR0")).Should().BeFalse();
    }
}
