using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Sim.Tests.Engine;

/// <summary>What the host generates must be what the controller accepts: the PROG 1000/1001 library, line by line.</summary>
public class LibraryAcceptanceTests
{
    [Fact]
    public void Every_line_of_the_generated_prog1000_library_is_accepted()
    {
        using var h = new SimHarness();
        var refused = new List<string>();
        foreach (var raw in Prog1000Library.Generate(MachineProfile.Default).Split('\n'))
        {
            var line = raw.Trim();
            var code = line.IndexOf(';');
            if (code >= 0)
            {
                line = line[..code].Trim();
            }

            if (line.Length == 0)
            {
                continue;
            }

            var reply = h.Send(line);
            if (reply != "<ACK>")
            {
                refused.Add($"{line} -> {reply}");
            }
        }

        refused.Should().BeEmpty();
    }

    [Fact]
    public void Cutter_compensation_codes_are_stored_and_run()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 1 CLEAR", "CCR2.5 CC1 LINEAR X10 F600", "CC0 X20", "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        h.Sim.ExecutedMoves.Select(m => m.X).Should().Equal(10, 20);
        h.Send("CC3").Should().Contain("ERR003");
    }
}
