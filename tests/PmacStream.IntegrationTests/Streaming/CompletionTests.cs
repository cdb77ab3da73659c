using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// A job is complete when the machine has finished the program, not when the rotary buffer is empty: the last lines
/// sit in the controller's lookahead while their moves still run.
/// </summary>
public sealed class CompletionTests : IDisposable
{
    private readonly TestFolder _temp = new("completion");

    public void Dispose() => _temp.Dispose();

    [Theory]
    [InlineData(StrategyKind.Full)]
    [InlineData(StrategyKind.Chunk)]
    public async Task A_long_move_before_the_last_one_is_not_taken_for_the_end(StrategyKind strategy)
    {
        // Line 2 runs 18 s; with the buffer empty and M0 standing at 2 over many readings, the end must still wait for
        // line 3 (found once as "completed: 1 of 2 blocks" while X was half-way, the job recorded as completed).
        var source = Path.Combine(_temp.Path, $"long-{strategy}.nc");
        File.WriteAllText(source, "G21 G90 G17\nG01 X300 F1000\nG01 X301\nM30\n");
        using var rig = new SimRig(source, 1000, new StreamingOptions { Strategy = strategy, BufferWords = 20_000 });
        await rig.Session.StartAsync();
        for (var i = 0; i < 2_000 && rig.Session.State == SessionState.Running; i++)
        {
            await rig.Session.TickAsync();
            if (rig.Session.State == SessionState.Completed)
            {
                break;
            }

            rig.Sim.Advance(TimeSpan.FromSeconds(0.05));
        }

        rig.Session.State.Should().Be(SessionState.Completed, rig.Session.Status.Message);
        rig.Session.Status.CurrentLine.Should().Be(3, "the end is the last line's move done");
        rig.ExecutedLines().Should().Equal([2, 3], "both moves ran before the job was called complete");
        rig.Sim.IsRunning().Should().BeTrue("the rotary program itself waits for more lines; only its motion has ended");
    }
}
