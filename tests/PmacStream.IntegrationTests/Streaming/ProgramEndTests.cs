using System.Globalization;
using System.Text;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The end of a job on the simulator: a rotary program has no end of its own (it waits for more lines), so the session
/// quits it (<c>&amp;1Q</c>) once the last block executes; the last move still runs to its end, the coordinate system
/// stops running, and the next job on the same controller starts instead of being refused as "running a program".
/// </summary>
public sealed class ProgramEndTests
{
    private static string Program(int moves)
    {
        var sb = new StringBuilder("G21 G90 G17\nG00 X0 Y0\nG01 F3000\n");
        for (var i = 1; i <= moves; i++)
        {
            sb.Append(CultureInfo.InvariantCulture, $"G01 X{i % 20 * 2} Y{i / 20}\n");
        }

        var path = Path.Combine(Directory.CreateTempSubdirectory("pmacstream-end-").FullName, "end.nc");
        File.WriteAllText(path, sb.Append("M30\n").ToString());
        return path;
    }

    [Theory]
    [InlineData(StrategyKind.Chunk)]
    [InlineData(StrategyKind.Pr)]
    [InlineData(StrategyKind.Adaptive)]
    public async Task A_completed_job_ends_the_rotary_program_and_the_next_job_starts(StrategyKind strategy)
    {
        var source = Program(150);
        using var rig = new SimRig(source, 40, new StreamingOptions { Strategy = strategy, BufferWords = 20_000 });
        await rig.Session.StartAsync();
        (await rig.RunAsync(0.5)).Should().BeTrue(rig.Session.Status.Message);

        rig.Sim.IsRunning().Should().BeFalse("the quit ends the rotary program once the last move has run");
        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines(), "the quit loses no move, the last one among them");
        rig.Sim.Counters.Underruns.Should().Be(0, "an ended program is not a starved one");
        var moves = rig.Sim.ExecutedMoves.Count;

        // Resuming the completed job asks nothing and sends nothing: the job is done.
        var again = new StreamingSession(rig.Connection, rig.Program, rig.Options, new MemorySink(), time: rig.Time);
        await again.ResumeAsync(rig.Sink.Record());
        again.State.Should().Be(SessionState.Completed);
        rig.Sim.Advance(TimeSpan.FromSeconds(5));
        rig.Sim.IsRunning().Should().BeFalse();
        rig.Sim.ExecutedMoves.Count.Should().Be(moves, "nothing ran again");

        // The next job on the same controller starts (a program still running would refuse it).
        var next = new StreamingSession(rig.Connection, rig.Program, rig.Options, new MemorySink(), time: rig.Time);
        rig.Session = next;
        await next.StartAsync();
        (await rig.RunAsync(0.5)).Should().BeTrue(next.Status.Message);
        rig.Sim.IsRunning().Should().BeFalse();
        rig.Sim.ExecutedMoves.Count.Should().Be(2 * moves, "the second job ran every move once more");
    }
}
