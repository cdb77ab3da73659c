using PmacStream.Plc;

namespace PmacStream.Core.Tests.Plc;

public class PlcGeneratorTests
{
    // The motor forward/reverse interlock's two published PLC statements (OCR damage 'I' -> '|', '1' -> '|' repaired).
    private const string SeedKm1 = "(M800^1)&(M801|M900)&(M901^1)&(M803^1)";
    private const string SeedKm2 = "(M800^1)&(M802|M901)&(M900^1)&(M803^1)";

    private static LadderProgram Motor() =>
        LadderParser.Parse(File.ReadAllText(Path.Combine(PlcTestPaths.Samples, "motor-fwd-rev.ladder")), "motor-fwd-rev.ladder");

    private static long Eval(string expr, IReadOnlyDictionary<int, long> values)
    {
        var ev = new PlcEvaluator();
        foreach (var (m, v) in values)
        {
            ev.Set(m, v);
        }

        return PlcEvaluator.ParseExpression(expr).Eval(ev);
    }

    [Fact]
    public void Seed_motor_circuit_generates_the_seed_statements()
    {
        var g = PlcGenerator.Generate(Motor());
        g.PlcNumber.Should().Be(10);
        g.Statements.Select(s => s.Statement).Should().Equal("M900=" + SeedKm1, "M901=" + SeedKm2);
    }

    [Fact]
    public void Generated_rungs_have_the_seed_truth_tables_over_all_inputs()
    {
        var g = PlcGenerator.Generate(Motor());
        int[] vars = [800, 801, 802, 803, 900, 901];
        var seed = new[] { SeedKm1, SeedKm2 };
        for (var r = 0; r < 2; r++)
        {
            var generated = g.Statements[r].Statement[(g.Statements[r].Statement.IndexOf('=') + 1)..];
            var ones = 0;
            for (var bits = 0; bits < 1 << vars.Length; bits++)
            {
                var values = vars.Select((m, k) => (m, (long)((bits >> k) & 1))).ToDictionary(x => x.m, x => x.Item2);
                var want = Eval(seed[r], values);
                Eval(generated, values).Should().Be(want, $"rung {r} with inputs {Convert.ToString(bits, 2).PadLeft(6, '0')}");
                ones += (int)want;
            }

            ones.Should().BeInRange(1, (1 << vars.Length) - 1, "the truth table is not constant, so the comparison can fail");
        }
    }

    [Fact]
    public void Program_layout_is_definitions_then_input_copy_rungs_output_copy_and_enable()
    {
        var g = PlcGenerator.Generate(Motor(), new PlcGeneratorOptions { PlcNumber = 3 });
        var l = g.DownloadLines;
        l[0].Should().Be("DISABLE PLC 3");
        l.Should().ContainInOrder(
            "M1000->Y:$078800,0,8", "M1001->Y:$0010F0,0,8", "M1002->Y:$078801,0,8", "M1003->Y:$0010F1,0,8",
            "M800->Y:$0010F0,0", "M803->Y:$0010F0,3", "M900->Y:$0010F1,0", "M901->Y:$0010F1,1");
        var open = l.ToList().IndexOf("OPEN PLC 3 CLEAR");
        open.Should().BeGreaterThan(0);
        l.Take(open).Where(x => !x.StartsWith("DISABLE", StringComparison.Ordinal)).Should().OnlyContain(x => x.Contains("->"));
        l[open + 1].Should().Be("M1001=M1000");
        l[^3].Should().Be("M1002=M1003");
        l[^2].Should().Be("CLOSE");
        l[^1].Should().Be("ENABLE PLC 3");
        g.DownloadLines.Should().OnlyContain(x => !x.Contains(';'));
        g.Text.Should().Contain("M900=(M800^1)&(M801|M900)&(M901^1)&(M803^1) ; KM1 (line 16)\r\n");
    }

    [Fact]
    public void Rung_statements_touch_only_image_bits_never_the_physical_words()
    {
        var program = LadderParser.Parse(File.ReadAllText(Path.Combine(PlcTestPaths.Samples, "sand-mould-spindle.ladder")));
        var g = PlcGenerator.Generate(program);
        var allowed = program.Symbols.Select(s => s.MVariable).ToHashSet();
        foreach (var s in g.Statements)
        {
            var refs = System.Text.RegularExpressions.Regex.Matches(s.Statement, @"M(\d+)").Select(m => int.Parse(m.Groups[1].Value));
            refs.Should().OnlyContain(m => allowed.Contains(m), s.Statement);
        }

        g.PlcNumber.Should().Be(11);
        g.Statements.Single(s => s.Rung.Coil.Name == "SPINDLE").Statement.Should().StartWith("M902=");
        g.DownloadLines.Should().Contain("M1000->Y:$078800,0,16").And.Contain("M1100->Y:$0010F2,0").And.Contain("M1101->Y:$0010F2,1");
    }

