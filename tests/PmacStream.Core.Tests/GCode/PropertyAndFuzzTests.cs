using System.Globalization;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>Seeded property and fuzz tests (hand-written generators: no FsCheck here).</summary>
public class PropertyAndFuzzTests
{
    private static double Val(Random r, int range, int decimals) =>
        Math.Round((r.NextDouble() * 2 - 1) * range, decimals);

    private static string Num(double v) => v.ToString("0.####", CultureInfo.InvariantCulture);

    private static string RandomBlock(Random r)
    {
        var sb = new StringBuilder();
        if (r.Next(3) > 0)
        {
            sb.Append("N").Append(r.Next(1, 100000)).Append(' ');
        }

        var motion = r.Next(6);
        switch (motion)
        {
            case 0: sb.Append("G00 "); break;
            case 1: sb.Append("G01 "); break;
            case 2: sb.Append("G02 "); break;
            case 3: sb.Append("G03 "); break;
            case 4: sb.Append("G04 P").Append(r.Next(0, 5000)).Append(' '); break;
        }

        if (motion != 4)
        {
            foreach (var axis in "XYZ")
            {
                if (r.Next(3) > 0)
                {
                    sb.Append(axis).Append(Num(Val(r, 500, 4))).Append(' ');
                }
            }

            if (motion is 2 or 3)
            {
                if (r.Next(2) == 0)
                {
                    sb.Append("R").Append(Num(Val(r, 300, 3))).Append(' ');
                }
                else
                {
                    sb.Append("I").Append(Num(Val(r, 100, 4))).Append(" J").Append(Num(Val(r, 100, 4))).Append(' ');
                }
            }
        }

        if (r.Next(4) == 0)
        {
            sb.Append("F").Append(Num(Math.Abs(Val(r, 5000, 1)))).Append(' ');
        }

        if (r.Next(8) == 0)
        {
            sb.Append("S").Append(r.Next(0, 24000)).Append(' ');
        }

        if (r.Next(10) == 0)
        {
            sb.Append("T").Append(r.Next(0, 25)).Append(' ');
        }

        return sb.ToString().TrimEnd();
    }

    [Fact]
    public void Formatting_a_decoded_block_and_reading_it_again_gives_the_same_block()
    {
        var r = new Random(20261122);
        var interp = new Interpreter(MachineProfile.Default);
        var checkedBlocks = 0;
        for (var i = 0; i < 3000; i++)
        {
            var text = RandomBlock(r);
            var stateBefore = interp.State;
            var positionBefore = interp.Position;
            var original = interp.Step(GCodeReader.LexLine(text, i + 1));
            if (original is null)
            {
                continue;
            }

            var formatted = original.ToGCode();
            var replay = new Interpreter(MachineProfile.Default, stateBefore, positionBefore);
            var again = replay.Step(GCodeReader.LexLine(formatted, i + 1));
            if (again != original)
            {
                again.Should().BeEquivalentTo(original, $"'{text}' was formatted as '{formatted}'");
            }

            again.Should().Be(original);
            checkedBlocks++;
        }

        checkedBlocks.Should().BeGreaterThan(2500);
    }

    [Fact]
    public void Number_text_round_trips_through_the_lexer()
    {
        var r = new Random(42);
        for (var i = 0; i < 5000; i++)
        {
            var v = Val(r, 100000, r.Next(0, 5));
            var b = GCodeReader.LexLine("X" + ModalState.Num(v));
            b.Words.Should().ContainSingle().Which.Value.Should().Be(v);
        }
    }

    [Fact]
    public void Checker_never_throws_on_random_bytes_and_reports_lines_in_range()
    {
        var r = new Random(1234);
        var checker = new Checker(MachineProfile.Default);
        for (var i = 0; i < 300; i++)
        {
            var bytes = new byte[r.Next(0, 3000)];
            r.NextBytes(bytes);
            AssertSane(checker, bytes);
        }
    }

    [Fact]
    public void Checker_never_throws_on_mutated_programs()
    {
        var demo = File.ReadAllBytes(RepoRoot.DemoProgram)[..6000];
        const string Interesting = "GMXYZIJKRFSTHDPNO%/();.-+ \t\r\n0123456789@\0é";
        var r = new Random(99);
        var checker = new Checker(MachineProfile.Default);
        for (var i = 0; i < 300; i++)
        {
            var bytes = (byte[])demo.Clone();
            var mutations = r.Next(1, 40);
            for (var m = 0; m < mutations; m++)
            {
                var at = r.Next(bytes.Length);
                bytes[at] = r.Next(3) switch
                {
                    0 => (byte)r.Next(256),
                    _ => (byte)Interesting[r.Next(Interesting.Length)],
                };
            }

            AssertSane(checker, bytes);
        }
    }

    private static void AssertSane(Checker checker, byte[] bytes)
    {
        var diags = new List<Diagnostic>();
        var blocks = new List<DecodedBlock>();
        var summary = checker.Check(new MemoryStream(bytes), "fuzz", diags.Add, blocks.Add);
        var lines = Math.Max(1, summary.Lines);
        diags.Where(d => d.Line < 1 || d.Line > lines || d.Column < 1 || d.Message.Length == 0).Should().BeEmpty();
        blocks.Where(b => b.Line < 1 || b.Line > lines || !double.IsFinite(b.DurationSeconds) || !double.IsFinite(b.End.X)).Should().BeEmpty();
        summary.Blocks.Should().Be(blocks.Count);
        summary.Errors.Should().Be(diags.Count(d => d.Severity == Severity.Error) + summary.UnlistedErrors, "every error is counted, listed or not");
        summary.Warnings.Should().Be(diags.Count(d => d.Severity == Severity.Warning) + summary.UnlistedWarnings);
        diags.GroupBy(d => d.Line).Should().NotContain(g => g.Count() > FindingLimits.PerLine + 3, "at most 64 a line are listed (with a W002 and the whole-program W001/E120, W007)");
    }
}
