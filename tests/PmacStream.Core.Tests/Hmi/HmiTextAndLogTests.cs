using PmacStream.Hmi;
using Serilog;
using Serilog.Events;

namespace PmacStream.Core.Tests.Hmi;

public sealed class HmiTextAndLogTests
{
    [Fact]
    public void Every_text_has_english_and_chinese()
    {
        foreach (var id in Enum.GetValues<TextId>())
        {
            var en = HmiText.Get(id, HmiLanguage.English);
            var zh = HmiText.Get(id, HmiLanguage.Chinese);
            HmiText.IsDefined(id).Should().BeTrue($"{id} needs a text");
            en.Should().NotBeNullOrWhiteSpace();
            if (id is not TextId.DevicePcomm)
            {
                zh.Should().MatchRegex(@"[\u4e00-\u9fff]", $"{id} needs a Chinese text");
            }
        }
    }

    [Fact]
    public void The_execute_button_reads_as_in_the_paper()
    {
        HmiText.Get(TextId.Execute, HmiLanguage.Chinese).Should().Be("程序段执行");
        HmiText.Format(TextId.ChunkRow, HmiLanguage.English, "p_0001.pmc", 1, 1000, 998).Should().Be("p_0001.pmc   lines 1–1000   (998 blocks)");
    }

    [Fact]
    public void Log_sink_forwards_information_and_up_with_source_and_drops_oldest_when_full()
    {
        var sink = new HmiLogSink(capacity: 3);
        using var logger = new LoggerConfiguration().MinimumLevel.Debug().WriteTo.Hmi(sink).CreateLogger();
        var log = logger.ForContext<HmiTextAndLogTests>();

        log.Debug("hidden {N}", 0);
        for (var i = 1; i <= 5; i++)
        {
            log.Information("job event {N}", i);
        }

        var lines = sink.Drain();
        lines.Should().HaveCount(3);
        lines[0].Should().Contain("INF HmiTextAndLogTests: job event 3");
        lines[2].Should().EndWith("job event 5");
        sink.Dropped.Should().Be(2);
        sink.Drain().Should().BeEmpty();

        log.Error(new IOException("link down"), "stream stopped");
        sink.Drain().Single().Should().Contain("ERR").And.EndWith("stream stopped (link down)");
    }

    [Fact]
    public void Log_sink_honours_its_minimum_level()
    {
        var sink = new HmiLogSink(minimum: LogEventLevel.Debug);
        using var logger = new LoggerConfiguration().MinimumLevel.Verbose().WriteTo.Hmi(sink).CreateLogger();

        logger.Verbose("v");
        logger.Debug("> {Command}", "M0");

        sink.Drain().Should().ContainSingle().Which.Should().Contain("DBG -: > \"M0\"");
    }
}

public sealed class ControllerLibraryTests
{
    private sealed class RefusingConnection(string refuse) : PmacStream.Pmac.IPmacConnection
    {
        public List<string> Received { get; } = [];
        public string Description => "refusing";
        public Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
        {
            Received.Add(command);
            return command == refuse ? throw new PmacStream.Pmac.PmacErrorException(3, command) : Task.FromResult(string.Empty);
        }

        public Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default) => throw new NotSupportedException();
        public Task FlushAsync(CancellationToken cancellationToken = default) => Task.CompletedTask;
        public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => Task.FromResult(string.Empty);
        public ValueTask DisposeAsync() => ValueTask.CompletedTask;
    }

    [Fact]
    public async Task Library_download_goes_on_past_a_refused_line_and_reports_it()
    {
        var library = PmacStream.Jobs.ControllerLibrary.Lines();
        library.Should().Contain(l => l.StartsWith("OPEN PROG 1000", StringComparison.Ordinal)).And.Contain("CLOSE");
        var refuse = library.First(l => l.StartsWith("N1000", StringComparison.Ordinal));
        var conn = new RefusingConnection(refuse);

        var refused = await PmacStream.Jobs.ControllerLibrary.DownloadTolerantAsync(conn, library);

        refused.Should().Equal(refuse);
        conn.Received.Should().Equal(library, "every line was offered, in order, the refused one included");
    }
}
