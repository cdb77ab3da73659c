using System.Net;
using System.Net.Sockets;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>EthernetConnection against the simulator's TCP server over real loopback sockets.</summary>
public sealed class EthernetTransportTests : IAsyncLifetime
{
    private readonly ScriptedController _controller = new();
    private PmacTcpServer _server = null!;
    private EthernetConnection _connection = null!;

    public Task InitializeAsync()
    {
        _server = _controller.StartTcp();
        _connection = new EthernetConnection(new EthernetOptions { Port = _server.Port, Timeout = TimeSpan.FromSeconds(2) });
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _connection.DisposeAsync();
        await _server.DisposeAsync();
    }

    [Fact]
    public async Task Replies_are_parsed_without_ack()
    {
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947");
        (await _connection.GetResponseAsync("P500=80")).Should().BeEmpty();
        (await _connection.GetResponseAsync("P500")).Should().Be("80");
        _connection.Description.Should().Be($"tcp 127.0.0.1:{_server.Port}");
    }

    [Fact]
    public async Task Error_replies_throw_with_number_and_manual_text()
    {
        var act = () => _connection.GetResponseAsync("BAD");
        var e = (await act.Should().ThrowAsync<PmacErrorException>()).Which;
        e.Number.Should().Be(3);
        e.Message.Should().Contain("unrecognized command");
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947", "an error does not break the link");
    }

    [Theory]
    [InlineData(1398)]
    [InlineData(1399)]
    [InlineData(5000)]
    [InlineData(20000)]
    public async Task Long_replies_are_gathered_across_getbuffer(int length)
    {
        var reply = await _connection.GetResponseAsync($"LONG {length}");
        reply.Should().HaveLength(length);
        reply[length - 1].Should().Be((char)('A' + ((length - 1) % 26)));
    }

    [Fact]
    public async Task Download_sends_every_line_in_order_through_writebuffer()
    {
        var lines = Enumerable.Range(0, 5000).Select(i => $"X{i}.5 Y{i}").ToArray();
        var packetsBefore = _server.PacketsServed;
        await _connection.DownloadAsync(lines);
        _controller.Executed.Should().Equal(lines);
        (_server.PacketsServed - packetsBefore).Should().BeLessThan(lines.Length / 20, "lines are batched, many per packet");
    }

    [Fact]
    public async Task Download_error_in_the_middle_reports_the_line_and_runs_nothing_after_it()
    {
        var lines = Enumerable.Range(0, 3000).Select(i => i == 1777 ? "BAD LINE" : $"X{i}").ToArray();
        var act = () => _connection.DownloadAsync(lines);
        var e = (await act.Should().ThrowAsync<PmacErrorException>()).Which;
        e.LineInBatch.Should().Be(1777);
        e.Command.Should().Be("BAD LINE");
        e.Number.Should().Be(3);
        _controller.Executed.Should().Equal(lines.Take(1777), "the controller ran exactly the lines before the refused one");
    }

    [Fact]
    public async Task Pipelined_download_sends_every_line_in_order()
    {
        var lines = Enumerable.Range(0, 5000).Select(i => $"X{i}.5 Y{i}").ToArray();
        await _connection.DownloadAsync(lines, packetsInFlight: 8);
        _controller.Executed.Should().Equal(lines);
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947", "every reply was read: the next exchange is in step");
    }

    [Fact]
    public async Task Pipelined_download_refused_mid_way_reports_the_lines_stored_behind_the_gap()
    {
        // With four packets in flight the three sent after the refused one reach the controller before its reply
        // comes back: their lines are stored after the gap, and the exception counts them.
        var lines = Enumerable.Range(0, 3000).Select(i => i == 1777 ? "BAD LINE" : $"X{i}").ToArray();
        var act = () => _connection.DownloadAsync(lines, packetsInFlight: 4);
        var e = (await act.Should().ThrowAsync<PmacErrorException>()).Which;
        e.LineInBatch.Should().Be(1777);
        e.Number.Should().Be(3);
        e.LinesStoredAfterGap.Should().BeGreaterThan(0);
        _controller.Executed.Take(1777).Should().Equal(lines.Take(1777));
        var after = _controller.Executed.Skip(1777).ToList();
        after.Should().HaveCount(e.LinesStoredAfterGap, "the count is what the controller stored");
        var from = Array.IndexOf(lines, after[0]);
        from.Should().BeGreaterThan(1777, "the rest of the refused packet is not stored");
        after.Should().Equal(lines.Skip(from).Take(after.Count), "the packets behind the gap, whole and in order");
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947", "the replies of the packets in flight were all read");
    }

    [Fact]
    public async Task One_packet_in_flight_stores_nothing_after_a_refusal()
    {
        var lines = Enumerable.Range(0, 3000).Select(i => i == 1777 ? "BAD LINE" : $"X{i}").ToArray();
        var act = () => _connection.DownloadAsync(lines, packetsInFlight: 1);
        (await act.Should().ThrowAsync<PmacErrorException>()).Which.LinesStoredAfterGap.Should().Be(0);
        _controller.Executed.Should().Equal(lines.Take(1777));
    }

