using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Preparation;

public class SyncAssignmentTests
{
    private const string Source = "G01 X1\nM08\nN30 G01 X2 F300\nG04 P500\n";

    [Theory]
    [InlineData(TrackingPlacement.Exact, false)]
    [InlineData(TrackingPlacement.Exact, true)]
    [InlineData(TrackingPlacement.Paper, false)]
    [InlineData(TrackingPlacement.Paper, true)]
    public void The_splitter_writes_the_assignment_exactly_as_the_type_places_it(TrackingPlacement placement, bool keepN)
    {
        var options = new SplitOptions { Tracking = placement, KeepN = keepN, ProgramTail = "" };
        var sync = SyncAssignment.Of(options);
        using var tp = new TempProgram(Source);

        ChunkText.Body(tp.Split(options), options).Should().Equal(
            sync.Place("G01 X1 F(P500)", 1),
            "M08",
            "P500=300",
            sync.Place("G01 X2 F(P500)", 3, keepN ? "N30" : null),
            sync.Place("G04 P500", 4));
    }

    [Fact]
    public void Exact_placement_leads_the_line_and_paper_placement_ends_it()
    {
        new SyncAssignment().Place("G01 X1", 7).Should().Be("M0==7 G01 X1");
        new SyncAssignment(placement: TrackingPlacement.Paper).Place("G01 X1", 7, "N70").Should().Be("N70 G01 X1 M0==7");
        new SyncAssignment(placement: TrackingPlacement.Paper).LagsOneMove.Should().BeTrue();
        new SyncAssignment().LagsOneMove.Should().BeFalse();
    }

    [Fact]
    public void Every_move_the_splitter_wrote_reads_back_as_its_source_line_with_any_variable()
    {
        var options = new SplitOptions { TrackVariable = "M123", Tracking = TrackingPlacement.Paper, ProgramTail = "" };
        using var tp = new TempProgram(Source);
        var result = tp.Split(options);
        var sync = SyncAssignment.Of(result.Manifest);

        sync.Variable.Should().Be("M123");
        var read = ChunkText.Body(result, options).Select(l => sync.TryRead(l, out var n) ? n : 0).ToList();
        read.Should().Equal(1, 0, 0, 3, 4);
    }

    [Theory]
    [InlineData("M0==12 G01 X1", true, 12)]
    [InlineData("g01 x1 m0 == 12", true, 12)]
    [InlineData("N5 M0==0 X1", true, 0)]
    [InlineData("M08", false, 0)]
    [InlineData("M0=12 X1", false, 0)]
    [InlineData("M01==12", false, 0)]
    [InlineData("PM0==12", false, 0)]
    [InlineData("M10==12", false, 0)]
    public void A_line_reads_as_tracked_only_with_this_variable_and_the_synchronous_operator(string line, bool tracked, int sourceLine)
    {
        var sync = new SyncAssignment("M0");
        sync.TryRead(line, out var n).Should().Be(tracked);
        n.Should().Be(sourceLine);
    }

    [Fact]
    public void Without_the_assignment_a_marker_alone_is_no_motion_left_to_classify()
    {
        var sync = new SyncAssignment();
        sync.Without("M0==12 G01 X1 F(P500)").Should().Be("  G01 X1 F(P500)");
        sync.Without("M0==12").Trim().Should().BeEmpty();
        sync.Without("M08").Should().Be("M08");
    }

    [Fact]
    public void The_online_read_and_reset_name_the_variable_and_a_blank_one_is_M0()
    {
        var sync = new SyncAssignment("  ");
        sync.Variable.Should().Be("M0");
        sync.Prefix.Should().Be("M0==");
        sync.ReadCommand.Should().Be("M0");
        sync.ResetCommand.Should().Be("M0=0");
        sync.Format(42).Should().Be("M0==42");
        new SyncAssignment(" M7 ").ResetCommand.Should().Be("M7=0");
    }

    [Fact]
    public void A_chunked_program_classifies_lines_through_its_manifests_assignment()
    {
        var options = new SplitOptions { TrackVariable = "M9", ProgramTail = "" };
        using var tp = new TempProgram(Source);
        var program = ChunkedProgram.Open(tp.Split(options).OutputDirectory);

        program.Sync.Variable.Should().Be("M9");
        program.Classify("M9==3 G01 X2 F(P500)").TrackedLine.Should().Be(3);
        program.Classify("M0==3 G01 X2 F(P500)").TrackedLine.Should().Be(0, "another variable is not this program's tracking");
        program.Classify("M9==3").IsMotion.Should().BeFalse("a marker alone carries no move");
    }
}
