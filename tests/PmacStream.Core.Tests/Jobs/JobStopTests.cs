using PmacStream.Jobs;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>The operator's continue (Enter at a program stop) acts on the stop it was given for, and on no later one.</summary>
public class JobStopTests
{
    private static StreamingStatus At(SessionState state, ProgramStop? stop) =>
        new(state, 1, 100, 1, stop?.Line ?? 10, 5, 5, null, TimeSpan.Zero, null, 1, 100, 0, string.Empty, stop);

    [Fact]
    public void A_continue_goes_on_at_its_own_stop_only()
    {
        var m00 = new ProgramStop(64, "M00");
        var m01 = new ProgramStop(132, "M01");
        Job.ContinuesNow(At(SessionState.Stopped, m00), continueAtStops: false, continueFrom: m00).Should().BeTrue();
        Job.ContinuesNow(At(SessionState.Stopped, m00), continueAtStops: false, continueFrom: null).Should().BeFalse("nobody pressed Enter");

        // Enter was pressed at line 64, but the controller was continued from its panel first: the stop at 132 waits.
        Job.ContinuesNow(At(SessionState.Stopped, m01), continueAtStops: false, continueFrom: m00).Should().BeFalse();
        Job.ContinuesNow(At(SessionState.Running, null), continueAtStops: false, continueFrom: m00).Should().BeFalse();

        // --stops continue: every stop.
        Job.ContinuesNow(At(SessionState.Stopped, m01), continueAtStops: true, continueFrom: null).Should().BeTrue();
    }
}
