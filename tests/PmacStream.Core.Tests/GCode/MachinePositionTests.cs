using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>The interpreter's positions are machine coordinates in millimetres: offsets, units and tool length applied (issue 17).</summary>
public class MachinePositionTests
{
    private static readonly MachineProfile Machine = MachineProfile.Parse(
        MachineProfile.Default.ToJson().Replace("\"workOffsets\": {}", "\"workOffsets\": { \"G55\": [100, 50, -10] }, \"toolLengths\": { \"1\": 50, \"2\": 75.5 }"),
        "machine");

    private static List<DecodedBlock> Run(string program)
    {
        var interp = new Interpreter(Machine);
        return program.Split('\n').Select((l, i) => interp.Step(GCodeReader.LexLine(l, i + 1))).OfType<DecodedBlock>().ToList();
    }

    [Fact]
    public void Inch_values_become_millimetres()
    {
        var b = Run("G20 G90 G01 X1. Y2. F10.\nG91 X0.5");
        b[0].End.Should().Be(new Point3(25.4, 50.8, 0));
        b[1].End.X.Should().BeApproximately(38.1, 1e-9);
        b[0].X.Should().Be(1.0, "the block's words stay as written");
        b[0].DurationSeconds.Should().BeApproximately(Math.Sqrt(5) * 25.4 / 254 * 60, 1e-9, "10 in/min is 254 mm/min");
    }

    [Fact]
    public void Tool_length_and_work_offset_add_up_on_z()
    {
        var b = Run("G90 G55 G00 X0 Y0 Z0\nG43 H1 Z0\nG44 H2 Z0\nG49 Z0\nG10 L10 P1 R60.\nG43 H1 Z0");
        b.Where(x => x.Motion != MotionKind.None).Select(x => x.End.Z).Should().Equal(-10, 40, -85.5, -10, 50);
        b[0].End.X.Should().Be(100);
    }

    [Fact]
    public void G92_and_g10_l20_from_the_position_use_the_tool_length_in_force()
    {
        var b = Run("G90 G43 H1 G00 Z10.\nG92 Z0\nZ5.");
        b[^1].End.Z.Should().Be(65, "machine Z 60 read as 0: Z5 is machine 65");
    }

    [Fact]
    public void A_peck_cycle_writes_out_every_step()
    {
        var canon = new CanonRecorder();
        var interp = new Interpreter(Machine) { Canon = canon };
        interp.Step(GCodeReader.LexLine("G90 G00 X0 Y0 Z10.", 1));
        interp.Step(GCodeReader.LexLine("G98 G73 X1. Y1. Z-3. R1. Q1. F100.", 2))!.End.Should().Be(new Point3(1, 1, 10));
        var steps = canon.Steps;
        steps.Count(s => s.Kind == HostMoveKind.Feed).Should().Be(4, "R1 to Z-3 in pecks of 1");
        steps.Last().Target.Z.Should().Be(10, "G98: back to the initial level");
    }
}
