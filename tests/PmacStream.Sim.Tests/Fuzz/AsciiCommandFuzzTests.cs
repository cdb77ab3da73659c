using System.Text;
using PmacStream.Sim.Servers;
using Xunit.Abstractions;

namespace PmacStream.Sim.Tests.Fuzz;

/// <summary>
/// Fuzz target of the simulator's ASCII command parser (what the serial line and every packet's text reach):
/// seeded command lines built from the controller's own words, numbers and operators, then mutated (random bytes,
/// cut, doubled, huge numbers, deep nesting), run on one simulator whose virtual clock moves now and then so the
/// stored programs and PLCs run too. The documented answers are replies, <c>ERRnnn</c> included; an exception, an
/// engine fault or a line that does not finish fails, naming the seed and the line.
/// </summary>
public sealed class AsciiCommandFuzzTests(ITestOutputHelper output)
{
    private static readonly string[] Words =
    [
        "&1", "&2", "#1", "#3", "B0", "R", "S", "H", "Q", "A", "K", "%50", "%0", "PR", "?", "??", "???", "$$$", "VER", "CID", "TYPE",
        "OPEN ROT", "OPEN PROG 5", "OPEN PROG 1000", "OPEN PLC 3", "CLOSE", "CLEAR", "DEFINE ROT 200", "DEF ROT 8388607", "DELETE ROT",
        "DEL GAT", "LIST PROG 5", "LIST PLC 3", "LIST ROT", "ENABLE PLC 3", "DISABLE PLC 3", "ENA PLC 1..31", "SAVE",
        "P1=", "P500=", "Q7=", "I5=", "I3=", "I6=", "M0==", "M0=", "M1->Y:$078800,0,8", "M2->X:$0,4,U", "M3->", "M4->*", "#1->1000X",
        "LINEAR", "RAPID", "CIRCLE1", "CIRCLE2", "ABS", "INC", "NORMAL K-1", "X", "Y", "Z", "A", "U", "I", "J", "R", "F", "F(P500)", "TM", "TA", "TS",
        "DWELL", "DELAY", "IF(", "ELSE", "ENDIF", "WHILE(", "ENDWHILE", "GOTO", "GOSUB", "CALL", "RET", "RETURN", "STOP", "N", "G", "M", "T", "D",
        "READ(A,B)", "SIN(", "COS(", "SQRT(", "ABS(", "INT(", "ATAN2(", "EXP(", "LN(", ")", "+", "-", "*", "/", "%", "&", "|", "^", "!", "=", "==",
        "!=", ">", "<", "AND", "OR", ";", ",", "..", "$", ":",
    ];

    [Fact]
    public async Task The_command_parser_survives_seeded_mutated_lines()
    {
        var budget = new FuzzBudget(2028);
        var random = new Random(budget.Seed);
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Instant, RetainExecutedMoves = false, MaxStatementsPerCalculation = 10_000 });
        var port = sim.OpenPort("fuzz");
        long lines = 0, errors = 0;
        while (budget.Left)
        {
            var line = NextLine(random);
            var what = $"seed {budget.Seed}, line {lines}: '{Printable(line)}'";
            var run = Task.Run(() =>
            {
                var reply = port.Execute(line);
                if (random.Next(20) == 0)
                {
                    sim.Advance(TimeSpan.FromMilliseconds(random.Next(1, 200)));
                }

                return reply;
            });
            (await Task.WhenAny(run, Task.Delay(FuzzBudget.HangLimit)) == run).Should().BeTrue($"the line must finish ({what})");
            byte[] reply;
            try
            {
                reply = await run;
            }
            catch (Exception e)
            {
                throw new Xunit.Sdk.XunitException($"{e.GetType().Name}: {e.Message} ({what})");
            }

            errors += Array.IndexOf(reply, (byte)7) >= 0 ? 1 : 0;
            sim.InternalFaults.Should().Be(0, what);
            lines++;
        }

        lines.Should().BeGreaterThan(100);
        errors.Should().BeGreaterThan(0, "mutated lines must reach the error replies");
        (lines - errors).Should().BeGreaterThan(0, "generated lines must also be accepted");
        output.WriteLine($"seed {budget.Seed}: {lines} lines in {budget.Elapsed.TotalSeconds:0.0} s, {errors} answered with an error, {sim.Counters.MovesExecuted} moves run; 0 exceptions, 0 engine faults, 0 hangs");
    }

    [Fact]
    public async Task The_serial_line_survives_seeded_byte_streams()
    {
        var budget = new FuzzBudget(2029);
        var random = new Random(budget.Seed);
        using var sim = new PmacSimulator(new SimOptions { Speed = SimSpeed.Instant, RetainExecutedMoves = false });
        long streams = 0, bytes = 0;
        while (budget.Left)
        {
            // Lines with CRs, control characters (Ctrl-B..X), LFs and bytes above 127, as a line noise or a wrong baud rate sends.
            var text = new StringBuilder();
            for (var n = random.Next(1, 20); n > 0; n--)
            {
                text.Append(NextLine(random)).Append(random.Next(6) == 0 ? (char)random.Next(0, 32) : '\r');
            }

            var input = Encoding.Latin1.GetBytes(text.ToString());
            var stream = new ByteStreamScript(input, new Random(random.Next()));
            await using var server = new PmacSerialServer(() => sim.OpenPort("fuzz-serial"), stream);
            server.Start();
            var finished = await Task.WhenAny(server.Completion, Task.Delay(FuzzBudget.HangLimit)) == server.Completion;
            finished.Should().BeTrue($"seed {budget.Seed}, stream {streams}: {Convert.ToHexString(input)}");
            await server.Completion; // rethrows what the serving loop did not expect
            sim.InternalFaults.Should().Be(0);
            streams++;
            bytes += input.Length;
        }

        streams.Should().BeGreaterThan(10);
        output.WriteLine($"seed {budget.Seed}: {streams} streams ({bytes} bytes) in {budget.Elapsed.TotalSeconds:0.0} s; 0 exceptions, 0 engine faults, 0 hangs");
    }

    private static string NextLine(Random random)
    {
        var sb = new StringBuilder();
        for (var n = random.Next(1, 14); n > 0; n--)
        {
            sb.Append(random.Next(4) == 0 ? Number(random) : Words[random.Next(Words.Length)]);
            sb.Append(random.Next(3) == 0 ? string.Empty : " ");
        }

        var line = sb.ToString();
        return random.Next(6) switch
        {
            0 => Mutate(line, random),
            1 => Mutate(Mutate(line, random), random),
            _ => line,
        };
    }

    private static string Number(Random random) => random.Next(8) switch
    {
        0 => "1e308",
        1 => "-0",
        2 => "$" + random.Next().ToString("X", System.Globalization.CultureInfo.InvariantCulture),
        3 => new string('9', random.Next(20, 400)),
        4 => ".5",
        5 => "1.2.3",
        _ => random.Next(-100_000, 100_000).ToString(System.Globalization.CultureInfo.InvariantCulture),
    };

    private static string Mutate(string line, Random random)
    {
        if (line.Length == 0)
        {
            return line;
        }

        var i = random.Next(line.Length);
        return random.Next(6) switch
        {
            0 => line.Insert(i, ((char)random.Next(0, 256)).ToString()),
            1 => line.Remove(i, 1),
            2 => line[..i],
            3 => line + line,
            4 => line.Insert(i, new string('(', random.Next(1, 3000))),
            _ => line.Insert(i, new string(')', random.Next(1, 50))),
        };
    }

    private static string Printable(string line) =>
        new(line.Select(c => c is < ' ' or > '~' ? '?' : c).Take(400).ToArray());
}
