using System.Diagnostics;
using System.Net;
using PmacStream.Sim;
using PmacStream.Sim.Servers;

namespace PmacStream.Testing;

/// <summary>
/// The rig's controller layer served over a socket: <see cref="SimHarness"/>'s simulator behind a VR_PMAC TCP server
/// on its one port (one Ethernet port, as a Turbo PMAC has), its clock running on the wall clock. For
/// <c>pmacstream</c> processes, which reach a controller only through a transport (two stations, a lease, a kill).
/// </summary>
public sealed class ServedSim : IAsyncDisposable
{
    private readonly PmacTcpServer _server;

    private ServedSim(SimHarness harness, PmacTcpServer server)
    {
        Harness = harness;
        _server = server;
    }

    /// <summary>The layer below: the simulator and the port the TCP server serves.</summary>
    public SimHarness Harness { get; }

    public PmacSimulator Sim => Harness.Sim;

    /// <summary>The address a command's <c>--tcp</c> takes.</summary>
    public string Spec => $"127.0.0.1:{_server.Port}";

    public long PacketsServed => _server.PacketsServed;

    /// <summary>A simulator at <paramref name="speed"/> served on a free loopback port, its clock started.</summary>
    public static ServedSim Start(SimSpeed speed)
    {
        var harness = new SimHarness(new SimOptions { Speed = speed }, "ethernet");
        var ethernet = harness.Port;
        var server = new PmacTcpServer(() => ethernet, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        harness.Sim.StartClock();
        return new ServedSim(harness, server);
    }

    /// <summary>
    /// Waits until M0 reaches <paramref name="line"/>; fails with <paramref name="output"/> when the job's process ended
    /// first (<paramref name="exited"/>) or a minute passed.
    /// </summary>
    /// <exception cref="InvalidOperationException">The job did not reach the line.</exception>
    public async Task WaitForLineAsync(int line, Func<bool> exited, Func<Task<string>> output)
    {
        var sw = Stopwatch.StartNew();
        while (Sim.ReadVariable('M', 0) < line)
        {
            if (exited() || sw.Elapsed > TimeSpan.FromSeconds(60))
            {
                throw new InvalidOperationException($"the job did not reach line {line}: {await output()}");
            }

            await Task.Delay(20);
        }
    }

    /// <summary>The source lines of the executed moves in order, a line's consecutive moves once, the preamble (0) left out.</summary>
    public List<int> ExecutedLines()
    {
        var executed = new List<int>();
        foreach (var m in Sim.ExecutedMoves)
        {
            if (m.SourceLine > 0 && (executed.Count == 0 || executed[^1] != m.SourceLine))
            {
                executed.Add(m.SourceLine);
            }
        }

        return executed;
    }

    public async ValueTask DisposeAsync()
    {
        Sim.StopClock();
        await _server.DisposeAsync();
        Harness.Dispose();
    }
}
