using PmacStream.Pmac;
using PmacStream.Sim.Servers;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>SerialConnection (System.IO.Ports) against the simulator's serial server through a socat pty pair.</summary>
public sealed class SerialTransportTests(ITestOutputHelper output) : IAsyncLifetime
{
    private readonly ScriptedController _controller = new();
    private SocatPair? _pair;
    private PmacSerialServer? _server;
    private SerialConnection? _connection;

    public Task InitializeAsync() => Task.CompletedTask;

    /// <summary>
    /// The pty pair, the simulator's serial server on one end and the transport on the other. Reports the test
    /// SKIPPED (a fixture's set-up cannot) when socat is not on PATH.
    /// </summary>
    private SerialConnection Connect()
    {
        _pair = SocatPair.Start();
        _server = PmacSerialServer.OpenDevice(_controller.OpenPort, _pair.A);
        _server.Start();
        _connection = new SerialConnection(new SerialOptions { PortName = _pair.B, Settings = new SerialSettings(115200), Timeout = TimeSpan.FromSeconds(2) });
        output.WriteLine($"pty pair {_pair.A} <-> {_pair.B}");
        return _connection;
    }

    public async Task DisposeAsync()
    {
        if (_connection is not null)
        {
            await _connection.DisposeAsync();
        }

        _pair?.Kill();
        if (_server is not null)
        {
            await _server.DisposeAsync();
        }

        _pair?.Dispose();
    }

    [SkippableFact]
    public async Task Replies_and_errors_over_the_pty()
    {
        var connection = Connect();
        (await connection.GetResponseAsync("VER")).Should().Be("1.947");
        (await connection.GetResponseAsync("P500=80")).Should().BeEmpty();
        (await connection.GetResponseAsync("p500")).Should().Be("80");
        var act = () => connection.GetResponseAsync("BAD");
        (await act.Should().ThrowAsync<PmacErrorException>()).Which.Number.Should().Be(3);
        (await connection.GetResponseAsync("VER")).Should().Be("1.947");
    }

    [SkippableFact]
    public async Task Long_reply_is_read_to_its_ack()
    {
        var connection = Connect();
        (await connection.GetResponseAsync("LONG 6000")).Should().HaveLength(6000);
    }

    [SkippableFact]
    public async Task Download_error_in_the_middle_reports_the_line_and_sends_nothing_after_it()
    {
        var connection = Connect();
        var lines = Enumerable.Range(0, 300).Select(i => i == 123 ? "BAD" : $"X{i}").ToArray();
        var act = () => connection.DownloadAsync(lines);
        (await act.Should().ThrowAsync<PmacErrorException>()).Which.LineInBatch.Should().Be(123);
        _controller.Executed.Should().Equal(lines.Take(123));
        await WaitUntil(() => _server!.CommandsServed >= 124);
        await Task.Delay(100);
        _server!.CommandsServed.Should().Be(124, "the refused line was the last one sent");
    }

    [SkippableFact]
    public async Task Flush_and_control_characters()
    {
        var connection = Connect();
        await connection.FlushAsync();
        await WaitUntil(() => _controller.Flushes == 1);
        _controller.Flushes.Should().Be(1);
        (await connection.ControlAsync('\x02')).Should().Be("812000804001\r");
    }

    [SkippableFact]
    public async Task A_slow_controller_times_out_and_the_line_recovers()
    {
        var connection = Connect();
        await using var quick = new SerialConnection(SerialPorts.Open(_pair!.B, new SerialSettings(115200)), TimeSpan.FromMilliseconds(300));
        await connection.DisposeAsync();
        var act = () => quick.GetResponseAsync("SLEEP 800");
        (await act.Should().ThrowAsync<PmacLinkException>()).WithMessage("*no complete reply*");

        // Let the late ACK arrive before the next command, so the test shows it is discarded (not a race).
        await WaitUntil(() => _server!.CommandsServed >= 1);
        await Task.Delay(300);
        (await quick.GetResponseAsync("VER")).Should().Be("1.947", "the late ACK was discarded before the next command");
    }

    [SkippableFact]
    public async Task A_timeout_fires_on_time_even_when_the_thread_pool_is_busy()
    {
        var connection = Connect();
        // An HMI can keep every pool thread busy. System.IO.Ports on Unix ends timed-out reads from a pool-thread
        // timer, so before SystemIoSerialPort polled for data itself this read waited for the late ACK and took it
        // as the reply to the command that had timed out.
        await using var quick = new SerialConnection(SerialPorts.Open(_pair!.B, new SerialSettings(115200)), TimeSpan.FromMilliseconds(300));
        await connection.DisposeAsync();
        using var release = new ManualResetEventSlim();
        ThreadPool.GetMinThreads(out var workers, out _);
        var blockers = Enumerable.Range(0, workers + 4).Select(_ => Task.Run(() => release.Wait())).ToArray();
        try
        {
            var clock = System.Diagnostics.Stopwatch.StartNew();
            var act = () => quick.GetResponseAsync("SLEEP 1500");
            (await act.Should().ThrowAsync<PmacLinkException>()).WithMessage("*no complete reply*");
            clock.Elapsed.Should().BeLessThan(TimeSpan.FromMilliseconds(1400), "the 300 ms timeout fired before the controller's late reply");
        }
        finally
        {
            release.Set();
            await Task.WhenAll(blockers);
        }

        await WaitUntil(() => _server!.CommandsServed >= 1);
        await Task.Delay(300);
        (await quick.GetResponseAsync("VER")).Should().Be("1.947");
    }

    [SkippableFact]
    public async Task A_pulled_cable_is_a_link_error()
    {
        var connection = Connect();
        (await connection.GetResponseAsync("VER")).Should().Be("1.947");
        _pair!.Kill();
        var act = () => connection.GetResponseAsync("VER");
        await act.Should().ThrowAsync<PmacLinkException>();
    }

    private static async Task WaitUntil(Func<bool> condition)
    {
        for (var i = 0; i < 1000 && !condition(); i++)
        {
            await Task.Delay(10);
        }
    }
}
