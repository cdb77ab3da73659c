using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 16's measure on the twelve real programs of ../shared/gcode-corpus, through the one gate every face uses
/// (the job service's prepare step, default profile): a program with errors is refused for them (named in
/// CorpusUnderDefaultProfileTests), a program with codes the controller cannot run yet is refused naming each code at
/// its first line, and every program the gate passes streams into the simulator (chunk strategy, going on at program
/// stops) with every moving line executed exactly once, in order.
/// </summary>
public sealed class CorpusStreamTests(ITestOutputHelper output) : IDisposable
{
    /// <summary>
    /// The codes the controller cannot run yet, with their first lines: refused unless forced. None left in the corpus:
    /// mill_hp_2's M31 and M33 (chip conveyor) run as the library's machine outputs, and its G41 without a radius is an
    /// error (E132), so it is among the programs with errors.
    /// </summary>
    private static readonly Dictionary<string, string> NotYet = new();

    /// <summary>Programs the check refuses under the default profile (why: CorpusUnderDefaultProfileTests).</summary>
    private static readonly HashSet<string> WithErrors =
        ["pete-restall__Cluck2Sesame-Prototype__Enclosure.nc", "danheeks__voxelcut__gr105.tap", "enier290188__cnc__mill_hp_2.nc"];

    /// <summary>
    /// Programs that check clean and that the controller runs as they are: inch units, G28/G30, G53, tool changes,
    /// tool length and canned cycles through the library and the host's conversions.
    /// </summary>
    private static readonly HashSet<string> Runnable =
    [
        "SabirHusnain__CNC-GCode-Milling-and-Lathe__Nikola.nc", "Sienci-Labs__gsender__MB-2.3_test.nc", "CauldronDevelopmentLLC__CAMotics__flower_mold.nc",
        "CauldronDevelopmentLLC__CAMotics__vcarve.ngc", "LMHDPRO__MAC__1003.nc", "SafetyDav3__cnc-sprayer__fusion-inch.nc", "Sienci-Labs__gsender__KB-22_test.gcode",
        "rustyford__cam__router_panel.ngc", "stcline__CNC_Training__smiley.nc",
    ];

    private readonly TestFolder _temp = new("corpus-stream");

    public void Dispose() => _temp.Dispose();

    public static TheoryData<string> Programs => new(NotYet.Keys.Concat(WithErrors).Concat(Runnable).Order(StringComparer.Ordinal));

    [SkippableTheory]
    [MemberData(nameof(Programs))]
    public async Task Each_corpus_program_passes_the_gate_and_runs_every_moving_line_once_or_is_refused_naming_why(string name)
    {
        var files = Requires.Corpus();
        files.Select(Path.GetFileName).Should().BeEquivalentTo(NotYet.Keys.Concat(WithErrors).Concat(Runnable), "every corpus program is in one of the three lists");
        var source = files.Single(f => Path.GetFileName(f) == name);
        var service = new JobService(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });
        var request = new PrepareRequest(source, RunSettings.Default) { OutDir = Path.Combine(_temp.Path, "chunks") };

        if (!Runnable.Contains(name))
        {
            var act = () => service.PrepareAsync(request);
            var refused = (await act.Should().ThrowAsync<ProgramRefusedException>()).Which;
            if (WithErrors.Contains(name))
            {
                refused.ErrorCount.Should().BeGreaterThan(0);
                refused.NotRunnableCodes.Should().BeEmpty("the check's errors refuse it first");
                refused.Diagnostics.Should().OnlyContain(d => d.Severity == Severity.Error && d.Code.StartsWith('E'));
            }
            else
            {
                ProgramGate.Describe(refused.NotRunnableCodes).Should().Be(NotYet[name]);
                refused.Diagnostics.Select(d => (d.Code, d.Line)).Should().Equal(refused.NotRunnableCodes.OrderBy(c => c.Value).ThenBy(c => c.Key, StringComparer.Ordinal).Select(c => (DiagnosticCodes.NotRunnableInJob, c.Value)));
                refused.Diagnostics.Should().OnlyContain(d => d.Column >= 1);
            }

            output.WriteLine($"{name}: refused: {refused.Message}");

            // Forced past the gate, as `stream --force` runs it (what is not G-code is dropped, a code not runnable
            // yet is skipped by the controller): the streaming itself still runs every moving line once.
            var forced = await service.PrepareAsync(request with { Force = true });
            if (!WithErrors.Contains(name))
            {
                forced.Program.Manifest.NotYetCodes.Should().NotBeEmpty();
            }

            await StreamExactlyOnceAsync(name + " (forced)", forced.Program);
            return;
        }

        var prepared = await service.PrepareAsync(request);
        prepared.Program.Manifest.NotYetCodes.Should().BeEmpty();
        await StreamExactlyOnceAsync(name, prepared.Program);
    }

    private async Task StreamExactlyOnceAsync(string name, ChunkedProgram program)
    {
        using var sim = new PmacSimulator(new SimOptions { RetainExecutedMoves = false });
        var port = sim.OpenPort("stream");
        SimRig.LoadLibrary(port);
        var check = new ExecutedLineCheck(program.TrackedLines(), null, program.ExpandedBlocks()).Attach(sim);
        var options = RunSettings.Default.ToStreamingOptions(StrategyKind.Chunk, singleBlock: false, defineBuffer: true);
        var session = new StreamingSession(new InProcessConnection(port, "sim"), program, options, time: SimRig.Clock(sim));
        await session.StartAsync();
        var stops = 0;
        for (var tick = 0; tick < 200_000 && session.State != SessionState.Completed; tick++)
        {
            session.State.Should().NotBe(SessionState.Faulted, session.Status.Message);
            await session.TickAsync();
            if (session.State == SessionState.Stopped)
            {
                stops++;
                await session.ResumeMotionAsync(); // --stops continue
            }

            sim.Advance(TimeSpan.FromSeconds(2));
        }

        session.State.Should().Be(SessionState.Completed, session.Status.Message);
        sim.RunUntilIdle(TimeSpan.FromHours(24));
        var result = check.Finish();
        result.FirstBreak.Should().BeNull();
        result.Executed.Should().Be(program.Manifest.TotalMotionBlocks).And.Be(result.Expected, "every moving line once, in order");
        output.WriteLine($"{name}: {result.Executed} of {program.Manifest.TotalMotionBlocks} blocks executed once, {session.Status.Underruns} underruns, {stops} program stops");
    }
}
