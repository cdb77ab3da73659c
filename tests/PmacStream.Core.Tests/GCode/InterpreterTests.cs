using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

public class InterpreterTests
{
    private static List<DecodedBlock> Run(string program, MachineProfile? profile = null)
    {
        var interp = new Interpreter(profile ?? MachineProfile.Default);
        var result = new List<DecodedBlock>();
        var n = 0;
        foreach (var line in program.Split('\n'))
        {
            if (interp.Step(GCodeReader.LexLine(line, ++n)) is { } b)
            {
                result.Add(b);
            }
        }

        return result;
    }

    [Fact]
    public void Power_on_state_comes_from_the_profile_startup_codes()
    {
        var s = new Interpreter(MachineProfile.Paper).State;
        (s.GA, s.GB, s.GC, s.GD, s.GE, s.GF, s.GH).Should().Be((0.0, 21.0, 90.0, 54.0, 17.0, 49.0, 40.0));
        (s.GG, s.GI, s.MA, s.MB, s.MC).Should().Be(((double?)null, (double?)null, (double?)null, 5.0, 9.0));
        s.G.Should().HaveCount(9);
        s.Feed.Should().BeNull();
        s.Units.Should().Be(LengthUnits.Millimetres);

        // fanuc-mill orders its first nine groups as paper-24g7m's columns mean them; GI holds the canned cycle group.
        var f = new Interpreter(MachineProfile.Default).State;
        (f.GA, f.GB, f.GC, f.GD, f.GE, f.GF, f.GG, f.GH, f.GI).Should().Be((0.0, 21.0, 90.0, 54.0, 17.0, 49.0, (double?)null, 40.0, 80.0));
        f.G.Should().HaveCount(MachineProfile.Default.GGroups.Count).And.Contain([94.0, 98.0, 64.0, 91.1]);
        (f.MA, f.MB, f.MC, f.Spindle, f.Coolant, f.Motion, f.Cycle).Should().Be(((double?)null, 5.0, 9.0, 5, 9, 0.0, (double?)null));
    }

    [Fact]
    public void Linear_moves_track_absolute_incremental_and_time_at_feed()
    {
        var b = Run("G01 X30 Y40 F600\nG91 X-10\nG90 Z-5");
        b[0].Motion.Should().Be(MotionKind.Linear);
        b[0].End.Should().Be(new Point3(30, 40, 0));
        b[0].Length.Should().BeApproximately(50, 1e-9);
        b[0].DurationSeconds.Should().BeApproximately(5, 1e-9);
        b[1].End.Should().Be(new Point3(20, 40, 0));
        b[1].Modal.Absolute.Should().BeFalse();
        b[2].End.Should().Be(new Point3(20, 40, -5));
        b[2].Start.Should().Be(b[1].End);
    }

    [Fact]
    public void Rapids_use_the_profile_rate_and_null_for_empty_lines()
    {
        var b = Run("(comment)\n\nO1234\n%\nG00 X150");
        b.Should().ContainSingle();
        b[0].Line.Should().Be(5);
        b[0].Motion.Should().Be(MotionKind.Rapid);
        b[0].DurationSeconds.Should().BeApproximately(150 / MachineProfile.Default.RapidRate * 60, 1e-9);
    }

    [Fact]
    public void Arcs_ijk_and_r_forms_give_centre_direction_and_length()
    {
        var b = Run("G01 X10 Y0 F100\nG03 X0 Y10 I-10 J0\nG02 X10 Y0 R10\nG02 X-10 Y0 R-10\nG03 X-10 Y0 I10");
        b[1].Motion.Should().Be(MotionKind.ArcCcw);
        b[1].Center.Should().Be(new Point3(0, 0, 0));
        b[1].Length.Should().BeApproximately(Math.PI * 5, 1e-9);
        b[2].Motion.Should().Be(MotionKind.ArcCw);
        b[2].Center!.Value.X.Should().BeApproximately(0, 1e-9);
        b[2].Center!.Value.Y.Should().BeApproximately(0, 1e-9);
        b[2].Length.Should().BeApproximately(Math.PI * 5, 1e-9);
        b[3].Length.Should().BeApproximately(Math.PI * 10, 1e-9);   // R-10 from (10,0) to (-10,0): half circle
        b[4].Length.Should().BeApproximately(Math.PI * 20, 1e-9);   // no axis words, I/J: full circle
        b[4].End.Should().Be(b[4].Start);
    }

    [Fact]
    public void Helix_and_other_planes()
    {
        var b = Run("G01 X10 Y0 Z0 F100\nG03 X-10 Y0 Z-2 I-10 J0\nG18\nG02 X-20 Z8 I-10 K0");
        b[1].Length.Should().BeApproximately(Math.Sqrt(Math.Pow(Math.PI * 10, 2) + 4), 1e-9);
        b[3].Modal.Plane.Should().Be(18);
        b[3].Center.Should().Be(new Point3(-20, 0, -2));
        b[3].Length.Should().BeApproximately(Math.PI * 5, 1e-9);     // CW quarter in ZX seen from +Y
    }

