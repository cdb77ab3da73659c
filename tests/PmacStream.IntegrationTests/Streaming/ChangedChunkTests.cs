using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>A chunk file edited or truncated after the split is never sent; sending stops at a block boundary and the job resumes exactly.</summary>
public class ChangedChunkTests
{
    [Theory]
    [InlineData(StrategyKind.Chunk)]
    [InlineData(StrategyKind.Pr)]
    [InlineData(StrategyKind.Adaptive)]
    public async Task A_chunk_changed_after_the_split_faults_the_job_before_any_of_it_is_sent_and_resume_completes_exactly(StrategyKind strategy)
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 300, new StreamingOptions { Strategy = strategy, BufferWords = 20_000 });
        var expected = rig.Program.TrackedLines().ToList();
        var victim = rig.Program.ChunkPath(6);
        var original = File.ReadAllBytes(victim);
        var edited = File.ReadAllText(victim).Replace("X", "X1", StringComparison.Ordinal);

        await rig.Session.StartAsync();
        File.WriteAllText(victim, edited); // after the start, as an editor or a half-finished copy would

        (await rig.RunAsync(1.0)).Should().BeFalse("the job cannot complete with a changed chunk");
        rig.Session.State.Should().Be(SessionState.Faulted);
        rig.Session.Status.Message.Should().Contain("changed since the split").And.Contain(Path.GetFileName(victim));
        rig.Sim.RunUntilIdle(TimeSpan.FromHours(1));
        var ran = rig.ExecutedLines();
        ran.Should().Equal(expected.Take(ran.Count), "what ran is the start of the program, nothing repeated or skipped");
        ran[^1].Should().BeLessThan(rig.Program.Chunk(6).FirstSourceLine, "nothing of the changed chunk reached the controller");

        File.WriteAllBytes(victim, original);
        (await rig.Session.RecoverAsync()).Should().BeTrue(rig.Session.Status.Message);
        (await rig.RunAsync(1.0)).Should().BeTrue(rig.Session.Status.Message);
        rig.ExecutedLines().Should().Equal(expected, "every block once, in order, across the fault");
    }

    [Fact]
    public void A_changed_chunk_is_refused_when_it_is_read_naming_the_file()
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 300, new StreamingOptions { BufferWords = 20_000 });
        var victim = rig.Program.ChunkPath(2);
        File.WriteAllBytes(victim, File.ReadAllBytes(victim)[..^20]); // truncated, as by a full disk or an interrupted copy

        var act = () => rig.Program.Body(2);

        act.Should().Throw<InvalidDataException>().WithMessage($"*{Path.GetFileName(victim)}*changed since the split*split the program again*");
    }
}
