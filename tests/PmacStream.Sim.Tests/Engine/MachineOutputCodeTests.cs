using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Sim.Tests.Engine;

/// <summary>
/// fanuc-mill's machine output M codes run on the controller: the generated library's routine, called from a motion
/// program, leaves its output M-variable set in the simulator's memory, after the moves around it have run.
/// </summary>
public class MachineOutputCodeTests
{
    [Theory]
    [InlineData("M88", 909, 1, false)]
    [InlineData("M89", 909, 0, true)]
    [InlineData("M10", 910, 1, true)]
    [InlineData("M11", 910, 0, true)]
    [InlineData("M12", 911, 1, true)]
    [InlineData("M13", 911, 0, true)]
    [InlineData("M31", 912, 1, false)]
    [InlineData("M32", 912, 1, true)]
    [InlineData("M33", 912, 0, true)]
    [InlineData("M73", 914, 1, false)]
    [InlineData("M74", 914, 0, true)]
    [InlineData("M83", 915, 1, false)]
    [InlineData("M84", 915, 0, true)]
    public void Each_output_code_sets_its_output_variable_on_the_simulator(string code, int variable, int expected, bool waitsForMovesAhead)
    {
        using var h = new SimHarness();
        LoadLibrary(h);
        // Start from the other state, so the routine is what sets it.
        h.Ok($"M{variable}={1 - expected}");
        var kinds = Run(h, code);
        h.M(variable).Should().Be(expected, $"{code} sets M{variable} to {expected}");
        kinds.Should().Equal(waitsForMovesAhead ? [MoveKind.Linear, MoveKind.Dwell, MoveKind.Linear] : [MoveKind.Linear, MoveKind.Linear],
            waitsForMovesAhead ? "DWELL0 lets the move before end first" : "an output switched on does not stop the blend");
    }

    [Fact]
    public void The_chip_conveyor_direction_follows_forward_and_reverse()
    {
        using var h = new SimHarness();
        LoadLibrary(h);
        Run(h, "M32");
        (h.M(912), h.M(913)).Should().Be((1, 1), "M32 runs the conveyor in reverse");
        Run(h, "M31");
        (h.M(912), h.M(913)).Should().Be((1, 0), "M31 runs it forward");
        Run(h, "M33");
        (h.M(912), h.M(913)).Should().Be((0, 0), "M33 stops it");
    }

    [Fact]
    public void A_configured_output_variable_is_the_one_set()
    {
        using var h = new SimHarness();
        LoadLibrary(h, new Prog1000Options { Comments = false, ChipConveyor = "M950" });
        Run(h, "M31");
        h.M(950).Should().Be(1);
        h.M(912).Should().Be(0, "the default output is not used when another is configured");
    }

    private static void LoadLibrary(SimHarness h, Prog1000Options? options = null)
    {
        var text = Prog1000Library.Generate(MachineProfile.Default, options ?? new Prog1000Options { Comments = false });
        h.Download(text.Split("\r\n").Where(l => l.Length > 0).ToArray());
    }

    /// <summary>Runs a move, the code, another move; both moves must have run (the routine neither stops nor skips them). Returns the kinds executed.</summary>
    private static List<MoveKind> Run(SimHarness h, string code)
    {
        var before = h.Sim.ExecutedMoves.Count;
        h.Download("OPEN PROG 1 CLEAR", "LINEAR X1 F600", code, "X2", "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        var ran = h.Sim.ExecutedMoves.Skip(before).ToList();
        ran.Where(m => m.Kind != MoveKind.Dwell).Select(m => m.X.ToString(CultureInfo.InvariantCulture)).Should().Equal("1", "2");
        return ran.Select(m => m.Kind).ToList();
    }
}
