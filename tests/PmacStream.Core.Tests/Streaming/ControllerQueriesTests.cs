using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class ControllerQueriesTests
{
    [Theory]
    [InlineData("A80000020000000000", true)]   // in position, nothing queued
    [InlineData("A80000000000000000", false)]  // moving
    [InlineData("A80000220000000000", false)]  // in position but segments queued
    [InlineData("1", null)]
    [InlineData("ZZZZZZZZZZZZ", null)]
    public void The_status_word_says_whether_motion_stopped(string status, bool? stopped) =>
        ControllerQueries.MotionStopped(status).Should().Be(stopped);

    [Theory]
    [InlineData("A80001020000000000", true)]
    [InlineData("A80010020000000000", false)]
    [InlineData("", null)]
    public void The_status_word_says_whether_a_program_runs(string status, bool? running) =>
        ControllerQueries.ProgramRunning(status).Should().Be(running);

    [Fact]
    public async Task The_tracked_line_is_the_first_value_of_the_reply_rounded()
    {
        var (queries, port) = Rig(c => c == "M7" ? "12.0000001\r3" : "0");
        (await queries.TrackedLineAsync(default)).Should().Be(12);
        port.Executed.Should().Equal("M7");
    }

    [Fact]
    public async Task A_reply_that_is_no_number_is_a_link_fault_not_a_zero()
    {
        var (queries, _) = Rig(_ => "HELLO");
        await FluentActions.Awaiting(() => queries.TrackedLineAsync(default).AsTask()).Should().ThrowAsync<PmacLinkException>();
        await FluentActions.Awaiting(() => queries.LinesAheadAsync(default).AsTask()).Should().ThrowAsync<PmacLinkException>();
        await FluentActions.Awaiting(() => queries.ProbeAsync("P501", default).AsTask()).Should().ThrowAsync<PmacLinkException>();
    }

    [Fact]
    public async Task The_feed_is_the_feed_variable_or_the_override_and_a_refused_read_is_unknown()
    {
        Func<string, string> reply = c => c == "P500" ? "ERR003" : c == "P9" ? "800" : "150";
        (await Rig(reply, FeedMode.Paper).Queries.FeedAsync(default)).Should().BeNull();
        (await Rig(reply, FeedMode.Paper, "P9").Queries.FeedAsync(default)).Should().Be(800);
        var (queries, port) = Rig(reply, FeedMode.Override);
        (await queries.FeedAsync(default)).Should().Be(150);
        port.Executed.Should().Equal("&1 %");
    }

    [Fact]
    public async Task A_status_of_another_shape_is_asked_once_and_then_motion_counts_as_stopped()
    {
        var (queries, port) = Rig(_ => "1");
        (await queries.MotionStoppedAsync(default)).Should().BeTrue();
        queries.StatusUnknown.Should().BeTrue();
        (await queries.MotionStoppedAsync(default)).Should().BeTrue();
        port.Executed.Should().Equal("&1??");
    }

    [Fact]
    public async Task An_error_reply_to_the_status_is_a_fault_not_stopped()
    {
        var (queries, _) = Rig(_ => "ERR001");
        await FluentActions.Awaiting(() => queries.MotionStoppedAsync(default).AsTask()).Should().ThrowAsync<PmacErrorException>();
        queries.StatusUnknown.Should().BeFalse();
    }

    [Fact]
    public async Task No_online_command_is_sent_while_the_buffer_is_open_except_CLOSE()
    {
        var port = new ScriptedController(_ => string.Empty);
        var channel = new ControllerChannel(new InProcessConnection(port.OpenPort())) { BufferOpen = true };

        await FluentActions.Awaiting(() => channel.OnlineAsync("M0", default).AsTask()).Should().ThrowAsync<InvalidOperationException>();
        port.Executed.Should().BeEmpty("it would have been stored in the buffer");

        await channel.OnlineAsync("close", default);
        channel.BufferOpen.Should().BeFalse();
        await channel.OnlineAsync("M0", default);
        port.Executed.Should().Equal("close", "M0");
    }

    [Fact]
    public async Task A_refused_CLOSE_means_nothing_was_open()
    {
        var channel = new ControllerChannel(new InProcessConnection(new ScriptedController(_ => "ERR003").OpenPort())) { BufferOpen = true };
        await channel.TryCloseAsync(default);
        channel.BufferOpen.Should().BeFalse();
    }

    internal static (ControllerQueries Queries, ScriptedController Port) Rig(Func<string, string> reply, FeedMode feed = FeedMode.Paper, string? feedVariable = null)
    {
        var port = new ScriptedController(reply);
        var queries = new ControllerQueries(new ControllerChannel(new InProcessConnection(port.OpenPort())), new CoordinateSystemCommands(1, feed, feedVariable), new SyncAssignment("M7"));
        return (queries, port);
    }
}
