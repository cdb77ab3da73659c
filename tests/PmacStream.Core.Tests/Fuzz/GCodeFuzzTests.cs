using System.Text;
using PmacStream.Core.Tests.Preparation;
using PmacStream.GCode;
using PmacStream.Preparation;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.Fuzz;

/// <summary>
/// Fuzz targets of the lexer, the checker and the splitter (issue 20): seeded random programs and mutations of the
/// sample and the shared CAM corpus (bytes flipped, lines cut, doubled and swapped, runs of junk words, numbers and
/// parentheses thousands long, NULs, byte-order marks, lines past the 1 MiB cut). Each input must finish, raise no
/// exception but the splitter's documented refusal, list at most 64 findings a line while counting every one, give
/// the same findings, totals and positions through the splitter's lane as through the full path, and never split what
/// the check refuses. <c>PMACSTREAM_FUZZ_SECONDS</c> (4 in CI) and <c>PMACSTREAM_FUZZ_SEED</c> as for the simulator's
/// targets; <c>bench/scripts/fuzz.sh</c> runs them longer from fresh seeds. A failure names the seed and the input,
/// and keeps the input in the temporary folder.
/// </summary>
public sealed class GCodeFuzzTests(ITestOutputHelper output)
{
    private const string Interesting = "GMXYZIJKRFSTHDPNO%/();.-+ \t\r\n0123456789@\0\u00e9:;";
    private static readonly string[] Runs = ["X ", "X1", "(", ")", "9", ".", "-", "N1 ", "G0", "G1X1", "%\n", "/", "\r", "\0", "M3S", "x", ";"];

    [Fact]
    public async Task The_lexer_and_checker_survive_seeded_and_mutated_programs_and_agree_with_the_lane()
    {
        var budget = new FuzzBudget(3030);
        var random = new Random(budget.Seed);
        var seeds = Seeds();
        long inputs = 0, bytes = 0, findings = 0, unlisted = 0, laneLines = 0;
        // The time budget, but never fewer inputs than the assertions below need: a loaded machine runs slower.
        while (budget.Left || inputs <= 20)
        {
            var text = NextInput(random, seeds);
            var profile = MachineProfile.Named(MachineProfile.BuiltInNames[random.Next(MachineProfile.BuiltInNames.Count)])!;
            var what = $"seed {budget.Seed}, input {inputs} ({text.Length} bytes, profile {profile.Name}, kept as {Kept(budget, inputs)})";
            var summary = await FinishesAsync(() => CheckSane(profile, text, what), text, what);
            laneLines += await FinishesAsync(() => AxisLaneTests.CheckSameThroughTheLane(text, profile, what), text, what);
            findings += summary.Errors + summary.Warnings;
            unlisted += summary.UnlistedErrors + summary.UnlistedWarnings;
            bytes += text.Length;
            inputs++;
        }

        inputs.Should().BeGreaterThan(20);
        findings.Should().BeGreaterThan(0, "mutated programs must reach the findings");
        laneLines.Should().BeGreaterThan(0, "the lane must take lines too");
        output.WriteLine($"seed {budget.Seed}: {inputs} inputs ({bytes / 1024} KiB) in {budget.Elapsed.TotalSeconds:0.0} s, {findings} findings ({unlisted} counted, not listed), {laneLines} lines through the lane; 0 exceptions, 0 hangs, 0 lane disagreements");
    }

