using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>Where the tool ends after the codes paper-24g7m's set does not have: cycles, reference returns, machine coordinates, offsets.</summary>
public class CycleAndOffsetTests
{
    private static List<DecodedBlock> Run(string program, string profile = MachineProfile.DefaultName, List<Diagnostic>? diags = null)
    {
        var interp = new Interpreter(MachineProfile.Named(profile)!);
        var n = 0;
        return program.Split('\n').Select(l => interp.Step(GCodeReader.LexLine(l, ++n), diags)).OfType<DecodedBlock>().ToList();
    }

    [Fact]
    public void Drilling_cycles_drill_each_positioning_block_and_return_to_r_or_the_initial_level()
    {
        var b = Run("G00 X0 Y0 Z10\nG99 G81 X5 Y5 Z-3 R2 F100\nX10\nG98 Y10\nG80\nX0");
        b[1].Motion.Should().Be(MotionKind.Cycle);
        b[1].End.Should().Be(new Point3(5, 5, 2), "G99 returns to the R level");
        b[2].End.Should().Be(new Point3(10, 5, 2), "Z and R stay in force: the next block is another hole");
        b[3].End.Should().Be(new Point3(10, 10, 10), "G98 returns to the level the tool had when the cycle began");
        b[1].DurationSeconds.Should().BeGreaterThan(5.0 / 100 * 60, "5 mm at F100 into the hole, plus the rapids");
        b[5].Motion.Should().Be(MotionKind.Rapid, "after G80 a positioning block moves in the motion mode again");
        b[5].End.Should().Be(new Point3(0, 10, 10));
        b[1].Modal.Cycle.Should().Be(81);
        b[4].Modal.Cycle.Should().BeNull();
    }

    [Fact]
    public void A_motion_code_ends_a_cycle_and_incremental_repeats_step_along_the_row()
    {
        var b = Run("G00 X0 Y0 Z10\nG91 G99 G81 X10 Z-5 R-8 K3 F100\nG90 G00 X0");
        b[1].End.Should().Be(new Point3(30, 0, 2), "three holes 10 apart; R is 8 below the initial level");
        b[2].Motion.Should().Be(MotionKind.Rapid);
        b[2].Modal.Cycle.Should().BeNull("a group 01 code cancels the cycle (FANUC)");
        b[2].Modal.GI.Should().Be(80);
    }

    [Fact]
    public void LinuxCNC_cycles_are_in_the_motion_group_and_G80_leaves_no_motion_mode()
    {
        var diags = new List<Diagnostic>();
        var b = Run("G0 X0 Y0 Z10\nG81 X1 Y1 Z-1 R2 F50\nG80\nX5", "linuxcnc-mill", diags);
        b[1].End.Should().Be(new Point3(1, 1, 10), "LinuxCNC starts in G98");
        b[1].Modal.GA.Should().Be(81);
        diags.Should().ContainSingle(d => d.Code == DiagnosticCodes.NoMotionMode && d.Line == 4);
    }

    [Fact]
    public void Reference_returns_pass_the_point_and_end_at_the_reference_position()
    {
        var json = MachineProfile.Default.ToJson().Replace("\"referencePositions\": {}", "\"referencePositions\": { \"G28\": [0, 0, 100], \"G30\": [-50, 0, 80] }");
        var profile = MachineProfile.Parse(json);
        var interp = new Interpreter(profile);
        var n = 0;
        var b = "G00 X10 Y20 Z5\nG28 G91 Z0\nG90 G30 X10".Split('\n').Select(l => interp.Step(GCodeReader.LexLine(l, ++n))).OfType<DecodedBlock>().ToList();
        b[1].End.Should().Be(new Point3(10, 20, 100), "only the axes named go home");
        b[1].Motion.Should().Be(MotionKind.Rapid);
        b[2].End.Should().Be(new Point3(-50, 20, 100));
        b[2].Length.Should().BeApproximately(60, 1e-9, "0 to the point X10, then 60 to the second reference");
    }

