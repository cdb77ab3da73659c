using System.Text;

namespace PmacStream.Sim.Tests.Engine;

/// <summary>Random and mutated command lines: the engine always answers a well-framed reply and never throws.</summary>
public class RobustnessTests
{
    private static readonly string[] Seeds =
    [
        "P500=80", "&1B0R", "OPEN ROT", "CLOSE", "M0==12 G01 X10 Y20 F(P500)", "OPEN PROG 1000 CLEAR", "N0 RAPID RET",
        "IF (M1=1 AND P2<3) P3=1", "WHILE (P1<3) P1=P1+1", "ENDWHILE", "M800->Y:$078800,0,8", "ENA PLC 1", "%50", "??",
        "DEFINE ROT 100", "DEL GAT", "LIST PROG 1000", "READ(X,Y)", "CALL 1000.01", "CIRCLE1 X1 Y1 R-5", "DWELL(P1*2)",
        "I3=2 I6=1", "$$$", "H", "Q", "A", "S", "R", "P1..3=4", "OPEN PLC 1 CLEAR", "#1->1000X", "PR", "X(P1/0)",
    ];

    [Fact]
    public void Random_and_mutated_lines_get_framed_replies()
    {
        using var h = new SimHarness(new SimOptions { DefaultRotWords = 5000 });
        var second = h.Sim.OpenPort("second");
        var rng = new Random(20261122);
        const string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 .=()+-*/&|^$#%?!<>,:;\"'~\\\t\x01\x06\x07\x18\x7f";
        for (var i = 0; i < 20_000; i++)
        {
            string line;
            switch (rng.Next(4))
            {
                case 0:
                    line = Seeds[rng.Next(Seeds.Length)];
                    break;
                case 1:
                    {
                        var chars = Seeds[rng.Next(Seeds.Length)].ToCharArray();
                        var mutations = rng.Next(1, 4);
                        for (var m = 0; m < mutations && chars.Length > 0; m++)
                        {
                            chars[rng.Next(chars.Length)] = alphabet[rng.Next(alphabet.Length)];
                        }

                        line = new string(chars);
                        break;
                    }

                case 2:
                    line = string.Concat(Enumerable.Range(0, rng.Next(0, 40)).Select(_ => alphabet[rng.Next(alphabet.Length)]));
                    break;
                default:
                    line = Seeds[rng.Next(Seeds.Length)] + " " + Seeds[rng.Next(Seeds.Length)];
                    break;
            }

            var port = rng.Next(3) == 0 ? second : h.Port;
            var reply = port.Execute(line);
            var text = Encoding.ASCII.GetString(reply);
            var framed = port.I3 switch
            {
                2 or 3 => text.EndsWith('\x06') || (text.Contains('\x07') && (port.I6 == 0 ? text.EndsWith('\x07') : text.EndsWith('\r'))),
                _ => true,
            };
            framed.Should().BeTrue($"reply to '{line}' was '{SimPort.Visible(reply)}'");
            h.Sim.InternalFaults.Should().Be(0, $"'{line}' must not hit a simulator bug");
            if (i % 100 == 0)
            {
                h.Advance(rng.NextDouble() * 2);
                h.Sim.RunPlcScan();
            }
        }

        h.Sim.RunUntilIdle(TimeSpan.FromHours(1));
        h.Send("CLOSE");
        second.Execute("CLOSE");
        h.Ok("I3=2 I6=1 P77=5 P77").Should().Be("5", "the controller still answers normally");
    }
}
