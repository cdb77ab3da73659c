using PmacStream.Pmac;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>
/// The transports against `pmacstream sim` itself (the real simulator engine) over the real media: TCP loopback and a
/// socat pty pair, in one process started and stopped like a user would.
/// </summary>
public sealed class SimCliTransportTests : IDisposable
{
    private static readonly string[] Program = [.. Enumerable.Range(1, 400).Select(i => $"X{i}.125 Y{i % 7}.5")];
    private readonly TestFolder _temp = new("simcli");

    private string Log => Path.Combine(_temp.Path, "executed.csv");

    public void Dispose() => _temp.Dispose();

    [Fact]
    public async Task Ethernet_against_the_simulator_process()
    {
        using var sim = SimProcess.Start("--tcp", "127.0.0.1:0", "--speed", "instant", "--executed-log", Log);
        await EthernetHalf(sim);
        StopsCleanly(sim);
    }

    [SkippableFact]
    public async Task Ethernet_and_serial_reach_the_same_simulator_process()
    {
        using var pair = SocatPair.Start();
        using var sim = SimProcess.Start("--tcp", "127.0.0.1:0", "--speed", "instant", "--executed-log", Log, "--serial", pair.A, "--baud", "115200");
        await EthernetHalf(sim);

        await using (var ser = new SerialConnection(new SerialOptions { PortName = pair.B, Settings = new SerialSettings(115200), Timeout = TimeSpan.FromSeconds(5) }))
        {
            (await ser.GetResponseAsync("VER")).Should().Be("1.947");
            (await ser.GetResponseAsync("P500")).Should().Be("80", "both media reach the same controller");
            var bad = () => ser.GetResponseAsync("FOO");
            (await bad.Should().ThrowAsync<PmacErrorException>()).Which.Number.Should().Be(3);
            (await ser.GetResponseAsync("LIST PROG 11")).Split('\n').Should().HaveCount(Program.Length);
            (await ser.GetResponseAsync("OPEN PROG 12 CLEAR")).Should().BeEmpty();
            var download = () => ser.DownloadAsync(["X1", "X2", "FOO BAR", "X3"]);
            (await download.Should().ThrowAsync<PmacErrorException>()).Which.LineInBatch.Should().Be(2);
            (await ser.GetResponseAsync("CLOSE")).Should().BeEmpty();
            (await ser.GetResponseAsync("LIST PROG 12")).Split('\n').Should().HaveCount(2);
        }

        StopsCleanly(sim);
        sim.Output.Should().Contain(l => l.StartsWith("pmacstream sim: serving serial " + pair.A, StringComparison.Ordinal));
    }

    /// <summary>Replies, errors, a refused line in a download, WRITEBUFFER batches; leaves P500=80 and PROG 11 behind.</summary>
    private static async Task EthernetHalf(SimProcess sim)
    {
        sim.Port.Should().BeGreaterThan(0, "the bound port is printed");
        await using var eth = new EthernetConnection(new EthernetOptions { Port = sim.Port, Timeout = TimeSpan.FromSeconds(5) });
        (await eth.GetResponseAsync("VER")).Should().Be("1.947");
        (await eth.GetResponseAsync("P500=80")).Should().BeEmpty();
        (await eth.GetResponseAsync("P500")).Should().Be("80");
        var bad = () => eth.GetResponseAsync("FOO");
        (await bad.Should().ThrowAsync<PmacErrorException>()).Which.Number.Should().Be(3);

        // A download with a refused line in the middle: the failing line is reported and the controller stored
        // exactly the lines before it (read back with LIST PROG, a reply far longer than one 1400-byte packet).
        (await eth.GetResponseAsync("OPEN PROG 10 CLEAR")).Should().BeEmpty();
        var lines = Program.Take(250).Append("FOO BAR").Concat(Program.Skip(250)).ToArray();
        var download = () => eth.DownloadAsync(lines);
        var e = (await download.Should().ThrowAsync<PmacErrorException>()).Which;
        e.LineInBatch.Should().Be(250);
        e.Command.Should().Be("FOO BAR");
        (await eth.GetResponseAsync("CLOSE")).Should().BeEmpty();
        var listing = await eth.GetResponseAsync("LIST PROG 10");
        listing.Length.Should().BeGreaterThan(1400);
        listing.Split('\n').Should().HaveCount(250, "nothing after the refused line was stored");

        // A whole program in WRITEBUFFER batches.
        (await eth.GetResponseAsync("OPEN PROG 11 CLEAR")).Should().BeEmpty();
        await eth.DownloadAsync(Program);
        (await eth.GetResponseAsync("CLOSE")).Should().BeEmpty();
        (await eth.GetResponseAsync("LIST PROG 11")).Split('\n').Should().HaveCount(Program.Length);

        await eth.FlushAsync();
        (await eth.ControlAsync('\x02')).Should().NotBeEmpty("Ctrl-B answers the motor status words");
    }

    private void StopsCleanly(SimProcess sim)
    {
        sim.Terminate().Should().Be(0, "SIGTERM is a clean stop");
        sim.Output.Should().Contain(l => l.StartsWith("pmacstream sim: stopped", StringComparison.Ordinal));
        File.Exists(Log).Should().BeTrue("the executed-move log is written on stop");
    }
}
