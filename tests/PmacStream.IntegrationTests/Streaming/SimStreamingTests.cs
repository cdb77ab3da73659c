using PmacStream.Program;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

public class SimStreamingTests
{
    [Theory]
    [InlineData(StrategyKind.Chunk, 1000, 2.0)]
    [InlineData(StrategyKind.Chunk, 300, 0.5)]
    [InlineData(StrategyKind.Pr, 1000, 1.0)]
    [InlineData(StrategyKind.Adaptive, 500, 1.0)]
    public async Task Demo_program_executes_every_block_once_in_order_on_the_simulator(StrategyKind strategy, int chunkLines, double secondsPerTick)
    {
        using var rig = new SimRig(SimRig.DemoPath, chunkLines, new StreamingOptions { Strategy = strategy, BufferWords = 20_000 });
        await rig.Session.StartAsync();
        (await rig.RunAsync(secondsPerTick)).Should().BeTrue(rig.Session.Status.Message);

        var expected = rig.Program.TrackedLines().ToList();
        expected.Should().HaveCount(rig.Program.Manifest.TotalMotionBlocks);
        rig.ExecutedLines().Should().Equal(expected);
    }
}
