using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Preview;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Preview;

/// <summary>
/// Under G41/G42 an inside corner moves the end of the move before it back to where the offset paths cross (one block
/// of lookahead, as rs274ngc): the preview and the ETA's move times use that amended end, the one the splitter sends
/// and the controller runs, not the end reported before the next move was known.
/// </summary>
public sealed class CompensatedCornerPreviewTests : IDisposable
{
    // A pocket counter-clockwise under G41 D1 (radius 5): every corner is an inside one.
    private const string Pocket = "O1\nG21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\nX100.\nY50.\nX0\nY0\nX50.\nG40 X50. Y25.\nM30\n";

    private readonly TestFolder _temp = new("preview-comp");

    public void Dispose() => _temp.Dispose();

    private static MachineProfile Fanuc()
    {
        var json = JsonNode.Parse(MachineProfile.Named("fanuc-mill")!.ToJson())!.AsObject();
        json["toolRadii"] = JsonNode.Parse("""{ "1": 5 }""");
        return MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radii");
    }

    private string Write()
    {
        var path = Path.Combine(_temp.Path, "pocket.nc");
        File.WriteAllText(path, Pocket);
        return path;
    }

    [Fact]
    public void The_preview_ends_each_move_where_the_splitter_sends_it_at_an_inside_corner()
    {
        var path = Write();
        var segments = new GCodeToolpathSource(path, Fanuc()).ReadSegments().ToList();
        var ends = segments.Where(s => s.SourceLine is >= 5 and <= 10).Select(s => (s.SourceLine, s.End)).ToList();
        ends.Should().Equal(
            (5L, new Point3(55, 5, -1)), (6L, new Point3(95, 5, -1)), (7L, new Point3(95, 45, -1)),
            (8L, new Point3(5, 45, -1)), (9L, new Point3(5, 5, -1)), (10L, new Point3(50, 5, -1)));
        for (var i = 1; i < segments.Count; i++)
        {
            segments[i].Start.Should().Be(segments[i - 1].End, "the path is continuous: a move starts where the one before ends");
        }

        // The splitter sends the same ends (the controller runs these).
        var result = Splitter.Split(path, new SplitOptions { OutDir = Path.Combine(_temp.Path, "chunks"), CheckProfile = Fanuc() });
        string.Concat(result.ChunkPaths.Select(File.ReadAllText)).Should().ContainAll("X55 Y5 Z-1", "X95 Y5 Z-1", "X95 Y45 Z-1", "X5 Y45 Z-1", "X5 Y5 Z-1");
    }

    [Fact]
    public void The_ETA_times_the_moves_as_amended()
    {
        var path = Write();
        var table = MoveTimeTable.FromProgram(path, profile: Fanuc());
        var segments = new GCodeToolpathSource(path, Fanuc()).ReadSegments().Where(s => s.SourceLine is >= 5 and <= 10).ToList();
        var expected = segments.Sum(s => s.Start.DistanceTo(s.End)) / 100.0 * 60.0; // F100 mm/min, straight moves
        table.SecondsBetween(4, 10).Should().BeApproximately(expected, 1e-6);
        expected.Should().BeApproximately((Math.Sqrt(425) + 40 + 40 + 90 + 40 + 45) / 100.0 * 60.0, 1e-6, "the entry from (50, 25) to (55, 5), then 40 + 40 + 90 + 40 + 45 mm on the offset path");
    }

    // The pocket with a plunge and a retract between its XY moves: queued behind the held move, they run at the crossing.
    private const string Plunged = "O1\nG21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\nX100.\nZ-2.\nY50.\nZ-1.\nX0\nY0\nX50.\nG40 X50. Y25.\nM30\n";

    [Fact]
    public void The_preview_and_the_ETA_run_Z_blocks_queued_behind_a_held_move_at_the_crossing()
    {
        var path = Path.Combine(_temp.Path, "plunged.nc");
        File.WriteAllText(path, Plunged);
        var segments = new GCodeToolpathSource(path, Fanuc()).ReadSegments().Where(s => s.SourceLine is >= 5 and <= 10).ToList();
        segments.Select(s => (s.SourceLine, s.End)).Should().Equal(
            (5L, new Point3(55, 5, -1)), (6L, new Point3(95, 5, -1)), (7L, new Point3(95, 5, -2)),
            (8L, new Point3(95, 45, -2)), (9L, new Point3(95, 45, -1)), (10L, new Point3(5, 45, -1)));
        for (var i = 1; i < segments.Count; i++)
        {
            segments[i].Start.Should().Be(segments[i - 1].End, "the path is continuous: the plunge starts where the held move ends");
        }

        // The splitter sends the same ends.
        var result = Splitter.Split(path, new SplitOptions { OutDir = Path.Combine(_temp.Path, "plunged-chunks"), CheckProfile = Fanuc() });
        string.Concat(result.ChunkPaths.Select(File.ReadAllText)).Should().ContainAll("X55 Y5 Z-1", "X95 Y5 Z-1", "X95 Y5 Z-2", "X95 Y45 Z-2", "X95 Y45 Z-1", "X5 Y45 Z-1");

        // The ETA: the held moves shortened, the plunges their own 1 mm each, at F100.
        var table = MoveTimeTable.FromProgram(path, profile: Fanuc());
        var expected = segments.Sum(s => s.Start.DistanceTo(s.End)) / 100.0 * 60.0;
        table.SecondsBetween(4, 10).Should().BeApproximately(expected, 1e-6);
        expected.Should().BeApproximately((Math.Sqrt(425) + 40 + 1 + 40 + 1 + 90) / 100.0 * 60.0, 1e-6);
    }

    [Fact]
    public void Amending_an_arc_times_the_angle_it_still_sweeps()
    {
        // A quarter circle of radius 10 about the origin, its end moved back to the eighth: half the time.
        var m = new CanonMotion(3, MotionKind.ArcCcw, new Point3(10, 0, 0), new Point3(0, 10, 0), new Point3(0, 0, 0), Math.PI * 5, 6, 100);
        var amended = MoveTimeTable.Amended(m, new Point3(10 * Math.Cos(Math.PI / 4), 10 * Math.Sin(Math.PI / 4), 0));
        amended.Seconds.Should().BeApproximately(3, 1e-9);
        amended.Length.Should().BeApproximately(Math.PI * 2.5, 1e-9);
    }
}
