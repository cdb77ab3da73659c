using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class CompletionDetectorTests
{
    [Fact]
    public void PR_is_asked_only_once_execution_reached_the_last_move_sent_or_everything_was_sent()
    {
        var d = new CompletionDetector();
        d.NeedsLinesAhead(allSent: false, lastSentLine: 20, trackedLine: 10).Should().BeFalse();
        d.NeedsLinesAhead(allSent: false, lastSentLine: 20, trackedLine: 20).Should().BeTrue();
        d.NeedsLinesAhead(allSent: true, lastSentLine: 20, trackedLine: 10).Should().BeTrue();
    }

    [Fact]
    public void An_empty_buffer_before_the_end_is_one_underrun_per_dry_spell()
    {
        var d = new CompletionDetector();
        d.Observe(allSent: false, linesAhead: 0, trackedLine: 10, finalTrackedLine: 100, running: true).Should().Be(BufferVerdict.Underrun);
        d.Observe(false, 0, 10, 100, true).Should().Be(BufferVerdict.None, "the same dry spell");
        d.Underruns.Should().Be(1);

        d.Observe(false, 3, 11, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(false, 0, 14, 100, true).Should().Be(BufferVerdict.Underrun, "lines arrived in between: a new dry spell");
        d.Underruns.Should().Be(2);
    }

    [Fact]
    public void Lines_ahead_of_execution_end_a_dry_spell()
    {
        var d = new CompletionDetector();
        d.Observe(false, 0, 10, 100, true).Should().Be(BufferVerdict.Underrun);
        d.NeedsLinesAhead(false, lastSentLine: 30, trackedLine: 12).Should().BeFalse();
        d.Observe(false, 0, 30, 100, true).Should().Be(BufferVerdict.Underrun);
        d.Underruns.Should().Be(2);
    }

    [Fact]
    public void A_held_job_with_an_empty_buffer_is_no_underrun()
    {
        var d = new CompletionDetector();
        d.Observe(false, 0, 10, 100, running: false).Should().Be(BufferVerdict.None);
        d.Underruns.Should().Be(0);
    }

    [Fact]
    public void Everything_sent_with_an_empty_buffer_and_M0_at_the_final_move_is_complete()
    {
        var d = new CompletionDetector();
        d.Observe(allSent: true, linesAhead: 1, trackedLine: 100, finalTrackedLine: 100, running: true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 100, 100, true).Should().Be(BufferVerdict.Completed);
        d.Underruns.Should().Be(0);
    }

    [Fact]
    public void When_M0_never_names_the_final_move_three_still_readings_of_an_empty_buffer_complete_the_job()
    {
        // Paper placement: M0 names the move before the executing one, so it may never read the final move.
        var d = new CompletionDetector();
        d.Observe(true, 0, 99, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 99, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 99, 100, true).Should().Be(BufferVerdict.Completed);
    }

    [Fact]
    public void A_moving_M0_or_lines_ahead_restart_the_still_readings()
    {
        var d = new CompletionDetector();
        d.Observe(true, 0, 97, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 97, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 98, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 1, 98, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 98, 100, true).Should().Be(BufferVerdict.None);
        d.Observe(true, 0, 98, 100, true).Should().Be(BufferVerdict.Completed);
    }
}
