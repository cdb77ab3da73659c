using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class ExecutionPaceTests
{
    [Fact]
    public void The_feed_factor_is_the_override_over_100_or_the_feed_variable_over_the_programmed_feed()
    {
        var time = new ManualTime();
        var over = new ExecutionPace(time, null, FeedMode.Override) { Feed = 150 };
        over.FeedFactor(10).Should().Be(1.5);

        var paper = new ExecutionPace(time, new TenthSecondMoves(programmedFeed: 300), FeedMode.Paper) { Feed = 600 };
        paper.FeedFactor(10).Should().Be(2);

        new ExecutionPace(time, new TenthSecondMoves(programmedFeed: null), FeedMode.Paper) { Feed = 600 }.FeedFactor(10).Should().Be(1, "no programmed feed known");
        new ExecutionPace(time, null, FeedMode.Override).FeedFactor(10).Should().Be(1, "feed not read yet");
    }

    [Fact]
    public void The_lead_is_the_move_times_of_the_lines_ahead_at_the_live_feed()
    {
        var pace = new ExecutionPace(new ManualTime(), new TenthSecondMoves(programmedFeed: 300), FeedMode.Paper) { Feed = 600 };
        pace.LeadSeconds(trackedLine: 10, lastLine: 30, movesAhead: 20).Should().BeApproximately(1.0, 1e-9, "20 moves of 0.1 s at twice the programmed feed");
    }

    [Fact]
    public void Without_move_times_the_lead_and_the_ETA_come_from_the_measured_block_rate()
    {
        var time = new ManualTime();
        var pace = new ExecutionPace(time, null, FeedMode.Paper);
        pace.Restart();
        pace.LeadSeconds(10, 30, 20).Should().Be(0, "nothing measured yet");
        pace.EtaByBlockRate(100, 1100).Should().BeNull();

        time.Advance(0.1);
        pace.Observe(trackedLine: 5, movesReached: 10, counting: true);
        pace.BlocksPerSecond.Should().Be(0, "intervals shorter than 0.25 s are not measured");

        time.Advance(0.4);
        pace.Observe(trackedLine: 50, movesReached: 50, counting: true);
        pace.BlocksPerSecond.Should().BeApproximately(100, 1e-9);
        pace.LeadSeconds(50, 70, movesAhead: 20).Should().BeApproximately(0.2, 1e-9);
        pace.EtaByBlockRate(100, 1100).Should().Be(TimeSpan.FromSeconds(10));
        pace.Elapsed.Should().Be(TimeSpan.FromSeconds(0.5));
    }

    [Fact]
    public void The_ETA_from_move_times_is_the_program_seconds_left_at_the_live_feed()
    {
        var pace = new ExecutionPace(new ManualTime(), new TenthSecondMoves(programmedFeed: 300), FeedMode.Paper) { Feed = 600 };
        pace.EtaByMoveTimes(trackedLine: 11, finalTrackedLine: 110)!.Value.TotalSeconds.Should().BeApproximately(5.0, 1e-6, "100 moves of 0.1 s at twice the feed, nothing measured yet");
        new ExecutionPace(new ManualTime(), null, FeedMode.Paper).EtaByMoveTimes(11, 110).Should().BeNull();
    }

    /// <summary>Every line a 0.1 s move at <paramref name="programmedFeed"/>.</summary>
    private sealed class TenthSecondMoves(double? programmedFeed) : IMoveTimes
    {
        public double SecondsBetween(int afterLine, int throughLine) => Math.Max(0, throughLine - afterLine) * 0.1;

        public double? ProgrammedFeedAt(int line) => programmedFeed;
    }
}
