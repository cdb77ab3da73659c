using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>The one start-from-line planner: work coordinates, both safe-Z modes, and the block's own feed.</summary>
public sealed class StartPlanTests : IDisposable
{
    private readonly TestFolder _temp = new("plan");

    public void Dispose() => _temp.Dispose();

    private static MachineProfile WithG54(double x, double y, double z)
    {
        var json = JsonNode.Parse(MachineProfile.Default.ToJson())!;
        json["workOffsets"] = new JsonObject { ["G54"] = new JsonArray(x, y, z) };
        return MachineProfile.Parse(json.ToJsonString());
    }

    private string Source(string text)
    {
        var path = Path.Combine(_temp.Path, $"plan-{Guid.NewGuid():N}.nc");
        File.WriteAllText(path, text);
        return path;
    }

    private const string Part =
        "G21 G17 G90 G54\n" +    // 1
        "T2 M06\n" +             // 2
        "S8000 M03\n" +          // 3
        "G00 Z25\n" +            // 4  highest Z (work) so far
        "G00 X10 Y20\n" +        // 5
        "M08\n" +                // 6
        "G01 Z-1 F200\n" +       // 7
        "G01 X40 F900\n" +       // 8
        "G01 Y60 F1200\n" +      // 9  block with its own F
        "G01 X10\n" +            // 10
        "M30\n";

    [Fact]
    public void The_preamble_is_in_work_coordinates_of_the_active_offset()
    {
        var src = Source(Part);
        try
        {
            var profile = WithG54(100, 50, -200);
            var plan = StartFromLine.Plan(src, 9, new StartPlanOptions { Profile = profile, SafeZ = 10 });

            plan.Line.Should().Be(9);
            plan.Start.Should().Be(new Point3(40, 20, -1), "the end of line 8 in G54 work coordinates, not machine (140, 70, -201)");
            plan.GCode.Should().Contain("G00 X40 Y20").And.Contain("G01 Z-1 F500").And.Contain("G90 G00 Z10");
            plan.SafeZ.Should().Be(10);

            // Order: modal state first (units/plane/offset, tool, spindle, coolant), then retract, XY, feed down, then modes and feed.
            var g = plan.GCode.ToList();
            g[0].Should().StartWith("G99.9 ", "the library's power-on state first: the controller may hold another job's shifts");
            g[1].Should().Be("G17 G54", "the controller preamble is in millimetres: no units code");
            var retract = g.IndexOf("G90 G00 Z10");
            g.Take(retract).Should().NotContain(l => l.StartsWith("T", StringComparison.Ordinal), "the host hands the tool to M06; a T word would call PROG 1002").And.Contain("S8000 M03").And.Contain("M08");
            g.Skip(retract).Should().Equal("G90 G00 Z10", "G00 X40 Y20", "G01 Z-1 F500", "G90 G01 F1200");
        }
        finally
        {
            File.Delete(src);
        }
    }

    [Fact]
    public void Highest_so_far_retracts_above_the_highest_Z_reached_in_work_coordinates()
    {
        var src = Source(Part);
        try
        {
            var profile = WithG54(100, 50, -200);
            var plan = StartFromLine.Plan(src, 9, new StartPlanOptions { Profile = profile, SafeZMode = SafeZMode.HighestSoFar, Clearance = 3, SafeZ = 10 });
            plan.SafeZ.Should().Be(28, "Z25 (work) was the highest before line 9, plus 3");
            plan.GCode.Should().Contain("G90 G00 Z28");

            // Nothing moved before the first block: the fixed height is the fallback.
            var first = StartFromLine.Plan(src, 1, new StartPlanOptions { SafeZMode = SafeZMode.HighestSoFar, SafeZ = 12 });
            first.Line.Should().Be(4);
            first.SafeZ.Should().Be(12);
        }
        finally
        {
            File.Delete(src);
        }
    }

    [Fact]
    public void The_preamble_feed_is_the_one_the_block_runs_with()
    {
        var src = Source(Part);
        try
        {
            // Line 9 sets F1200 itself; in paper mode that travels as P500=1200 on a line before the block's marker,
            // which a start at the block skips: the preamble must leave P500 at 1200, not the 900 of line 8.
            var plan = StartFromLine.Plan(src, 9, new StartPlanOptions { FeedMode = FeedMode.Paper });
            plan.PmacLines.Last(l => l.StartsWith("P500=", StringComparison.Ordinal)).Should().Be("P500=1200");
            plan.State.Feed.Should().Be(900, "the state before the block stays what it was");

            var plain = StartFromLine.Plan(src, 10, new StartPlanOptions { FeedMode = FeedMode.Paper });
            plain.PmacLines.Last(l => l.StartsWith("P500=", StringComparison.Ordinal)).Should().Be("P500=1200", "line 10 inherits 1200");
        }
        finally
        {
            File.Delete(src);
        }
    }
}
