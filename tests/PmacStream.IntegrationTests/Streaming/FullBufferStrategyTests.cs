using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The <c>full</c> strategy (issue 28) against the host stalls a lossy link causes: a program written for 5,000
/// blocks/s (the simulator runs it at the Turbo PMAC's 2,000), and every 2 s of machine time the host frozen for 1 s,
/// as a request waiting for TCP's retransmission timeouts is. The full strategy keeps every block once, in order, with
/// no underrun; the paper's chunk strategy, whose window leaves well under a second ahead, starves in the same stalls.
/// </summary>
public sealed class FullBufferStrategyTests(ITestOutputHelper output) : IDisposable
{
    private readonly TestFolder _temp = new("full-strategy");

    public void Dispose() => _temp.Dispose();

    [Fact]
    public async Task The_full_strategy_rides_out_one_second_stalls_at_the_controllers_top_block_rate_and_the_chunk_strategy_does_not()
    {
        var program = await PrepareAsync(rate: 5000, blocks: 12_000);
        var times = MoveTimeTable.FromProgram(program.Manifest.SourcePath)!;
        var full = await RunAsync(program, times, StrategyKind.Full);
        var chunk = await RunAsync(program, times, StrategyKind.Chunk);
        output.WriteLine($"full: {full.Underruns} underruns, worst lead {full.WorstLead:0.000} s; chunk: {chunk.Underruns} underruns, worst lead {chunk.WorstLead:0.000} s");

        full.Underruns.Should().Be(0, "the full buffer holds more than the longest stall");
        full.WorstLead.Should().BeGreaterThan(1.0, "a 24,000-word buffer holds about 1.3 s at 2,000 blocks/s, a chunk window well under a second");
        chunk.WorstLead.Should().BeLessThan(full.WorstLead);
        chunk.Underruns.Should().BeGreaterThan(0, "the chunk window leaves less than the stall ahead (why full is the default)");
    }

    private async Task<ChunkedProgram> PrepareAsync(int rate, int blocks)
    {
        // The link-fault bench's program: moves of 0.25 mm at the feed that makes RATE blocks a second, a zig-zag raster.
        var source = Path.Combine(_temp.Path, "raster.nc");
        var text = TestPrograms.Text(string.Create(CultureInfo.InvariantCulture, $"G21 G17 G90\nG00 X0 Y0 Z0\nG01 F{rate * 0.25 * 60}\n"), blocks, TestPrograms.RasterOf(400));
        await File.WriteAllTextAsync(source, text);
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });
        return (await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { OutDir = Path.Combine(_temp.Path, "chunks") })).Program;
    }

    private static async Task<(long Underruns, double WorstLead)> RunAsync(ChunkedProgram program, MoveTimeTable times, StrategyKind strategy)
    {
        using var sim = new PmacSimulator(new SimOptions { RetainExecutedMoves = false });
        var port = sim.OpenPort("stream");
        SimRig.LoadLibrary(port);
        var check = new ExecutedLineCheck(program.TrackedLines(), null, program.ExpandedBlocks()).Attach(sim);
        var options = RunSettings.Default.ToStreamingOptions(strategy, singleBlock: false, defineBuffer: true);
        var session = new StreamingSession(new InProcessConnection(port, "sim"), program, options, moveTimes: times, time: SimRig.Clock(sim));
        await session.StartAsync();
        for (var tick = 1; tick < 20_000 && session.State != SessionState.Completed; tick++)
        {
            session.State.Should().NotBe(SessionState.Faulted, session.Status.Message);
            await session.TickAsync();
            // A 50 ms tick; every 40th the host stands still for a second, as behind a retransmission timeout.
            sim.Advance(TimeSpan.FromSeconds(tick % 40 == 0 ? 1.0 : 0.05));
        }

        session.State.Should().Be(SessionState.Completed, session.Status.Message);
        sim.RunUntilIdle(TimeSpan.FromHours(1));
        var result = check.Finish();
        result.FirstBreak.Should().BeNull();
        result.Executed.Should().Be(program.Manifest.TotalMotionBlocks).And.Be(result.Expected, "every block once, in order");
        return (sim.Counters.Underruns, session.WorstLeadSeconds);
    }
}
