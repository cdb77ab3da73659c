using System.Diagnostics;
using System.Globalization;
using System.Net;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Benchmarks.Transport;

/// <summary>
/// What one VR_PMAC packet costs the simulator's TCP server (<c>tcp-packets N</c>): N GETRESPONSE round trips (a tick's
/// <c>M0</c>) over loopback to a minimal endpoint, client and server in this process. Reports bytes allocated per
/// round trip (all threads: the client's share is the same before and after a server change) and the wall time.
/// </summary>
public static class PacketCostBench
{
    public static async Task<int> Run(string[] args)
    {
        var n = int.Parse(args[0], CultureInfo.InvariantCulture);
        var (ports, _, engine) = BenchmarkEngines.Create("fast");
        await using var server = new PmacTcpServer(ports, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0) });
        server.Start();
        var connection = new EthernetConnection(new EthernetOptions { Port = server.Port, Timeout = TimeSpan.FromSeconds(10) });
        for (var i = 0; i < 2000; i++)
        {
            connection.GetResponseAsync("M0").GetAwaiter().GetResult(); // warm up: JIT, connection
        }

        GC.Collect();
        var b0 = GC.GetTotalAllocatedBytes(precise: true);
        var sw = Stopwatch.StartNew();
        for (var i = 0; i < n; i++)
        {
            connection.GetResponseAsync("M0").GetAwaiter().GetResult();
        }

        var wall = sw.Elapsed;
        var bytes = GC.GetTotalAllocatedBytes(precise: true) - b0;
        Console.WriteLine($"{n} GETRESPONSE round trips: {(double)bytes / n:0} bytes allocated each (client and server), {1e6 * wall.TotalSeconds / n:0.0} us each");
        await connection.DisposeAsync();
        engine?.Dispose();
        return 0;
    }
}