    [Fact]
    public void G53_moves_in_machine_coordinates_for_its_block_only()
    {
        var json = MachineProfile.Default.ToJson().Replace("\"workOffsets\": {}", "\"workOffsets\": { \"G54\": [100, 0, -50] }");
        var interp = new Interpreter(MachineProfile.Parse(json));
        var n = 0;
        var b = "G00 X0 Z0\nG53 Z0\nZ1".Split('\n').Select(l => interp.Step(GCodeReader.LexLine(l, ++n))).OfType<DecodedBlock>().ToList();
        b[0].End.Should().Be(new Point3(100, 0, -50));
        b[1].End.Should().Be(new Point3(100, 0, 0), "machine Z0");
        b[2].End.Should().Be(new Point3(100, 0, -49), "the work offset applies again");
    }

    [Fact]
    public void G92_G52_and_G10_move_the_coordinates_not_the_tool()
    {
        var b = Run("G00 X10 Y10\nG92 X0 Y0\nG00 X5\nG92.1\nX5\nG52 X100\nX0\nG52 X0\nG10 L2 P1 X1000\nX0");
        b[1].Motion.Should().Be(MotionKind.None);
        b[1].End.Should().Be(new Point3(10, 10, 0));
        b[2].End.Should().Be(new Point3(15, 10, 0), "after G92 X0 at X10, X5 is machine 15");
        b[4].End.Should().Be(new Point3(5, 10, 0));
        b[6].End.Should().Be(new Point3(100, 10, 0));
        b[9].End.Should().Be(new Point3(1000, 10, 0), "G10 L2 P1 set G54's offset");
    }

    [Fact]
    public void G10_L20_sets_extended_offsets_in_FANUC_and_the_offset_that_makes_here_read_as_the_values_in_grbl()
    {
        var fanuc = Run("G00 X10\nG10 L20 P1 X500\nX0\nG54.1 P1\nX0");
        fanuc[2].End.X.Should().Be(0, "FANUC's L20 is the extended offset P1, not G54");
        fanuc[4].End.X.Should().Be(500);

        var grbl = Run("G0 X10\nG10 L20 P1 X0\nX5", "grbl");
        grbl[2].End.X.Should().Be(15, "X10 now reads as X0 in G54");
    }

    [Fact]
    public void Absolute_arc_centres_with_G90_1_check_without_radius_errors()
    {
        var diags = new List<Diagnostic>();
        var b = Run("G00 X10 Y0\nG90.1 G03 X0 Y10 I0 J0 F100", diags: diags);
        diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
        b[1].Center.Should().Be(new Point3(0, 0, 0));
        Run("G00 X10 Y0\nG03 X0 Y10 I0 J0 F100", diags: diags);
        diags.Should().Contain(d => d.Code == DiagnosticCodes.ArcRadiusMismatch, "the same words are an error as incremental centres");
    }

    [Fact]
    public void Inverse_time_feed_wants_f_on_every_move_and_takes_a_minute_over_f()
    {
        var diags = new List<Diagnostic>();
        var b = Run("G93 G01 X10 F2\nX20", diags: diags);
        b[0].DurationSeconds.Should().Be(30);
        diags.Should().ContainSingle(d => d.Code == DiagnosticCodes.FeedMoveWithoutFeed && d.Line == 2);
    }

    [Fact]
    public void Every_state_reads_the_same_meaning_from_its_codes_in_every_profile()
    {
        foreach (var name in MachineProfile.BuiltInNames)
        {
            var profile = MachineProfile.Named(name)!;
            var b = Run(name == "grbl" ? "G20 G18 G91 M4 M8 S100\nG1 X1 F10" : "G20 G18 G91 M04 M08 S100\nG01 X1 F10", name);
            var s = b[^1].Modal;
            (s.Units, s.Plane, s.Absolute, s.Spindle, s.Coolant, s.Motion).Should().Be((LengthUnits.Inches, 18, false, 4, 8, (double?)1), name);
            s.G.Count.Should().Be(profile.GGroups.Count);
            s.M.Count.Should().Be(profile.MGroups.Count);
        }
    }
}
