using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// G68 rotation, G51 scaling, G51.1 mirror and G61 exact stop in the interpreter: positions computed by hand (machine
/// coordinates, G55 at X100 Y50 Z-10 so that the transformations are shown to come before the work offset).
/// </summary>
public class TransformTests
{
    private static readonly MachineProfile Machine = MachineProfile.Parse(
        MachineProfile.Default.ToJson().Replace("\"workOffsets\": {}", "\"workOffsets\": { \"G55\": [100, 50, -10] }"), "machine");

    private static readonly double Cos30 = Math.Sqrt(3) / 2;

    private static (List<DecodedBlock> Blocks, List<Diagnostic> Diags) Run(string program)
    {
        var interp = new Interpreter(Machine);
        var diags = new List<Diagnostic>();
        var blocks = program.Split('\n').Select((l, i) => interp.Step(GCodeReader.LexLine(l, i + 1), diags)).OfType<DecodedBlock>().ToList();
        return (blocks, diags);
    }

    private static void ShouldBe(Point3 got, double x, double y, double z)
    {
        got.X.Should().BeApproximately(x, 1e-9);
        got.Y.Should().BeApproximately(y, 1e-9);
        got.Z.Should().BeApproximately(z, 1e-9);
    }

    [Fact]
    public void A_square_rotated_30_degrees_about_a_centre()
    {
        // Square 10x10 from (20,10), rotated 30 degrees about (10,10): corner (20,10) -> (10+10cos30, 10+10sin30).
        var (b, d) = Run("G55 G90 G00 X0 Y0 Z0\nG68 X10. Y10. R30.\nG01 X20. Y10. F100.\nY20.\nX10.\nG69\nG01 X0 Y0");
        d.Should().NotContain(x => x.Severity == Severity.Error);
        var moves = b.Where(x => x.Motion != MotionKind.None).Select(x => x.End).ToList();
        ShouldBe(moves[1], 100 + 10 + (10 * Cos30), 50 + 10 + 5, -10);
        // (20,20): from the centre (10,10): rotate -> (10cos30 - 10 sin30, 10 sin30 + 10 cos30)
        ShouldBe(moves[2], 100 + 10 + (10 * Cos30) - 5, 50 + 10 + 5 + (10 * Cos30), -10);
        // (10,20): (0,10) from the centre -> (-5, 10cos30); Y omitted keeps its programmed 20, not the rotated one
        ShouldBe(moves[3], 100 + 10 - 5, 50 + 10 + (10 * Cos30), -10);
        ShouldBe(moves[4], 100, 50, -10);
    }

    [Fact]
    public void An_incremental_move_is_turned_with_the_rotation()
    {
        var (b, _) = Run("G55 G90 G00 X0 Y0 Z0\nG68 X0 Y0 R90.\nG91 G01 X10. F100.\nY5.");
        ShouldBe(b[2].End, 100, 60, -10);
        ShouldBe(b[3].End, 95, 60, -10);
    }

    [Fact]
    public void An_arc_under_rotation_keeps_its_radius_and_turns_its_centre()
    {
        // G02 from (10,0) to (0,-10) about (0,0) with I-10, rotated 90 degrees about the origin: from (0,10) to (10,0),
        // centre (0,0).
        var (b, d) = Run("G55 G90 G00 X10. Y0 Z0\nG68 X0 Y0 R90.\nG00 X10. Y0\nG02 X0 Y-10. I-10. J0 F100.");
        d.Should().NotContain(x => x.Severity == Severity.Error);
        ShouldBe(b[2].End, 100, 60, -10);
        ShouldBe(b[3].End, 110, 50, -10);
        ShouldBe(b[3].Center!.Value, 100, 50, -10);
        b[3].Motion.Should().Be(MotionKind.ArcCw);
        b[3].Length.Should().BeApproximately(Math.PI * 10 / 2, 1e-9);
    }

    [Fact]
    public void Scaling_by_2_about_a_point_and_its_arcs()
    {
        var (b, d) = Run("G55 G90 G00 X0 Y0 Z0\nG51 X10. Y10. P2000\nG01 X20. Y10. F100.\nG03 X10. Y20. R10.\nG50\nG00 X0 Y0");
        d.Should().NotContain(x => x.Severity == Severity.Error);
        ShouldBe(b[2].End, 130, 60, -10);   // 10 + 2*(20-10)
        ShouldBe(b[3].End, 110, 80, -10);
        ShouldBe(b[3].Center!.Value, 110, 60, -10);   // centre (10,10) stays, radius 20
        b[3].Length.Should().BeApproximately(Math.PI * 20 / 2, 1e-9);
        ShouldBe(b[5].End, 100, 50, -10);
        Run("G51 X0 Y0 P2.5\nG01 X2. F100.").Blocks[1].End.X.Should().Be(5, "a decimal P is the factor itself");
    }

    [Fact]
    public void An_arc_under_unequal_scaling_is_refused()
    {
        var (_, d) = Run("G90 G00 X10. Y0\nG51 X0 Y0 I2000 J1000\nG02 X0 Y-10. I-10. J0 F100.");
        d.Should().Contain(x => x.Code == DiagnosticCodes.TransformNotRunnable && x.Line == 3);
    }

    [Fact]
    public void A_mirrored_arc_runs_the_other_way()
    {
        var (b, _) = Run("G90 G00 X10. Y0\nG51.1 X0\nG00 X10. Y0\nG02 X0 Y-10. I-10. J0 F100.");
        ShouldBe(b[2].End, -10, 0, 0);
        ShouldBe(b[3].End, 0, -10, 0);
        b[3].Motion.Should().Be(MotionKind.ArcCcw);
    }

    [Fact]
    public void A_drilling_cycle_under_rotation_drills_at_the_rotated_holes()
    {
        var canon = new CanonRecorder();
        var interp = new Interpreter(Machine) { Canon = canon };
        foreach (var (l, i) in new[] { "G55 G90 G00 X0 Y0 Z10.", "G68 X0 Y0 R90." }.Select((l, i) => (l, i)))
        {
            interp.Step(GCodeReader.LexLine(l, i + 1));
        }

        var hole = interp.Step(GCodeReader.LexLine("G98 G81 X10. Y0 Z-5. R2. F100.", 3))!;
        ShouldBe(hole.End, 100, 60, 0);   // back to the initial level Z10 (machine 0)
        canon.Steps.Where(m => m.Kind == HostMoveKind.Feed).Select(m => m.Target).Should().ContainSingle()
            .Which.Should().Be(new Point3(100, 60, -15));
        var next = interp.Step(GCodeReader.LexLine("Y10.", 4))!;
        ShouldBe(next.End, 90, 60, 0);
    }

    [Fact]
    public void Exact_stop_mode_marks_every_move_until_g64()
    {
        var interp = new Interpreter(Machine);
        var marks = new List<bool>();
        foreach (var l in new[] { "G01 X1. F100.", "G61", "X2.", "G04 P10", "X3.", "G64", "X4.", "G09 X5.", "X6." })
        {
            interp.Step(GCodeReader.LexLine(l, 1));
            marks.Add(interp.ExactStopBlock);
        }

        marks.Should().Equal(false, false, true, false, true, false, false, true, false);
    }
}
