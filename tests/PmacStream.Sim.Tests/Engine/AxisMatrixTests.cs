namespace PmacStream.Sim.Tests.Engine;

/// <summary>The axis transformation matrix the library's offsets live in, and indirect variables (issue 17).</summary>
public class AxisMatrixTests
{
    [Fact]
    public void Adis_renames_the_position_and_later_moves_reach_program_position_plus_displacement()
    {
        using var h = new SimHarness();
        h.Ok("DEFINE TBUF 1");
        h.Download("OPEN PROG 1 CLEAR", "LINEAR ABS F6000 X10 Y10 Z0",
            "Q34=100 Q35=50 Q36=-10 TSEL1 ADIS34", "X0 Y0 Z0", "INC X5", "ABS Q34=0 Q35=0 Q36=0 ADIS34", "X0 Y0 Z0", "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        h.Sim.ExecutedMoves.Select(m => (m.X, m.Y, m.Z)).Should().Equal(
            (10.0, 10.0, 0.0), (100.0, 50.0, -10.0), (105.0, 50.0, -10.0), (0.0, 0.0, 0.0));
    }

    [Fact]
    public void A_new_define_tbuf_resets_the_matrix_a_coordinate_system_already_selected()
    {
        using var h = new SimHarness();
        h.Ok("DEFINE TBUF 1");
        h.Download("OPEN PROG 1 CLEAR", "LINEAR ABS F6000 Q34=100 Q35=50 Q36=-10 TSEL1 ADIS34", "X0 Y0 Z0", "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));

        // The library loaded again: DEFINE TBUF makes every matrix the identity, the one selected too.
        h.Ok("DEFINE TBUF 1");
        h.Download("OPEN PROG 2 CLEAR", "LINEAR ABS F6000 X1 Y1 Z1", "CLOSE");
        h.Ok("&1 B2 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        h.Sim.ExecutedMoves.Select(m => (m.X, m.Y, m.Z)).Should().Equal((100.0, 50.0, -10.0), (1.0, 1.0, 1.0));
    }

    [Fact]
    public void Tsel_of_a_matrix_tbuf_did_not_reserve_stops_the_program_and_arot_is_refused_not_ignored()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 1 CLEAR", "TSEL3 X1", "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        h.Sim.ExecutedMoves.Should().BeEmpty();
        h.Ok("DEFINE TBUF 1");
        h.Download("OPEN PROG 2 CLEAR", "TSEL1 AROT40 X1", "CLOSE");
        h.Ok("&1 B2 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        h.Sim.ExecutedMoves.Should().BeEmpty("rotation is not simulated: the program stops rather than run unrotated");
    }

    [Fact]
    public void Variables_numbered_by_an_expression_are_read_and_written()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 1 CLEAR", "Q20=2 P(7100+Q20*3)=12.5 P(7101+Q20*3)=P(7106)+1", "CLOSE");
        h.Ok("&1 B1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        h.Sim.ReadVariable('P', 7106).Should().Be(12.5);
        h.Sim.ReadVariable('P', 7107).Should().Be(13.5);
    }
}
