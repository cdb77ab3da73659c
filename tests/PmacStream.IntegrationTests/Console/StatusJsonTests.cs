using System.Text.Json;
using PmacStream.Cli.Commands;
using PmacStream.Machine;

namespace PmacStream.IntegrationTests.Console;

/// <summary>What `status --json` writes of a sample: the fields the issue names, the spindle and distance to go.</summary>
public sealed class StatusJsonTests
{
    private static MachineState Sample(SpindleReadout? spindle) =>
        new(MachineMode.Running, [new AxisState("X", 1, 12.5, 2.5, 7.25, true), new AxisState("A", 4, 90, 90, -45, false)], [], "G55", 100, 600, 598.2, spindle?.Programmed, 12, "job 3 running")
        {
            Spindle = spindle,
        };

    [Fact]
    public void A_sample_carries_the_spindle_programmed_and_actual_and_each_axis_to_go()
    {
        using var doc = JsonDocument.Parse(StatusCommand.Json(Sample(new SpindleReadout(1200, 1180, true, false))));
        var r = doc.RootElement;
        r.GetProperty("spindle").GetProperty("programmed").GetDouble().Should().Be(1200);
        r.GetProperty("spindle").GetProperty("actual").GetDouble().Should().Be(1180);
        r.GetProperty("spindle").GetProperty("direction").GetString().Should().Be("cw");
        r.GetProperty("axes")[0].GetProperty("toGo").GetDouble().Should().Be(7.25);
        r.GetProperty("axes")[1].GetProperty("name").GetString().Should().Be("A");
        r.GetProperty("homed").GetProperty("A").GetBoolean().Should().BeFalse();
        r.GetProperty("programmedFeed").GetDouble().Should().Be(600);
        r.GetProperty("feedOverride").GetDouble().Should().Be(100);
        StatusCommand.Table(Sample(new SpindleReadout(1200, 1180, true, false))).Should().Contain("spindle 1180 rpm (programmed 1200, cw)");
    }

    [Fact]
    public void Without_a_spindle_reading_the_key_is_left_out()
    {
        using var doc = JsonDocument.Parse(StatusCommand.Json(Sample(null)));
        doc.RootElement.TryGetProperty("spindle", out _).Should().BeFalse();
    }
}