    [Fact]
    public void Dwell_is_in_milliseconds_for_p_and_seconds_for_x()
    {
        var b = Run("G04 P1500\nG04 X2.5");
        b[0].Motion.Should().Be(MotionKind.Dwell);
        b[0].DurationSeconds.Should().Be(1.5);
        b[0].Modal.GG.Should().Be(4);
        b[1].DurationSeconds.Should().Be(2.5);
        b[1].End.Should().Be(b[1].Start);
    }

    [Theory]
    [InlineData("G20\nG04 X2.", 2.0)]       // X of G04 is seconds in any units: not 50.8 s
    [InlineData("G20\nG04 P2000", 2.0)]     // P in milliseconds (FANUC), unscaled too
    [InlineData("G21\nG04 X2.", 2.0)]
    public void A_dwell_in_an_inch_program_is_seconds_not_a_length(string program, double seconds)
    {
        var b = Run(program);
        b[1].Motion.Should().Be(MotionKind.Dwell);
        b[1].DurationSeconds.Should().Be(seconds);
    }

    [Fact]
    public void Non_modal_groups_hold_only_on_their_block()
    {
        var b = Run("G04 P1\nG09 G01 X1 F100\nM30\nM05", MachineProfile.Paper);
        b[0].Modal.GG.Should().Be(4);
        b[1].Modal.GG.Should().BeNull();
        b[1].Modal.GI.Should().Be(9);
        b[2].Modal.GI.Should().BeNull();
        b[2].Modal.MA.Should().Be(30);
        b[3].Modal.MA.Should().BeNull();
    }

    [Fact]
    public void Work_offsets_from_the_profile_shift_absolute_positions()
    {
        var json = MachineProfile.Default.ToJson().Replace("\"workOffsets\": {}", "\"workOffsets\": { \"G55\": [100, 50, -10] }");
        var profile = MachineProfile.Parse(json);
        var b = Run("G55 G00 X1 Y2 Z3\nG54 X1", profile);
        b[0].End.Should().Be(new Point3(101, 52, -7));
        b[0].Modal.WorkOffset.Should().Be(55);
        b[1].End.Should().Be(new Point3(1, 52, -7));
    }

    [Fact]
    public void Modal_state_records_tool_spindle_coolant_and_words()
    {
        var b = Run("T3 S6000 M03\nM08 G43 H3\nG41 D3");
        var s = b[2].Modal;
        (s.Tool, s.Spindle, s.SpindleSpeed, s.Coolant, s.LengthOffset, s.CutterComp).Should().Be((3, 3, 6000.0, 8, 3, 3));
        (s.GF, s.GH, s.MB, s.MC).Should().Be((43.0, 41.0, 3.0, 8.0));
        b[0].T.Should().Be(3);
        b[0].S.Should().Be(6000);
        b[1].H.Should().Be(3);
    }

    [Fact]
    public void Unchanged_state_is_shared_between_blocks()
    {
        var b = Run("G01 X1 F100\nX2\nX3");
        b[1].Modal.Should().BeSameAs(b[2].Modal);
    }

    [Fact]
    public void Resuming_from_any_block_with_its_prior_state_gives_the_same_blocks()
    {
        var text = File.ReadAllText(RepoRoot.DemoProgram);
        var lines = text.Replace("\r\n", "\n").Split('\n');
        var full = Run(string.Join('\n', lines));
        foreach (var k in new[] { 5, 40, 777, 2000, full.Count - 3 })
        {
            var prior = full[k - 1];
            var resumed = new Interpreter(MachineProfile.Default, prior.Modal, prior.End);
            for (var i = k; i < Math.Min(k + 50, full.Count); i++)
            {
                var block = resumed.Step(GCodeReader.LexLine(lines[full[i].Line - 1], full[i].Line));
                block.Should().Be(full[i] with { ByteOffset = 0 });
            }
        }
    }

    [Fact]
    public void Preamble_restores_the_modal_state_on_a_fresh_interpreter()
    {
        var b = Run("G20 G18 G91 G56 T4 S1200 M04 M08 G43 H4 G01 X1 F33.5");
        var target = b[0].Modal;
        var program = target.ToPreamble(new Point3(1, 2, 3));
        program.Should().Contain("G90 G00 X1 Y2");
        var fresh = Run(string.Join('\n', program));
        var s = fresh[^1].Modal;
        s.Should().Be(target);
        // Positions are millimetres: the preamble's X1 Y2 Z3 are inches (G20 is restored first).
        var end = fresh.Single(x => x.Motion == MotionKind.Rapid && x.Z.HasValue).End;
        (end.X, end.Y, end.Z).Should().Be((25.4, 50.8, 3 * 25.4));
    }
}