    [Fact]
    public async Task Flush_and_control_characters_reach_the_controller()
    {
        await _connection.FlushAsync();
        _controller.Flushes.Should().Be(1);
        (await _connection.ControlAsync('\x02')).Should().Be("812000804001\r");
    }

    [Fact]
    public async Task A_dropped_connection_is_reported_and_the_next_request_reconnects()
    {
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947");
        _server.DisconnectAll();
        await WaitUntil(() => _server.ClientCount == 0);
        var act = () => _connection.GetResponseAsync("VER");
        await act.Should().ThrowAsync<PmacLinkException>();
        _connection.IsConnected.Should().BeFalse();
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947");
    }

    [Fact]
    public async Task A_slow_controller_times_out_instead_of_hanging()
    {
        await using var slow = new EthernetConnection(new EthernetOptions { Port = _server.Port, Timeout = TimeSpan.FromMilliseconds(200) });
        var act = () => slow.GetResponseAsync("SLEEP 3000");
        (await act.Should().ThrowAsync<PmacLinkException>()).WithMessage("*no reply*200 ms*");
    }

    /// <summary>A loopback listener that accepts connections (the kernel does) and never answers.</summary>
    private static Socket MuteServer()
    {
        var mute = new Socket(SocketType.Stream, ProtocolType.Tcp);
        mute.Bind(new IPEndPoint(IPAddress.Loopback, 0));
        mute.Listen(1);
        return mute;
    }

    [Fact]
    public async Task A_server_that_accepts_but_never_answers_is_a_dead_link()
    {
        using var mute = MuteServer();
        await using var c = new EthernetConnection(new EthernetOptions { Port = ((IPEndPoint)mute.LocalEndPoint!).Port, Timeout = TimeSpan.FromMilliseconds(200) });
        var act = () => c.DownloadAsync(["X1", "X2"]);
        await act.Should().ThrowAsync<PmacLinkException>();
    }

    /// <summary>
    /// A request given up on is reset, never closed gracefully: after a close the kernel would go on retransmitting what
    /// it still held once a lost link came back, and the controller would store program lines after a resume had sent
    /// them again (issue 20: link-fault runs saw the old connection's requests arrive after the new one's).
    /// </summary>
    [Fact]
    public async Task A_request_whose_reply_timed_out_is_reset_so_the_controller_cannot_get_it_later()
    {
        using var mute = MuteServer();
        await using var c = new EthernetConnection(new EthernetOptions { Port = ((IPEndPoint)mute.LocalEndPoint!).Port, Timeout = TimeSpan.FromMilliseconds(200) });
        var act = () => c.DownloadAsync(["X1", "X2"]);
        await act.Should().ThrowAsync<PmacLinkException>();

        using var server = await mute.AcceptAsync();
        var buffer = new byte[4096];
        var got = await server.ReceiveAsync(buffer, SocketFlags.None);
        got.Should().Be(VrPmac.HeaderSize + 6, "the WRITEBUFFER packet with its two lines");
        var next = () => server.ReceiveAsync(buffer.AsMemory(), SocketFlags.None).AsTask();
        (await next.Should().ThrowAsync<SocketException>()).Which.SocketErrorCode.Should().Be(SocketError.ConnectionReset, "a reset, not a graceful end (0 bytes)");
    }

    [Fact]
    public async Task No_server_is_a_link_error_not_a_socket_exception()
    {
        var port = _server.Port;
        await _server.StopAsync();
        await using var c = new EthernetConnection(new EthernetOptions { Port = port, ConnectTimeout = TimeSpan.FromMilliseconds(500) });
        var act = () => c.GetResponseAsync("VER");
        (await act.Should().ThrowAsync<PmacLinkException>()).WithMessage("*cannot connect*");
    }

    [Fact]
    public async Task Cancellation_stops_the_wait_and_the_link_recovers()
    {
        using var cts = new CancellationTokenSource(TimeSpan.FromMilliseconds(100));
        var act = () => _connection.GetResponseAsync("SLEEP 1000", cts.Token);
        await act.Should().ThrowAsync<OperationCanceledException>();
        (await _connection.GetResponseAsync("VER")).Should().Be("1.947");
    }

    [Fact]
    public async Task Concurrent_callers_are_serialized_one_command_at_a_time()
    {
        var tasks = Enumerable.Range(0, 50).Select(i => _connection.GetResponseAsync($"P{i}={i}")).ToArray();
        await Task.WhenAll(tasks);
        var reads = await Task.WhenAll(Enumerable.Range(0, 50).Select(i => _connection.GetResponseAsync($"P{i}")));
        reads.Should().Equal(Enumerable.Range(0, 50).Select(i => i.ToString(System.Globalization.CultureInfo.InvariantCulture)));
    }

    private static async Task WaitUntil(Func<bool> condition)
    {
        for (var i = 0; i < 200 && !condition(); i++)
        {
            await Task.Delay(10);
        }
    }
}