    [Fact]
    public async Task The_splitter_never_splits_what_the_check_refuses_and_splits_the_same_through_the_lane()
    {
        var budget = new FuzzBudget(3031);
        var random = new Random(budget.Seed);
        var seeds = Seeds();
        long inputs = 0, refused = 0, split = 0;
        while (budget.Left || inputs <= 5)
        {
            // Fewer mutations than for the checker: more inputs get through the check and are split.
            var text = NextInput(random, seeds, random.Next(2) == 0 ? 2 : 40);
            var what = $"seed {budget.Seed}, input {inputs} ({text.Length} bytes, kept as {Kept(budget, inputs)})";
            var options = new SplitOptions
            {
                CheckProfile = MachineProfile.Default,
                Tracking = random.Next(2) == 0 ? TrackingPlacement.Exact : TrackingPlacement.Paper,
                Feed = random.Next(2) == 0 ? FeedMode.Paper : FeedMode.Override,
                BlocksPerChunk = random.Next(5, 300),
            };
            var errors = new Checker(MachineProfile.Default).Check(new MemoryStream(text), "fuzz", _ => { }).Errors;
            var outcome = await FinishesAsync(() => SplitOnce(text, options, what), text, what);
            if (errors > 0)
            {
                outcome.Should().NotBe(SplitOutcome.Split, $"the check found {errors} error(s): nothing of it may reach a chunk ({what})");
            }

            refused += outcome == SplitOutcome.Refused ? 1 : 0;
            split += outcome == SplitOutcome.Split ? 1 : 0;
            await FinishesAsync(
                () =>
                {
                    AxisLaneTests.SameSplit(text, options with { CheckProfile = random.Next(2) == 0 ? MachineProfile.Default : null, AllowErrors = random.Next(2) == 0 }, what);
                    return 0;
                },
                text,
                what);
            inputs++;
        }

        inputs.Should().BeGreaterThan(5);
        output.WriteLine($"seed {budget.Seed}: {inputs} inputs in {budget.Elapsed.TotalSeconds:0.0} s, {split} split, {refused} refused; 0 exceptions, 0 hangs, 0 lane disagreements");
    }

    private enum SplitOutcome
    {
        Split,
        Refused,
    }

    /// <summary>Splits once; the splitter's refusal (<see cref="SplitException"/>) is its documented answer to bad input.</summary>
    private static SplitOutcome SplitOnce(byte[] text, SplitOptions options, string what)
    {
        using var program = new TempProgram(text);
        try
        {
            var result = program.Split(options);
            result.Manifest.TotalBlocks.Should().BeGreaterThan(0, what);
            return SplitOutcome.Split;
        }
        catch (SplitException e)
        {
            e.ErrorCount.Should().BeGreaterThan(0, what);
            e.Diagnostics.Count.Should().BeLessThanOrEqualTo(Math.Max(options.MaxReportedErrors, 1), what);
            return SplitOutcome.Refused;
        }
    }

    /// <summary>Checks <paramref name="text"/>: nothing thrown, findings in range, at most 64 listed a line, every one counted.</summary>
    private static CheckSummary CheckSane(MachineProfile profile, byte[] text, string what)
    {
        var listed = new List<Diagnostic>();
        var blocks = 0L;
        var summary = new Checker(profile).Check(new MemoryStream(text), "fuzz", listed.Add, _ => blocks++);
        var lines = Math.Max(1, summary.Lines);
        listed.Should().NotContain(d => d.Line < 1 || d.Line > lines || d.Column < 1 || d.Message.Length == 0, what);
        listed.GroupBy(d => d.Line).Should().NotContain(g => g.Count() > FindingLimits.PerLine + 3, what);
        summary.Errors.Should().Be(listed.Count(d => d.Severity == Severity.Error) + summary.UnlistedErrors, what);
        summary.Warnings.Should().Be(listed.Count(d => d.Severity == Severity.Warning) + summary.UnlistedWarnings, what);
        summary.Blocks.Should().Be(blocks, what);
        double.IsFinite(summary.EstimatedSeconds).Should().BeTrue(what);
        return summary;
    }

    /// <summary>
    /// Runs one input's work; more than <see cref="FuzzBudget.HangLimit"/> is a hang, any exception a failure. A failing
    /// input is kept in the temporary folder under the name <paramref name="what"/> gives, to run again.
    /// </summary>
    private static async Task<T> FinishesAsync<T>(Func<T> work, byte[] text, string what)
    {
        var run = Task.Run(work);
        try
        {
            if (await Task.WhenAny(run, Task.Delay(FuzzBudget.HangLimit)) != run)
            {
                throw new Xunit.Sdk.XunitException($"the input must finish within {FuzzBudget.HangLimit.TotalSeconds:0} s ({what})");
            }

            return await run;
        }
        catch (Exception e)
        {
            var kept = what[(what.IndexOf("kept as ", StringComparison.Ordinal) + 8)..^1];
            await File.WriteAllBytesAsync(kept, text);
            throw e is Xunit.Sdk.XunitException ? e : new Xunit.Sdk.XunitException($"{e.GetType().Name}: {e.Message} ({what})");
        }
    }

