using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>The PComm-style facade: devices by number, GetResponse, and Download with macro/include/log/map/dnld, over TCP.</summary>
public sealed class PmacDevicesTests : IAsyncLifetime, IDisposable
{
    private readonly ScriptedController _controller = new();
    private readonly TestFolder _temp = new("dl");
    private PmacTcpServer _server = null!;
    private PmacDevices _devices = null!;

    public Task InitializeAsync()
    {
        _server = _controller.StartTcp();
        _devices = new PmacDevices();
        _devices.AddFromSpec(0, $"tcp://127.0.0.1:{_server.Port}");
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        await _devices.DisposeAsync();
        await _server.DisposeAsync();
    }

    public void Dispose() => _temp.Dispose();

    private string Write(string name, params string[] lines)
    {
        var path = Path.Combine(_temp.Path, name);
        File.WriteAllLines(path, lines);
        return path;
    }

    private string MainWithLibrary(bool withError = false)
    {
        Write("lib.pmc", "; library", "#define XPOS 10", "X(XPOS)", withError ? "BAD THING" : "Y(XPOS)", "Z1");
        return Write(
            "main.pmc",
            "; a PMAC program",
            "#define FEED P500",
            "#define RATE FEED",
            "OPEN ROT   ; the rotary buffer",
            "",
            "F(RATE)",
            "#include \"lib.pmc\"",
            "CMD\"P1=FEED;x\"",
            "X(XPOS)",
            "CLOSE");
    }

    [Fact]
    public void Getresponse_returns_true_with_the_answer_or_false_with_the_error()
    {
        _devices.GetResponse(0, "VER", out var answer).Should().BeTrue();
        answer.Should().Be("1.947");
        _devices.GetResponse(0, "BAD", out answer).Should().BeFalse();
        answer.Should().Be("ERR003: data error or unrecognized command");
        var act = () => _devices.GetResponse(5, "VER", out _);
        act.Should().Throw<ArgumentOutOfRangeException>().WithMessage("*device 5 is not configured*");
    }

    [Fact]
    public void Download_expands_macros_and_includes_and_strips_comments()
    {
        var path = MainWithLibrary();
        _devices.Download(0, path, macro: true, map: false, log: false, dnld: true, out var success);
        success.Should().BeTrue();
        _controller.Executed.Should().Equal("OPEN ROT", "F(P500)", "X(10)", "Y(10)", "Z1", "CMD\"P1=FEED;x\"", "X(10)", "CLOSE");
        File.Exists(Path.ChangeExtension(path, ".log")).Should().BeFalse();
        File.Exists(Path.ChangeExtension(path, ".map")).Should().BeFalse();
    }

    [Fact]
    public async Task Without_macro_lines_go_as_written()
    {
        var path = Write("plain.pmc", "#define A 1", "X(A) ; c");
        var report = await _devices.DownloadAsync(0, path, new DownloadOptions(Macro: false));
        report.Success.Should().BeTrue();
        _controller.Executed.Should().Equal("#define A 1", "X(A)");
    }

    [Fact]
    public async Task An_error_in_an_included_file_is_reported_with_its_file_and_line_and_logged()
    {
        var path = MainWithLibrary(withError: true);
        var report = await _devices.DownloadAsync(0, path, new DownloadOptions(Macro: true, Log: true));
        report.Success.Should().BeFalse();
        report.LinesSent.Should().Be(3);
        report.Error.Should().Be(new DownloadError(3, Path.Combine(_temp.Path, "lib.pmc"), 4, "BAD THING"));
        _controller.Executed.Should().Equal("OPEN ROT", "F(P500)", "X(10)");

        var log = await File.ReadAllLinesAsync(Path.ChangeExtension(path, ".log"));
        log.Should().Contain($"{path}:4: OPEN ROT");
        log.Should().Contain($"{Path.Combine(_temp.Path, "lib.pmc")}:3: X(10)");
        log.Should().Contain($"; ERR003 (data error or unrecognized command) at {Path.Combine(_temp.Path, "lib.pmc")}:4: BAD THING");
        log.Should().NotContain(l => l.EndsWith(": Z1", StringComparison.Ordinal), "nothing after the refused line was sent");
        log[^1].Should().Be("; result: FAILED, 3 lines accepted");
    }

