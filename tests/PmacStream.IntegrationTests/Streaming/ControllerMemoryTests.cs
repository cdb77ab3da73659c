using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The controller's memory (issue 28): the <c>full</c> strategy defines its rotary buffer from what <c>SIZE</c> reports
/// free, less a reserve, capped by the setting; the simulator answers <c>SIZE</c> from its user memory (standard 26K
/// words, 212K expanded). And the credit of several packets in flight counts a line's words as the controller does,
/// never fewer (a refusal for room would leave later packets stored behind a gap).
/// </summary>
public sealed class ControllerMemoryTests : IDisposable
{
    private readonly TestFolder _temp = new("controller-memory");

    public void Dispose() => _temp.Dispose();

    [Theory]
    [InlineData(SimOptions.StandardUserMemoryWords, 0)]
    [InlineData(SimOptions.ExpandedUserMemoryWords, 0)]
    [InlineData(SimOptions.ExpandedUserMemoryWords, 50_000)]
    public async Task The_full_strategy_defines_its_buffer_from_the_free_memory_SIZE_reports(int memory, int cap)
    {
        var program = await PrepareAsync(blocks: 500);
        using var sim = new PmacSimulator(new SimOptions { UserMemoryWords = memory });
        var port = sim.OpenPort("stream");
        SimRig.LoadLibrary(port);
        var host = new InProcessConnection(port, "sim");
        await host.GetResponseAsync("&1 DELETE ROT");
        var free = Size(await host.GetResponseAsync("SIZE"));
        free.Should().BeGreaterThan(memory - 4_000, "the library takes a few thousand words at most").And.BeLessThan(memory);

        var options = (RunSettings.Default with { BufferWordsCap = cap }).ToStreamingOptions(StrategyKind.Full, singleBlock: false, defineBuffer: true);
        var session = new StreamingSession(host, program, options, time: SimRig.Clock(sim));
        await session.StartAsync();

        var expected = cap > 0 ? Math.Min(cap, free - StreamingDefaults.MemoryReserveWords) : free - StreamingDefaults.MemoryReserveWords;
        session.Context.BufferWords.Should().Be(expected);
        Size(await host.GetResponseAsync("SIZE")).Should().Be(free - expected, "the rotary buffer took exactly that much of the free memory");
    }

    [Fact]
    public async Task A_controller_that_refuses_SIZE_gets_the_settings_buffer()
    {
        var program = await PrepareAsync(blocks: 200);
        using var sim = new PmacSimulator(new SimOptions());
        var port = sim.OpenPort("stream");
        SimRig.LoadLibrary(port);
        var options = RunSettings.Default.ToStreamingOptions(StrategyKind.Full, singleBlock: false, defineBuffer: true);
        var session = new StreamingSession(new NoSizeConnection(new InProcessConnection(port, "sim")), program, options, time: SimRig.Clock(sim));
        await session.StartAsync();
        session.Context.BufferWords.Should().Be(RunSettings.FullBufferWords);
    }

    [Fact]
    public async Task The_credit_counts_no_line_lower_than_the_controller_does()
    {
        // Each distinct line of the demo's split and of the bench program, stored alone in a motion program: what
        // SIZE loses is the controller's count of its words.
        var program = await PrepareAsync(blocks: 300);
        var demo = await PrepareDemoAsync();
        var lines = Lines(program).Concat(Lines(demo)).Select(l => l.Text).Distinct().Take(1_500).ToList();
        lines.Should().HaveCountGreaterThan(300);
        using var sim = new PmacSimulator(new SimOptions());
        var host = new InProcessConnection(sim.OpenPort("words"), "sim");
        await host.GetResponseAsync("&1 DELETE ROT");
        var exact = 0;
        foreach (var line in lines)
        {
            await host.GetResponseAsync("OPEN PROG 77");
            await host.GetResponseAsync("CLEAR");
            await host.GetResponseAsync("CLOSE");
            var before = Size(await host.GetResponseAsync("SIZE"));
            await host.DownloadAsync(["OPEN PROG 77", line, "CLOSE"]);
            var words = before - Size(await host.GetResponseAsync("SIZE"));
            ControllerWords.Of(line).Should().BeGreaterThanOrEqualTo(words, $"'{line}' takes {words} words on the controller");
            exact += ControllerWords.Of(line) == words ? 1 : 0;
        }

        ControllerWords.Of("M0==12345 G01 X1.25 Y-2.50 F(P500)").Should().Be(7, "the bench block: M0== 2, G01 1, X 1, Y 1, F(P500) 2");
        exact.Should().BeGreaterThan(lines.Count * 9 / 10, "the count is the controller's for nearly every line, not a blanket surplus");
    }

    private static IEnumerable<PmacStream.Streaming.ProgramLine> Lines(ChunkedProgram p) => Enumerable.Range(1, p.TotalChunks).SelectMany(p.Body);

    private static int Size(string reply) => int.Parse(reply.Trim(), CultureInfo.InvariantCulture);

    private async Task<ChunkedProgram> PrepareAsync(int blocks)
    {
        var source = Path.Combine(_temp.Path, $"raster{blocks}.nc");
        var text = TestPrograms.Text("G21 G17 G90\nG00 X0 Y0 Z0\nG01 F1500\n", blocks, TestPrograms.RasterOf(40));
        await File.WriteAllTextAsync(source, text);
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });
        return (await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { OutDir = Path.Combine(_temp.Path, $"chunks{blocks}") })).Program;
    }

    private async Task<ChunkedProgram> PrepareDemoAsync()
    {
        var source = Path.Combine(_temp.Path, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, source);
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });
        return (await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { OutDir = Path.Combine(_temp.Path, "demo-chunks") })).Program;
    }

    /// <summary>A controller whose firmware does not know <c>SIZE</c> (ERR003).</summary>
    private sealed class NoSizeConnection(IPmacConnection inner) : IPmacConnection
    {
        public string Description => inner.Description;

        public Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default) =>
            command.Trim().Equals("SIZE", StringComparison.OrdinalIgnoreCase) ? throw new PmacErrorException(3, command) : inner.GetResponseAsync(command, cancellationToken);

        public Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default) => inner.DownloadAsync(lines, cancellationToken);

        public Task FlushAsync(CancellationToken cancellationToken = default) => inner.FlushAsync(cancellationToken);

        public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => inner.ControlAsync(control, cancellationToken);

        public ValueTask DisposeAsync() => inner.DisposeAsync();
    }
}
