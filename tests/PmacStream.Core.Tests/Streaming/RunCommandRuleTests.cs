using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>The run command of a recovered or resumed start goes only to a controller that has not started the program.</summary>
public class RunCommandRuleTests
{
    [Theory]
    [InlineData(true, 120, "running")]
    [InlineData(true, 0, "running its preamble, before the first tracked block")]
    [InlineData(true, 64, "held (feed hold keeps the program running)")]
    [InlineData(false, 64, "stopped at M00 at line 64")]
    [InlineData(false, 2001, "completed and idle at the last line")]
    [InlineData(null, 0, "status not understood")]
    [InlineData(null, 64, "status not understood, a line executed")]
    public void The_run_command_is_not_sent_to_a_program_that_runs_or_ran(bool? running, int m0, string state)
    {
        var seen = new ControllerReading(m0, running, 0, null);
        RunCommandRule.MaySend(seen).Should().BeFalse(state);
        RunCommandRule.WhyNot(seen, "M0").Should().Contain($"M0={m0}", state);
    }

    [Fact]
    public void The_run_command_goes_to_a_program_never_started()
    {
        var seen = new ControllerReading(0, false, 37, null);
        RunCommandRule.MaySend(seen).Should().BeTrue("nothing runs and no tracked block executed");
        RunCommandRule.WhyNot(seen, "M0").Should().BeNull();
    }
}
