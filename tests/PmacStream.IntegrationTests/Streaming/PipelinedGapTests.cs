using System.Globalization;
using System.Text.RegularExpressions;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Several WRITEBUFFER packets in flight (issue 28): a line refused while the packets behind it were already stored
/// leaves those lines in the rotary buffer after a gap. The session must abort the coordinate system before execution
/// reaches the gap and end the job at the last block executed; the restart from that block (the resume path of an
/// aborted job: a preamble on a redefined buffer) then runs the rest. Over both runs every block runs once, in order,
/// and no block behind the gap runs before the restart.
/// </summary>
public sealed class PipelinedGapTests(ITestOutputHelper output) : IDisposable
{
    private readonly TestFolder _temp = new("pipelined-gap");

    public void Dispose() => _temp.Dispose();

    [Fact]
    public async Task A_packet_refused_with_later_packets_stored_aborts_before_the_gap_and_the_restart_runs_every_block_once_in_order()
    {
        var (program, source) = await PrepareAsync(blocks: 6_000);
        var times = MoveTimeTable.FromProgram(program.Manifest.SourcePath)!;
        using var sim = new PmacSimulator(new SimOptions());
        var port = sim.OpenPort("stream");
        SimRig.LoadLibrary(port);
        var options = RunSettings.Default.ToStreamingOptions(StrategyKind.Full, singleBlock: false, defineBuffer: true);
        options.PacketsInFlight.Should().BeGreaterThan(1, "the full strategy pipelines by default");

        // Run 1: the fifth pipelined batch has its second packet refused while the packets behind it were stored.
        var gap = new PipelinedRefusalConnection(port);
        var first = new StreamingSession(gap, program, options, moveTimes: times, time: SimRig.Clock(sim));
        await first.StartAsync();
        await TickUntilAsync(first, sim, s => s is SessionState.Aborted or SessionState.Faulted or SessionState.Completed);
        first.State.Should().Be(SessionState.Aborted, first.Status.Message);
        gap.StoredAfterGap.Should().BeGreaterThan(0, "lines behind the refused one were in the buffer");
        var gapLine = int.Parse(Regex.Match(gap.Refused!, @"M0==(\d+)").Groups[1].Value, CultureInfo.InvariantCulture);
        sim.RunUntilIdle(TimeSpan.FromMinutes(10));
        var run1 = Blocks(sim, program, fromLine: 0);
        run1.Should().NotBeEmpty().And.OnlyContain(l => l < gapLine, "the abort came before execution reached the gap");
        var restart = first.Checkpoint.LastExecutedLine;
        restart.Should().BeGreaterThan(0).And.BeLessThan(gapLine);
        output.WriteLine($"refused line {gapLine} with {gap.StoredAfterGap} lines stored behind it; aborted at {restart}; {run1.Count} blocks ran; {first.Status.Message}");

        // Run 2: the restart an aborted job's resume makes: the block M0 named, behind the start planner's preamble.
        var executedBefore = sim.ExecutedMoves.Count;
        var plan = StartFromLine.Plan(source, restart, StartPlanOptions.For(program.Manifest, new StartPlanOptions { Profile = MachineProfile.Default }));
        var second = new StreamingSession(new InProcessConnection(port, "sim"), program, options, moveTimes: times, time: SimRig.Clock(sim));
        await second.StartAsync(plan.Line, plan.PmacLines);
        await TickUntilAsync(second, sim, s => s is SessionState.Completed or SessionState.Faulted or SessionState.Aborted);
        second.State.Should().Be(SessionState.Completed, second.Status.Message);
        sim.RunUntilIdle(TimeSpan.FromMinutes(10));
        var run2 = Blocks(sim, program, fromLine: plan.Line, skip: executedBefore);

        var expected = program.TrackedLines().ToList();
        run1.Concat(run2).Should().Equal(expected, "every block once, in order, over the aborted run and its restart");
    }

    private static async Task TickUntilAsync(StreamingSession session, PmacSimulator sim, Func<SessionState, bool> done)
    {
        for (var tick = 0; tick < 40_000 && !done(session.State); tick++)
        {
            await session.TickAsync();

            // Not a whole number of the program's 1 ms moves: the abort lands inside a move, which the restart runs
            // again from its start. (An abort exactly at a move's end logs that move and leaves M0 on it; its restart
            // is a zero-length move the simulator would log twice: the operator's abort path has that property too.)
            sim.Advance(TimeSpan.FromMilliseconds(50.37));
        }
    }

    /// <summary>The blocks the simulator ran (from its executed-move log), at or after <paramref name="fromLine"/>.</summary>
    private static List<int> Blocks(PmacSimulator sim, ChunkedProgram program, int fromLine, int skip = 0) =>
        ExecutedLineCheck.Blocks(sim.ExecutedMoves.Skip(skip).Where(m => m.SourceLine >= fromLine).Select(m => (m.SourceLine, m.BlockStart)), program.ExpandedBlocks()).ToList();

    private async Task<(ChunkedProgram Program, string Source)> PrepareAsync(int blocks)
    {
        // The link-fault bench's program at 1,000 blocks/s: moves of 0.25 mm, a zig-zag raster.
        var source = Path.Combine(_temp.Path, "raster.nc");
        var text = TestPrograms.Text(string.Create(CultureInfo.InvariantCulture, $"G21 G17 G90\nG00 X0 Y0 Z0\nG01 F{1000 * 0.25 * 60}\n"), blocks, TestPrograms.RasterOf(400));
        await File.WriteAllTextAsync(source, text);
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });
        var program = (await service.PrepareAsync(new PrepareRequest(source, RunSettings.Default) { OutDir = Path.Combine(_temp.Path, "chunks") })).Program;
        return (program, source);
    }
}
