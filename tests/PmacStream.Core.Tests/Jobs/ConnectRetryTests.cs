using System.Net;
using System.Net.Sockets;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Sim.Servers;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>
/// First contact over a lossy link: a lost SYN or first reply costs TCP's initial retransmission timeout, which can
/// outlast one reply timeout. The job service asks again on a new connection (the query changes nothing) before it
/// calls a controller unreachable. Here the first connection is accepted and never answered, as a link that lost the
/// reply; later ones reach a simulator.
/// </summary>
public sealed class ConnectRetryTests : IAsyncLifetime
{
    private readonly TestFolder _folder = new("connect-retry");
    private readonly PmacSimulator _sim = new(new SimOptions());
    private PmacTcpServer _server = null!;
    private readonly TcpListener _front = new(IPAddress.Loopback, 0);
    private readonly CancellationTokenSource _stop = new();
    private readonly List<TcpClient> _held = [];
    private int _accepted;

    public Task InitializeAsync()
    {
        SimRig.LoadLibrary(_sim.OpenPort("library"));
        var ethernet = _sim.OpenPort("ethernet");
        _server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        _server.Start();
        _front.Start();
        _ = Task.Run(AcceptAsync);
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _stop.CancelAsync();
        _front.Stop();
        foreach (var c in _held)
        {
            c.Dispose();
        }
        await _server.DisposeAsync();
        _sim.Dispose();
        _stop.Dispose();
        _folder.Dispose();
    }

    [Fact]
    public async Task A_first_contact_that_gets_no_reply_is_tried_again_on_a_new_connection()
    {
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_folder.Path, "jobs.db") });
        await using var link = await service.ConnectAsync(ConnectionSpec.Ethernet($"127.0.0.1:{Port}"));

        (await link.Connection.GetResponseAsync("I10")).Should().NotBeNullOrWhiteSpace("the second connection reaches the controller");
        Volatile.Read(ref _accepted).Should().Be(2, "the silent first connection was given up and a new one made");
    }

    [Fact]
    public async Task With_one_attempt_a_silent_controller_is_unreachable()
    {
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_folder.Path, "jobs.db"), ConnectAttempts = 1 });
        var act = () => service.ConnectAsync(ConnectionSpec.Ethernet($"127.0.0.1:{Port}"));

        (await act.Should().ThrowAsync<JobException>()).Which.Message.Should().Contain("cannot reach the controller").And.Contain("no reply to 'VERSION'");
        Volatile.Read(ref _accepted).Should().Be(1);
    }

    private int Port => ((IPEndPoint)_front.LocalEndpoint).Port;

    private async Task AcceptAsync()
    {
        try
        {
            while (!_stop.IsCancellationRequested)
            {
                var client = await _front.AcceptTcpClientAsync(_stop.Token);
                if (Interlocked.Increment(ref _accepted) == 1)
                {
                    _held.Add(client); // reads nothing, answers nothing: the reply was lost
                    continue;
                }

                _ = PipeAsync(client);
            }
        }
        catch (Exception e) when (e is OperationCanceledException or ObjectDisposedException or SocketException)
        {
            // The test ended.
        }
    }

    private async Task PipeAsync(TcpClient client)
    {
        using (client)
        using (var upstream = new TcpClient())
        {
            await upstream.ConnectAsync(IPAddress.Loopback, _server.Port);
            var a = client.GetStream();
            var b = upstream.GetStream();
            try
            {
                await Task.WhenAny(a.CopyToAsync(b, _stop.Token), b.CopyToAsync(a, _stop.Token));
            }
            catch (Exception e) when (e is OperationCanceledException or IOException or ObjectDisposedException)
            {
                // One side closed.
            }
        }
    }
}
