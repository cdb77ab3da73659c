using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>What the host sends instead of the program's own words (issue 17): chunks read back line by line.</summary>
public class HostConversionTests
{
    private static List<string> Body(string program, MachineProfile? profile = null, bool force = false)
    {
        using var tp = new TempProgram(program);
        var o = new SplitOptions { CheckProfile = profile ?? MachineProfile.Default, AllowErrors = force, ProgramTail = "" };
        var r = tp.Split(o);
        return ChunkText.Body(r, o);
    }

    [Fact]
    public void A_data_block_is_never_a_move()
    {
        var body = Body("O1\nG90 G54\nG10 L2 P2 X100. Y50. Z-10.\nG92 X0 Y0\nG52 X5.\nG01 X1. F100.\nM30\n");
        body.Should().Contain("G10 L2 P2 X100 Y50 Z-10").And.Contain("G52 X5");
        body.Where(l => l.Contains("X100", StringComparison.Ordinal) || l.Contains("G92", StringComparison.Ordinal) || l.Contains("G52", StringComparison.Ordinal))
            .Should().OnlyContain(l => !l.StartsWith("M0==", StringComparison.Ordinal), "data settings carry no tracking: nothing moves");
        body.Count(l => l.StartsWith("M0==", StringComparison.Ordinal)).Should().Be(1, "only G01 X1 moves");
        body[0].Should().Be(HostConversion.PowerOnState, "the controller starts in the interpreter's power-on state");
    }

    [Fact]
    public void An_inch_program_is_sent_in_millimetres_and_its_units_codes_are_not_sent()
    {
        var body = Body("O1\nG20 G90 G17\nG01 X1. Y0.5 F10.\nG02 X2. Y0.5 I0.5 J0\nM30\n");
        body.Should().NotContain(l => l.Contains("G20", StringComparison.Ordinal) || l.Contains("G21", StringComparison.Ordinal));
        body.Should().Contain("P500=254").And.Contain("M0==3 G01 X25.4 Y12.7 F(P500)").And.Contain("M0==4 G02 X50.8 Y12.7 I12.7 J0 F(P500)");
    }

    [Fact]
    public void An_R_a_rounding_short_of_half_the_chord_is_sent_as_the_half_circle_on_the_chord()
    {
        // rs274ngc runs R0.99996 over a chord of 2 in as the half circle centred on the chord; a PMAC given the
        // short R would spiral (Isx96), so the host sends the centre.
        var body = Body("O1\nG20 G90 G17\nG01 X0 Y0 F10.\nG02 X2. Y0 R0.99996\nG02 X0 Y0 R1.\nM30\n");
        body.Should().Contain("M0==4 G02 X50.8 Y0 I25.4 J0 F(P500)").And.Contain("M0==5 G02 X0 Y0 R25.4 F(P500)", "an R that reaches is sent as it is");
    }

    [Fact]
    public void Words_a_routine_reads_follow_its_code()
    {
        var body = Body("O1\nT3 M06\nG43 Z50. H3\nG04 X1.5\nM30\n");
        body.Should().Contain(l => l.EndsWith(" M06 T3", StringComparison.Ordinal), "M06 READs the tool; the T word alone would call PROG 1002");
        body.Should().NotContain(l => l.StartsWith('T'));
        var h = body.IndexOf("G43 H3");
        h.Should().BeGreaterThan(0, "READ(H) stops at the first letter it does not read: H goes right after G43");
        body[h + 1].Should().Be("M0==3 Z50 F(P500)");
        body.Should().Contain("M0==4 G04 P1500", "G04 X in seconds is sent as P in the profile's milliseconds");
    }

    [Fact]
    public void A_drilling_cycle_is_sent_as_its_moves_all_carrying_its_line_and_the_mode_comes_back()
    {
        var body = Body("O1\nG90 G00 X0 Y0 Z10.\nG01 Z5. F100.\nG99 G83 X5. Y5. Z-4. R2. Q1.5 F50.\nG80\nX1.\nM30\n");
        var cycle = body.Where(l => l.StartsWith("M0==4 ", StringComparison.Ordinal)).ToList();
        cycle.Should().HaveCountGreaterThan(8, "three pecks, each back to R and down again");
        cycle.Select(l => l.Split(' ').Last(w => w.StartsWith('Z'))).Last().Should().Be("Z2", "G99: back to R");
        body.Should().Contain("P500=50");
        var after = body.LastIndexOf(cycle[^1]) + 1;
        body[after].Should().Be("G01", "the program's G01 is in force again after the cycle's G00 moves");
        body.Should().NotContain(l => l.Contains("G83", StringComparison.Ordinal) || l.Contains("G80", StringComparison.Ordinal));
    }

    [Fact]
    public void A_reference_return_goes_through_its_point_and_to_the_reference_in_machine_coordinates()
    {
        var body = Body("O1\nG90 G00 X10. Y10. Z10.\nG91 G28 Z0\nG90 X0\nM30\n");
        var i = body.IndexOf("G90");
        // Only Z moves, through the intermediate point: X and Y stay wherever the machine is (at a program's first G28
        // the host does not know where that is, so naming them would move them).
        body.Skip(i).Take(5).Should().Equal("G90", "M0==3 G00 Z10 F(P500)", "M0==3 G53 G00 Z0 F(P500)", HostConversion.BackFromMachineCoordinates, "G91");
        Body("O1\nG91 G28 Z0\nM30\n").Should().Contain("M0==2 G00 Z0 F(P500)").And.NotContain(l => l.Contains('X') || l.Contains('Y'));
    }

