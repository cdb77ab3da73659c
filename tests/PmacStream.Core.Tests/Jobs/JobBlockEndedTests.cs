using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Machine;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>
/// After an alarm, the block the tracking variable names counts executed only when the axes stand at its end to the
/// controller's position report (issue 25's fault proof finding: 0.001 mm counted a move killed 0.5 um short as done,
/// while the controller had not finished it).
/// </summary>
public class JobBlockEndedTests
{
    private static readonly MachineAxis[] Axes = [new("X", 1, 1000), new("Y", 2, 1000), new("Z", 3, 1000)];

    [Theory]
    [InlineData(0, true)]
    [InlineData(0.00002, true)] // a report's rounding (1/32 count) and the chunk's 5 decimals
    [InlineData(0.0005, false)] // counted done by the old 0.001 mm rule: the fault proof's lost block
    [InlineData(0.0001, false)]
    public void A_block_counts_ended_only_at_its_end_to_the_position_report(double shortBy, bool ended)
    {
        var end = new Point3(10, 20, -1);
        Job.StandsAt(new Point3(10 - shortBy, 20, -1), end, Axes).Should().Be(ended);
        Job.StandsAt(new Point3(10, 20, -1 + shortBy), end, Axes).Should().Be(ended, "every axis, Z too");
    }

    [Fact]
    public void The_window_is_half_the_simulators_so_both_say_the_same()
    {
        // The simulator finds an aborted move ended within 1/8 count + 2e-5 units; the host within 1/16 count + 1e-5 mm.
        var sim = new Sim.SimOptions();
        var simWindow = (sim.AbortAtEndCounts / 1000) + sim.AbortAtEndUnits;
        var end = new Point3(0, 0, 0);
        Job.StandsAt(new Point3((simWindow / 2) - 1e-12, 0, 0), end, Axes).Should().BeTrue();
        Job.StandsAt(new Point3((simWindow / 2) + 1e-9, 0, 0), end, Axes).Should().BeFalse();
    }
}