    [Fact]
    public void Plc_number_comes_from_the_option_then_the_file_then_defaults_to_1()
    {
        var p = LadderParser.Parse("input A 0\noutput B 0\nB = A\n");
        PlcGenerator.Generate(p).PlcNumber.Should().Be(1);
        PlcGenerator.Generate(p with { PlcNumber = 5 }).PlcNumber.Should().Be(5);
        PlcGenerator.Generate(p with { PlcNumber = 5 }, new PlcGeneratorOptions { PlcNumber = 0 }).DownloadLines.Should().Contain("OPEN PLC 0 CLEAR");
        var bad = () => PlcGenerator.Generate(p, new PlcGeneratorOptions { PlcNumber = 32 });
        bad.Should().Throw<PlcGenerationException>();
    }

    [Theory]
    [InlineData("B = !(A | C)", "B=((M800|M802)^1)")]
    [InlineData("B = !(A & C) | A", "B=((M800&M802)^1)|M800")]
    [InlineData("B = A & C | !A & !C", "B=(M800&M802)|((M800^1)&(M802^1))")]
    [InlineData("B = !A", "B=(M800^1)")]
    [InlineData("B = A", "B=M800")]
    public void Format_brackets_every_group(string rung, string expected)
    {
        var p = LadderParser.Parse("input A 0\ninput C 2\noutput B 0\n" + rung + "\n");
        PlcGenerator.Generate(p).Statements[0].Statement.Should().Be(expected.Replace("B=", "M900=", StringComparison.Ordinal));
    }

    [Fact]
    public void A_rung_longer_than_a_pmac_line_is_refused_with_its_line()
    {
        var names = Enumerable.Range(0, 8).Select(i => $"I{i}").ToList();
        var decl = string.Concat(names.Select((n, i) => $"input {n} {i}\n")) + "output Q 0\n";
        var rung = "Q = " + string.Join(" | ", Enumerable.Range(0, 30).Select(k => $"(!{names[k % 8]} & {names[(k + 3) % 8]})"));
        var act = () => PlcGenerator.Generate(LadderParser.Parse(decl + rung + "\n"));
        act.Should().Throw<PlcGenerationException>().WithMessage("line 10:*split it with an internal relay*");
    }

    /// <summary>
    /// Property: for random contact networks, the generated PMAC expression (run through the PMAC-precedence
    /// evaluator) equals the network's own boolean meaning for every input combination.
    /// </summary>
    [Fact]
    public void Random_networks_generate_equivalent_expressions()
    {
        var rng = new Random(20261122);
        var names = new[] { "A", "B", "C", "D", "E" };
        var decl = string.Concat(names.Select((n, i) => $"input {n} {i}\n")) + "output Q 0\n";
        for (var trial = 0; trial < 300; trial++)
        {
            var text = RandomNetwork(rng, names, 3);
            var program = LadderParser.Parse(decl + "Q = " + text + "\n");
            var stmt = PlcGenerator.Generate(program).Statements[0].Statement;
            var expr = PlcEvaluator.ParseExpression(stmt[(stmt.IndexOf('=') + 1)..]);
            for (var bits = 0; bits < 32; bits++)
            {
                var ev = new PlcEvaluator();
                for (var k = 0; k < 5; k++)
                {
                    ev.Set(800 + k, (bits >> k) & 1);
                }

                var want = Meaning(program.Rungs[0].Network, bits) ? 1L : 0L;
                expr.Eval(ev).Should().Be(want, $"{text} -> {stmt} at inputs {bits}");
            }
        }
    }

    [Fact]
    public void Pmac_precedence_in_the_evaluator_binds_and_tighter_than_or_and_xor()
    {
        // Why the generator brackets: unbracketed, M800^1&M801 means M800^(1&M801) on a PMAC.
        var values = new Dictionary<int, long> { [800] = 1, [801] = 0 };
        Eval("M800^1&M801", values).Should().Be(1);
        Eval("(M800^1)&M801", values).Should().Be(0);
        Eval("1|0&0", values).Should().Be(1);
        Eval("2+3*4", values).Should().Be(14);
    }

    private static bool Meaning(LadderExpr e, int bits) => e switch
    {
        LadderContact c => (((bits >> (c.Symbol.MVariable - 800)) & 1) == 1) != c.NormallyClosed,
        LadderSeries s => s.Items.All(x => Meaning(x, bits)),
        LadderParallel p => p.Items.Any(x => Meaning(x, bits)),
        LadderNot n => !Meaning(n.Inner, bits),
        _ => throw new ArgumentException(e.ToString()),
    };

    private static string RandomNetwork(Random rng, string[] names, int depth)
    {
        var kind = depth == 0 ? 0 : rng.Next(4);
        return kind switch
        {
            0 => (rng.Next(2) == 0 ? "!" : "") + names[rng.Next(names.Length)],
            1 => "(" + string.Join(" & ", Enumerable.Range(0, rng.Next(2, 4)).Select(_ => RandomNetwork(rng, names, depth - 1))) + ")",
            2 => "(" + string.Join(" | ", Enumerable.Range(0, rng.Next(2, 4)).Select(_ => RandomNetwork(rng, names, depth - 1))) + ")",
            _ => "!(" + RandomNetwork(rng, names, depth - 1) + ")",
        };
    }
}
