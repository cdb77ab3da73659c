using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>The move-time table stays exact for small programs and bounded (thinned, interpolated) for huge ones.</summary>
public class MoveTimeTableTests
{
    private static List<(int Line, double Seconds, double Feed)> Program(int blocks, int seed)
    {
        var r = new Random(seed);
        var list = new List<(int, double, double)>();
        var line = 3;
        for (var b = 0; b < blocks; b++)
        {
            line += 1 + r.Next(3); // non-motion lines in between
            var feed = 500 + (100 * r.Next(20));
            list.Add((line, r.NextDouble() * 0.5, feed));
            if (r.Next(10) == 0)
            {
                list.Add((line, r.NextDouble() * 0.1, feed)); // a block with two moves
            }
        }

        return list;
    }

    [Theory]
    [InlineData(1, 10_000, 64)]
    [InlineData(2, 5_001, 100)]
    [InlineData(3, 257, 16)]
    public void A_thinned_table_keeps_its_budget_the_exact_total_and_errs_at_most_one_interval(int seed, int blocks, int maxSamples)
    {
        var moves = Program(blocks, seed);
        var exact = new MoveTimeTable(moves, int.MaxValue);
        var thin = new MoveTimeTable(moves, maxSamples);

        exact.SampleCount.Should().Be(blocks);
        thin.BlockCount.Should().Be(blocks);
        thin.SampleCount.Should().BeLessThanOrEqualTo(maxSamples + 1, "the budget, plus the last block that always ends the table");
        thin.TotalSeconds.Should().BeApproximately(exact.TotalSeconds, 1e-6);

        // The largest span of one sampling interval bounds the interpolation error.
        var stride = (int)Math.Ceiling((double)blocks / thin.SampleCount);
        var maxInterval = 0.0;
        var lines = moves.Select(m => m.Line).Distinct().ToList();
        for (var i = 0; i < lines.Count; i += 1)
        {
            var from = i == 0 ? 0 : lines[i - 1];
            var to = lines[Math.Min(lines.Count - 1, i + (2 * stride))];
            maxInterval = Math.Max(maxInterval, exact.SecondsBetween(from, to));
        }

        var previous = 0.0;
        for (var line = 0; line <= lines[^1] + 2; line++)
        {
            var t = thin.Through(line);
            t.Should().BeGreaterThanOrEqualTo(previous - 1e-9, $"prefix times never fall (line {line})");
            Math.Abs(t - exact.Through(line)).Should().BeLessThanOrEqualTo(maxInterval + 1e-9, $"line {line}");
            previous = t;
        }

        thin.Through(lines[^1]).Should().BeApproximately(exact.TotalSeconds, 1e-6);
        thin.SecondsBetween(0, lines[^1]).Should().BeApproximately(exact.TotalSeconds, 1e-6);
    }

    [Fact]
    public void Below_the_budget_the_table_is_exact_line_for_line()
    {
        var moves = Program(500, 7);
        var a = new MoveTimeTable(moves, 1000);
        var b = new MoveTimeTable(moves, int.MaxValue);
        a.SampleCount.Should().Be(500);
        for (var line = 0; line <= moves[^1].Line + 1; line++)
        {
            a.Through(line).Should().Be(b.Through(line));
            a.ProgrammedFeedAt(line).Should().Be(b.ProgrammedFeedAt(line));
        }
    }

    [Fact]
    public void A_gigabyte_sized_program_costs_only_the_sample_budget()
    {
        // 3 million blocks (about 100 MB of G-code) through the default budget.
        static IEnumerable<(int, double, double)> Moves()
        {
            for (var i = 1; i <= 3_000_000; i++)
            {
                yield return (i, 0.001, 1000);
            }
        }

        var t = new MoveTimeTable(Moves(), MoveTimeTable.DefaultMaxSamples);
        t.BlockCount.Should().Be(3_000_000);
        t.SampleCount.Should().BeLessThanOrEqualTo(MoveTimeTable.DefaultMaxSamples + 1);
        t.TotalSeconds.Should().BeApproximately(3000, 1e-6);
        t.SecondsBetween(1_000_000, 2_000_000).Should().BeApproximately(1000, 1e-6, "uniform moves interpolate exactly");
        t.ProgrammedFeedAt(1_234_567).Should().Be(1000);
    }

    [Theory]
    [InlineData("G20")]
    [InlineData("G21")]
    public void A_dwell_is_timed_in_seconds_whatever_the_length_units(string units)
    {
        // G04 X is seconds, P milliseconds (FANUC): an inch program dwells as long as a millimetre one, not 25.4 times.
        using var folder = new TestFolder("eta-dwell");
        var path = Path.Combine(folder.Path, "dwell.nc");
        File.WriteAllText(path, $"O1\n{units} G90\nG04 X2.\nG04 P1500\nM30\n");
        var table = MoveTimeTable.FromProgram(path);
        table.SecondsBetween(2, 3).Should().Be(2.0);
        table.SecondsBetween(3, 4).Should().Be(1.5);
        table.TotalSeconds.Should().Be(3.5);
    }
}