    [Fact]
    public async Task Map_lists_the_macros_with_values_and_origin()
    {
        var path = MainWithLibrary();
        (await _devices.DownloadAsync(0, path, new DownloadOptions(Map: true))).Success.Should().BeTrue();
        var map = await File.ReadAllLinesAsync(Path.ChangeExtension(path, ".map"));
        map.Should().Contain($"FEED\tP500\t; {path}:2");
        map.Should().Contain($"RATE\tFEED\t; {path}:3");
        map.Should().Contain($"XPOS\t10\t; {Path.Combine(_temp.Path, "lib.pmc")}:2");
    }

    [Fact]
    public async Task Dnld_false_prepares_logs_and_maps_but_sends_nothing()
    {
        var path = MainWithLibrary(withError: true);
        var report = await _devices.DownloadAsync(0, path, new DownloadOptions(Map: true, Log: true, Dnld: false));
        report.Should().Be(new DownloadReport(true, 0, null));
        _controller.Executed.Should().BeEmpty();
        _server.PacketsServed.Should().Be(0);
        var log = await File.ReadAllTextAsync(Path.ChangeExtension(path, ".log"));
        log.Should().Contain("X(10)").And.Contain("nothing sent (dnld=false)");
        File.Exists(Path.ChangeExtension(path, ".map")).Should().BeTrue();

        // dnld=false needs no configured device at all.
        await using var none = new PmacDevices();
        (await none.DownloadAsync(9, path, new DownloadOptions(Dnld: false))).Success.Should().BeTrue();
    }

    [Fact]
    public async Task A_missing_include_fails_before_anything_is_sent()
    {
        var path = Write("broken.pmc", "X1", "#include \"nowhere.pmc\"", "X2");
        var report = await _devices.DownloadAsync(0, path, new DownloadOptions(Log: true));
        report.Success.Should().BeFalse();
        report.Error.Should().Be(new DownloadError(0, path, 2, "#include file not found: nowhere.pmc"));
        _controller.Executed.Should().BeEmpty();
        (await File.ReadAllTextAsync(Path.ChangeExtension(path, ".log"))).Should().Contain("source error");
    }

    [Fact]
    public async Task Ifdef_else_endif_select_lines()
    {
        var path = Write("cond.pmc", "#define MILL", "#ifdef MILL", "X1", "#else", "X2", "#endif", "#ifndef MILL", "Y1", "#else", "Y2", "#endif");
        (await _devices.DownloadAsync(0, path, new DownloadOptions())).Success.Should().BeTrue();
        _controller.Executed.Should().Equal("X1", "Y2");
    }

    [Fact]
    public async Task A_big_chunk_downloads_in_order()
    {
        var lines = Enumerable.Range(0, 20000).Select(i => $"N{i} X{i * 0.001:0.###} Y1 ; step {i}").ToArray();
        var path = Write("chunk.pmc", lines);
        var report = await _devices.DownloadAsync(0, path, new DownloadOptions());
        report.Should().Be(new DownloadReport(true, 20000, null));
        _controller.Executed.Should().HaveCount(20000);
        _controller.Executed.Last().Should().Be("N19999 X19.999 Y1");
    }

    [Theory]
    [InlineData("tcp://10.0.0.5", "tcp 10.0.0.5:1025")]
    [InlineData("10.0.0.5:2000", "tcp 10.0.0.5:2000")]
    [InlineData("serial:/dev/ttyUSB0@115200,even", "serial /dev/ttyUSB0@115200")]
    [InlineData("serial:COM3", "serial COM3@38400")]
    [InlineData("pcomm32:1", "pcomm32 device 1")]
    public async Task Connection_specs_create_the_right_transport(string spec, string description)
    {
        await using var c = PmacConnections.Create(spec);
        c.Description.Should().Be(description);
    }

    [Theory]
    [InlineData("10.0.0.5")]
    [InlineData("tcp://h:99999")]
    [InlineData("serial:/dev/x@fast")]
    [InlineData("serial:/dev/x,mark")]
    [InlineData("pcomm32:x")]
    public void Bad_specs_are_refused_with_the_forms_that_work(string spec)
    {
        var act = () => PmacConnections.Create(spec);
        act.Should().Throw<FormatException>().WithMessage($"'{spec}'*");
    }
}
