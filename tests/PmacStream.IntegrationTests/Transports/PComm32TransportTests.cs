using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>
/// PComm32Connection's marshalling, through a stand-in Pcomm32 library built from C by this project (gcc), which
/// forwards to the simulator's TCP server. All in one class: the library keeps process-wide device state.
/// </summary>
public sealed class PComm32TransportTests : IAsyncLifetime
{
    private readonly ScriptedController _controller = new();
    private PmacTcpServer _server = null!;
    private PComm32Connection? _connection;

    public Task InitializeAsync()
    {
        _server = _controller.StartTcp();
        return Task.CompletedTask;
    }

    /// <summary>
    /// The driver API through the stand-in library, pointed at this test's server. Reports the test SKIPPED (a
    /// fixture's set-up cannot) when the library could not be built here.
    /// </summary>
    private PComm32Connection Connect()
    {
        var standIn = Requires.PComm32StandIn();
        SetStandInAddress(standIn, $"127.0.0.1:{_server.Port}");
        _connection = new PComm32Connection(0, standIn);
        return _connection;
    }

    public async Task DisposeAsync()
    {
        if (_connection is not null)
        {
            await _connection.DisposeAsync();
        }

        await _server.DisposeAsync();
    }

    /// <summary>.NET on Unix keeps environment changes managed-side, so the address goes in through a test hook.</summary>
    private static unsafe void SetStandInAddress(string standIn, string address)
    {
        var lib = System.Runtime.InteropServices.NativeLibrary.Load(standIn);
        var set = (delegate* unmanaged<byte*, void>)System.Runtime.InteropServices.NativeLibrary.GetExport(lib, "PmacStandInSetAddress");
        var bytes = System.Text.Encoding.ASCII.GetBytes(address + "\0");
        fixed (byte* p = bytes)
        {
            set(p);
        }
    }

    [Fact]
    public void Status_nibble_is_decoded()
    {
        PComm32Connection.DecodeStatus(unchecked((int)0x80000005), out var n).Should().Be(PCommStatus.Eot);
        n.Should().Be(5);
        PComm32Connection.DecodeStatus(unchecked((int)0xC0000000), out _).Should().Be(PCommStatus.Timeout);
        PComm32Connection.DecodeStatus(unchecked((int)0xD0000000), out _).Should().Be(PCommStatus.BadChecksum);
        PComm32Connection.DecodeStatus(unchecked((int)0xE0000006), out n).Should().Be(PCommStatus.Error);
        n.Should().Be(6);
        PComm32Connection.DecodeStatus(unchecked((int)0xF0000000), out _).Should().Be(PCommStatus.Fail);
        PComm32Connection.DecodeStatus(0x10000000, out _).Should().Be(PCommStatus.Unsolicited);
    }

    [Fact]
    public async Task A_missing_driver_is_reported_plainly()
    {
        await using var absent = new PComm32Connection(0, Path.Combine(Path.GetTempPath(), "no-such-dir", "Pcomm32.dll"));
        var act = () => absent.GetResponseAsync("VER");
        (await act.Should().ThrowAsync<PmacLinkException>()).WithMessage("PComm32 is not available*could not be loaded*");
    }

    [SkippableFact]
    public async Task Through_the_driver_api_replies_errors_long_replies_downloads_and_callbacks()
    {
        var connection = Connect();
        (await connection.GetResponseAsync("VER")).Should().Be("1.947");
        (await connection.GetResponseAsync("P7=42")).Should().BeEmpty();
        (await connection.GetResponseAsync("P7")).Should().Be("42");
        (await connection.GetResponseAsync("LONG 4000")).Should().HaveLength(4000);
        (await connection.ControlAsync('\x02')).Should().Be("812000804001\r");
        await connection.FlushAsync();
        _controller.Flushes.Should().Be(1);

        var error = () => connection.GetResponseAsync("BAD");
        (await error.Should().ThrowAsync<PmacErrorException>()).Which.Number.Should().Be(3);

        while (_controller.Executed.TryDequeue(out _))
        {
        }

        var lines = Enumerable.Range(0, 100).Select(i => i == 40 ? "BAD" : $"X{i}").ToArray();
        var download = () => connection.DownloadAsync(lines);
        (await download.Should().ThrowAsync<PmacErrorException>()).Which.LineInBatch.Should().Be(40);
        _controller.Executed.Should().Equal(lines.Take(40));

        // PComm's own file download, with its message and progress callbacks marshalled back into .NET.
        using var temp = new TestFolder("pcomm");
        var file = Path.Combine(temp.Path, "download.pmc");
        await File.WriteAllLinesAsync(file, ["X1 ; first", "", "X2", "BAD", "X3"]);
        while (_controller.Executed.TryDequeue(out _))
        {
        }

        var messages = new List<string>();
        var progress = new List<int>();
        var ok = await connection.DownloadFileAsync(file, new DownloadOptions(), messages.Add, progress.Add);
        ok.Should().BeFalse();
        messages.Should().ContainSingle().Which.Should().Be("ERR003 at line 4: BAD");
        progress.Should().Equal(20, 60);
        _controller.Executed.Should().Equal("X1", "X2");

        await File.WriteAllLinesAsync(file, ["X1", "X2"]);
        messages.Clear();
        (await connection.DownloadFileAsync(file, new DownloadOptions(), messages.Add)).Should().BeTrue();
        messages.Should().Equal("2 lines downloaded");
    }

    [SkippableFact]
    public async Task A_stopped_controller_becomes_a_link_error()
    {
        var connection = Connect();
        (await connection.GetResponseAsync("VER")).Should().Be("1.947");
        await _server.StopAsync();
        var act = () => connection.GetResponseAsync("VER");
        await act.Should().ThrowAsync<PmacLinkException>();
    }
}