    [Fact]
    public void A_block_block_delete_leaves_out_does_not_move_the_position_the_host_computes_from()
    {
        // The deleted G00 X50. never runs: G92 X0 makes the tool's X (10) the new zero, not 50.
        const string program = "O1\nG00 X10. Y0 Z5.\n/G00 X50.\nG92 X0\nG00 X10.\nM30\n";
        Body(program).Should().Contain("G92 X10").And.NotContain(l => l.Contains("X50", StringComparison.Ordinal));
        Body(program, force: true).Should().Contain("G92 X10");
    }

    [Fact]
    public void Feed_per_revolution_goes_as_feed_per_minute_at_the_spindle_speed_in_force_on_every_move()
    {
        // 0.2 mm/rev at 1000 rpm is 200 mm/min; after S2000 the same F is 400 mm/min. Raw, F0.2 would run at 0.2 mm/min.
        var body = Body("O1\nG21 G90 G00 X0 Y0 Z5.\nG95 S1000 M03\nG01 X10. F0.2\nX20.\nS2000\nX30.\nG94 F300\nX40.\nM30\n");
        body.SkipWhile(l => l != "M03").Skip(1).Take(6).Should().Equal(
            "P500=200", "M0==4 G01 X10 F(P500)", "M0==5 X20 F(P500)", "S2000", "P500=400", "M0==7 X30 F(P500)");
        body.Should().Contain("P500=300").And.NotContain("P500=0.2", "no per-revolution feed reaches the controller");
    }

    [Fact]
    public void Forced_splits_convert_as_checked_ones_do()
    {
        const string program = "O1\nG20 G90\nG01 X1. F10.\nG81 X2. Z-0.1 R0.1\nG80\nM30\n";
        Body(program, force: true).Should().Equal(Body(program));
    }

    [Fact]
    public void Exact_stop_sends_g09_after_every_move_until_g64()
    {
        var body = Body("O1\nG90 G01 X1. F100.\nG61\nX2.\nY2.\nG64\nX3.\nG09 Y3.\nM30\n");
        body.Should().NotContain(l => l.Contains("G61", StringComparison.Ordinal));
        var i = body.IndexOf("M0==4 X2 F(P500)");
        i.Should().BeGreaterThan(0);
        body[i + 1].Should().Be("G09", "the library's DWELL0 after the move: it ends at rest");
        body[i + 2].Should().Be("M0==5 Y2 F(P500)");
        body[i + 3].Should().Be("G09");
        var g64 = body.IndexOf("M0==7 X3. F(P500)");
        body[g64 + 1].Should().Be("M0==8 Y3 F(P500)", "G64 blends again; G09 of line 8 goes after its move, not before it");
        body[g64 + 2].Should().Be("G09");
    }

    [Fact]
    public void Moves_under_rotation_and_scaling_are_sent_as_the_positions_they_reach()
    {
        var body = Body("O1\nG90 G00 X0 Y0 Z0\nG68 X0 Y0 R90.\nG01 X10. Y0 F100.\nG91 X5.\nG90 G02 X0 Y-15. I-15. J0\nG69\nG51 X0 Y0 P2000\nG01 X1. Y1.\nG50\nX0 Y0\nM30\n");
        body.Should().NotContain(l => l.Contains("G68", StringComparison.Ordinal) || l.Contains("G69", StringComparison.Ordinal) ||
            l.Contains("G51", StringComparison.Ordinal) || l.Contains("G50", StringComparison.Ordinal));
        body.Should().Contain("M0==4 G01 X0 Y10 Z0 F(P500)");
        var inc = body.IndexOf("M0==5 G01 X0 Y15 Z0 F(P500)");
        inc.Should().BeGreaterThan(0, "an incremental move is sent absolute, turned");
        body[inc - 1].Should().Be("G90");
        body[inc + 1].Should().Be("G91");
        body.Should().Contain("M0==6 G02 X15 Y0 Z0 I0 J-15 F(P500)", "the arc from (0,15) about the origin, rotated: the centre vector is turned too");
        body.Should().Contain("M0==9 G01 X2 Y2 Z0 F(P500)");
        body.Should().Contain("M0==11 X0 Y0 F(P500)", "after G50 the block goes as written");
    }

    [Fact]
    public void Inverse_time_feeds_are_sent_per_minute_from_each_move_length()
    {
        var body = Body("O1\nG90 G00 X0 Y0 Z0\nG93 G01 X30. Y40. F2.\nG02 X40. Y30. I0 J-10. F1.\nG94 G01 X0 F500.\nM30\n");
        body.Should().NotContain(l => l.Contains("G93", StringComparison.Ordinal));
        body.Should().Contain("P500=100", "50 mm in half a minute");
        body.Should().Contain("P500=" + HostConversion.Num(Math.PI * 10 / 2), "a quarter circle of radius 10 in one minute: along the arc, not the chord");
        body.Should().Contain("P500=500.");
    }
}