    private static string Kept(FuzzBudget budget, long input) => Path.Combine(Path.GetTempPath(), $"pmacstream-fuzz-{budget.Seed}-{input}.nc");

    /// <summary>What mutations start from: the sample program and the shared corpus (when it is there), at most 24 KiB of each.</summary>
    private static List<byte[]> Seeds()
    {
        var files = new List<string> { RepoRoot.DemoProgram };
        files.AddRange(RepoRoot.CorpusPrograms ?? []);
        return files.Select(f => File.ReadAllBytes(f)).Select(b => b.Length > 24 << 10 ? b[..(24 << 10)] : b).ToList();
    }

    /// <summary>A random program or a seed, with up to <paramref name="maxMutations"/> mutations.</summary>
    private static byte[] NextInput(Random random, List<byte[]> seeds, int maxMutations = 40)
    {
        var start = random.Next(3) == 0
            ? AxisLaneTests.RandomProgram(random, random.Next(20, 300), clean: random.Next(2) == 0)
            : seeds[random.Next(seeds.Count)];
        var bytes = new List<byte>(start);
        for (var n = random.Next(0, maxMutations + 1); n > 0; n--)
        {
            Mutate(bytes, random);
        }

        return [.. bytes];
    }

    private static void Mutate(List<byte> bytes, Random random)
    {
        var at = bytes.Count == 0 ? 0 : random.Next(bytes.Count);
        switch (random.Next(12))
        {
            case 0:
                if (bytes.Count > 0)
                {
                    bytes[at] = (byte)random.Next(256);
                }

                break;
            case 1:
            case 2:
                bytes.Insert(at, (byte)Interesting[random.Next(Interesting.Length)]);
                break;
            case 3:
                bytes.RemoveRange(at, Math.Min(bytes.Count - at, random.Next(1, 200)));
                break;
            case 4:
                bytes.InsertRange(at, Repeat(Runs[random.Next(Runs.Length)], random.Next(1, random.Next(2) == 0 ? 40 : 3000)));
                break;
            case 5:
                // A line or a stretch copied elsewhere: doubled and swapped blocks.
                var length = Math.Min(bytes.Count - at, random.Next(1, 400));
                bytes.InsertRange(random.Next(bytes.Count + 1), bytes.GetRange(at, length));
                break;
            case 6:
                bytes.InsertRange(at, Encoding.ASCII.GetBytes(random.Next(4) switch
                {
                    0 => "G01 X" + new string('9', random.Next(14, 400)),
                    1 => "N" + random.Next() + " G02 X1 Y1 R0.0000001\n",
                    2 => "G01 X1e308 F-0\n",
                    _ => "G04 P" + random.Next() + "\n",
                }));
                break;
            case 7:
                bytes.Insert(at, (byte)(random.Next(3) switch { 0 => '\r', 1 => '\n', _ => 0 }));
                break;
            case 8:
                if (random.Next(40) == 0)
                {
                    // Past the 1 MiB cut (E114): rare, it is most of an input's time.
                    bytes.InsertRange(at, Repeat("X ", (GCodeReader.MaxLineLength / 2) + random.Next(1, 1000)));
                }

                break;
            case 9:
                if (random.Next(20) == 0)
                {
                    bytes.InsertRange(0, random.Next(2) == 0 ? [0xFF, 0xFE] : [0xEF, 0xBB, 0xBF]);
                }

                break;
            case 10:
                bytes.InsertRange(at, Encoding.ASCII.GetBytes("%\n"));
                break;
            default:
                bytes.RemoveRange(at, bytes.Count - at); // cut short
                break;
        }
    }

    private static byte[] Repeat(string text, int times) => Encoding.Latin1.GetBytes(new StringBuilder(text.Length * times).Insert(0, text, times).ToString());

}
