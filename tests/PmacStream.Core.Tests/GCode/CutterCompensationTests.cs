using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.GCode;

/// <summary>
/// G41/G42 computed by the host: the interpreter's block ends are the tool's compensated positions, the host sends
/// exactly those (an outside corner's arc first), and what is not compensated is refused with a named error.
/// </summary>
public class CutterCompensationTests
{
    private static MachineProfile WithRadii(string name, string radii)
    {
        var json = JsonNode.Parse(MachineProfile.Named(name)!.ToJson())!.AsObject();
        json["toolRadii"] = JsonNode.Parse(radii);
        return MachineProfile.Parse(json.ToJsonString(), name + "+radii");
    }

    private static readonly MachineProfile Fanuc = WithRadii("fanuc-mill", """{ "1": 5, "2": 2.5 }""");

    private static List<DecodedBlock> Run(string program, MachineProfile profile)
    {
        var interp = new Interpreter(profile);
        var list = new List<DecodedBlock>();
        foreach (var line in program.Split('\n'))
        {
            if (interp.Step(GCodeReader.LexLine(line, list.Count + 1)) is { } d)
            {
                list.Add(d);
            }
        }

        return list;
    }

    private static List<Diagnostic> Check(string program, MachineProfile profile) => new Checker(profile).CheckText(program).Diagnostics.ToList();

    private static void At(DecodedBlock b, double x, double y, double z)
    {
        b.End.X.Should().BeApproximately(x, 1e-9, $"X of line {b.Line}");
        b.End.Y.Should().BeApproximately(y, 1e-9, $"Y of line {b.Line}");
        b.End.Z.Should().BeApproximately(z, 1e-9, $"Z of line {b.Line}");
    }

    private const string Outside = "G21 G90 G17 G40 G49 G54\nG00 X0 Y-20. Z5.\nG01 Z-1. F500.\nG41 D1 X0 Y0\nY30.\nX40.\nY0\nG91 X-10. Y-5.\nG90 Z-2.\nG40 X0 Y-20.";

    [Fact]
    public void G41_ends_every_straight_move_one_radius_left_of_its_programmed_end_and_counts_incremental_words_from_the_programmed_point()
    {
        var b = Run(Outside, Fanuc);
        At(b[3], -5, 0, -1);   // entry: square to the entry move
        At(b[4], -5, 30, -1);  // straight on: no corner
        At(b[5], 40, 35, -1);  // around the outside corner (0, 30), then along
        At(b[6], 45, 0, -1);
        var n = Math.Sqrt(125);
        At(b[7], 30 + (5 * 5 / n), -5 - (5 * 10 / n), -1); // from the programmed (40, 0), not the tool's (45, 0)
        At(b[8], 30 + (5 * 5 / n), -5 - (5 * 10 / n), -2); // no XY motion: the tool stays beside the programmed point
        At(b[9], 0, -20, -2); // G40: to the programmed point
        b[5].Length.Should().BeApproximately((Math.PI / 2 * 5) + 40, 1e-9, "the corner's quarter circle and the line");
        Check(Outside, Fanuc).Where(d => d.Severity == Severity.Error).Should().BeEmpty();
    }

    [Fact]
    public void G42_is_the_mirror_image_and_a_rapid_goes_straight_to_the_corners_end()
    {
        var b = Run("G21 G90 G17\nG00 X0 Y-20. Z5.\nG01 Z-1. F500.\nG42 D2 X0 Y0\nG00 X-30.\nG01 Y-30.", Fanuc);
        At(b[3], 2.5, 0, -1);
        At(b[4], -30, 2.5, -1);
        At(b[5], -32.5, -30, -1);
        b[4].Length.Should().BeApproximately(Math.Sqrt((2.5 * 2.5) + (2.5 * 2.5)) + 30, 1e-9, "a rapid's corner is a straight way");
    }

    [Fact]
    public void The_host_sends_the_compensated_positions_with_the_outside_corners_arc_about_the_programmed_corner()
    {
        var interp = new Interpreter(Fanuc);
        var host = new HostConversion(interp);
        var sent = new List<string>();
        foreach (var line in Outside.Split('\n'))
        {
            var block = GCodeReader.LexLine(line, 1);
            interp.StepCore(block, null);
            sent.AddRange(host.TakeLines() ?? [line]);
        }

        sent.Should().ContainInOrder("G01 X-5 Y0 Z-1", "G01 X-5 Y30 Z-1", "G02 X0 Y35 I5 J0", "G01 X40 Y35 Z-1", "G02 X45 Y30 I0 J-5", "G01 X45 Y0 Z-1");
        sent.Should().Contain("G91", "the program's distance mode comes back after an incremental block sent absolute");
        sent.Should().NotContain(l => l.Contains("G41", StringComparison.Ordinal), "the controller's own compensation never runs");
    }

    [Fact]
    public void An_arc_keeps_its_centre_and_is_one_radius_larger_outside_and_smaller_inside_after_a_corner_arc_where_it_turns_away()
    {
        // G41: a G02 runs with the cutter outside (radius 15), a G03 inside (radius 5).
        var b = Run("G21 G90 G17\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100\nG02 X20. Y0 I10. J0\nG03 X40. Y0 I10. J0\nG01 X40. Y20.", Fanuc);
        At(b[3], 25, 0, 0);  // tangent on from the entry: no corner; end 15 from the centre (10, 0)
        b[3].Center.Should().Be(new Point3(10, 0, 0));
        b[3].Length.Should().BeApproximately(Math.PI * 15, 1e-9);
        At(b[4], 35, 0, 0);  // tangent on again, the cutter inside the G03: radius 5 about (30, 0)
        At(b[5], 35, 20, 0);
    }

    [Fact]
    public void An_inside_corner_moves_the_end_of_the_move_before_back_to_where_the_offset_paths_cross_and_starts_the_move_there()
    {
        // A pocket, counter-clockwise under G41: every corner is an inside one.
        var interp = new Interpreter(Fanuc);
        var ends = new List<(Point3 End, Point3? Amended)>();
        foreach (var line in "G21 G90 G17\nG00 X50. Y25.\nG41 D1 G01 X50. Y0 F100\nX100.\nY50.\nG03 X0 Y50. R60.\nG01 Y0\nG40 X50. Y25.".Split('\n'))
        {
            if (interp.Step(GCodeReader.LexLine(line, ends.Count + 1)) is { } d)
            {
                ends.Add((d.End, interp.AmendedEnd));
                if (interp.AmendedEnd is { } a)
                {
                    d.Start.Should().Be(a, "the move starts where the offset paths cross");
                }
            }
        }

        ends[2].End.Should().Be(new Point3(55, 0, 0), "the entry ends square to itself until the next move is known");
        ends[3].Amended.Should().Be(new Point3(55, 5, 0), "line to line: the entry's end moves back");
        ends[4].Amended!.Value.X.Should().BeApproximately(95, 1e-9);
        ends[5].Amended!.Value.Y.Should().BeApproximately(48.4565, 1e-4, "line to arc: the offset line meets the arc's offset circle (rs274: 95, 48.4565)");
        ends[6].Amended!.Value.Y.Should().BeApproximately(48.4565, 1e-4, "arc to line");
        ends[7].Amended.Should().BeNull("G40 ends the compensation: no corner");
    }

    [Fact]
    public void The_splitter_holds_a_compensated_move_until_the_next_and_sends_its_end_moved_back()
    {
        using var dir = new TestFolder("comp");
        var src = Path.Combine(dir.Path, "pocket.nc");
        File.WriteAllText(src, "O1\nG21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\nX100.\nY50.\nX0\nY0\nX50.\nG40 X50. Y25.\nM30\n");
        var result = Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(dir.Path, "chunks"), CheckProfile = Fanuc });
        var text = string.Concat(result.ChunkPaths.Select(File.ReadAllText));
        text.Should().ContainAll("X55 Y5 Z-1", "X95 Y5 Z-1", "X95 Y45 Z-1", "X5 Y45 Z-1", "X5 Y5 Z-1");
        text.Should().NotContain("X55 Y0 Z-1", "the entry's end was moved back before it was sent");
    }

    // A pocket under G41 D1 (radius 5), counter-clockwise: Z blocks, a dwell and a coolant code between its XY moves.
    private const string Plunged = "O1\nG21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\nX100.\nZ-2.\nG04 X0.5\nM08\nG00 Z1.\nG01 Z-1.\nY50.\nX0\nG40 X50. Y25.\nM30\n";

    [Fact]
    public void Z_blocks_between_two_compensated_moves_are_queued_behind_the_held_move_and_run_at_the_inside_corners_crossing()
    {
        var interp = new Interpreter(Fanuc);
        var decided = new List<(int Line, CompensationHold Hold, Point3? Amended)>();
        var ends = new CanonEnds();
        interp.Canon = ends;
        var line = 0;
        foreach (var text in Plunged.TrimEnd('\n').Split('\n'))
        {
            if (interp.Execute(GCodeReader.LexLine(text, ++line)))
            {
                decided.Add((line, interp.HoldOfBlock, interp.AmendedEnd));
            }
        }

        ends.Finish();
        decided.Where(d => d.Line is >= 5 and <= 13).Select(d => d.Hold).Should().Equal(
            CompensationHold.Held, CompensationHold.Held, CompensationHold.Queued, CompensationHold.Queued, CompensationHold.Queued,
            CompensationHold.Queued, CompensationHold.Queued, CompensationHold.Held, CompensationHold.Held);
        decided.Single(d => d.Line == 12).Amended.Should().Be(new Point3(95, 5, -1), "Y50 after the Z blocks: the inside corner of X100 and Y50");
        decided.Single(d => d.Line == 14).Hold.Should().Be(CompensationHold.None, "G40 lets everything go");

        // X100 ends at the crossing, and so do the plunge, the rapid retract and the plunge back (each its own Z).
        ends.Ends.Where(e => e.Line is >= 6 and <= 12).Should().Equal(
            (6, new Point3(95, 5, -1)), (7, new Point3(95, 5, -2)), (8, new Point3(95, 5, -2)), (10, new Point3(95, 5, 1)),
            (11, new Point3(95, 5, -1)), (12, new Point3(95, 45, -1)));
        Check(Plunged, Fanuc).Where(d => d.Severity == Severity.Error).Should().BeEmpty("E135 before: the Z blocks are queued now");

        // The splitter sends the same: every held line moved before it is handed over (the chunk boundary too).
        using var dir = new TestFolder("comp");
        var src = Path.Combine(dir.Path, "plunged.nc");
        File.WriteAllText(src, Plunged);
        foreach (var blocks in new[] { 1000, 3, 4 })
        {
            var result = Splitter.Split(src, new SplitOptions { OutDir = Path.Combine(dir.Path, "chunks" + blocks), CheckProfile = Fanuc, BlocksPerChunk = blocks });
            var text = string.Concat(result.ChunkPaths.Select(File.ReadAllText));
            text.Should().ContainAll("X95 Y5 Z-1", "X95 Y5 Z-2", "X95 Y5 Z1", "X95 Y45 Z-1");
            text.Should().NotContain("X100 Y5", "no line before the corner was sent unmoved");
            text.IndexOf("X95 Y5 Z-2", StringComparison.Ordinal).Should().BeLessThan(text.IndexOf("X95 Y5 Z1", StringComparison.Ordinal), "in order");
        }
    }

    [Theory]
    [InlineData(256, false)]
    [InlineData(257, true)]
    public void The_blocks_queued_behind_a_held_move_are_bounded_and_an_inside_corner_beyond_is_refused_naming_the_held_move(int between, bool refused)
    {
        var program = "G21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\nX100.\n" +
            string.Concat(Enumerable.Range(0, between).Select(i => i % 2 == 0 ? "Z-2.\n" : "Z-1.\n")) + "Y50.\nG40 X50. Y25.";
        var diags = Check(program, Fanuc);
        var corner = 6 + between;
        if (refused)
        {
            var e135 = diags.Should().ContainSingle(d => d.Code == DiagnosticCodes.CompensationConcaveCorner).Which;
            e135.Line.Should().Be(corner);
            e135.Message.Should().Contain("line 5").And.Contain("256");
        }
        else
        {
            diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
        }
    }

    /// <summary>The block ends as a consumer holds them under G41/G42 (<see cref="HeldMoves{T}"/>).</summary>
    private sealed class CanonEnds : ICanonicalMoves
    {
        private readonly HeldMoves<(int Line, Point3 End)> _held = new((m, crossing, _) => (m.Line, AmendedMove.MovedTo(m.End, crossing)));
        private readonly List<(int Line, Point3 End)> _block = [];

        public List<(int Line, Point3 End)> Ends { get; } = [];

        public void StartBlock(in CanonStart start) => _block.Clear();

        public void Step(in HostMove step)
        {
        }

        public void Motion(in CanonMotion motion) => _block.Add((motion.Line, motion.End));

        public void EndBlock(in CanonBlock block) => _held.Take(block, _block, Ends);

        public void Finish() => _held.Flush(Ends);
    }

    [Fact]
    public void The_radius_comes_from_G10_L12_and_L13_under_FANUC_and_from_the_spindle_tool_under_RS274NGC()
    {
        var b = Run("G21 G90 G17\nG10 L12 P7 R3.\nG10 L13 P7 R-0.5\nG00 X0 Y-20.\nG41 D7 G01 X0 Y0 F100", Fanuc);
        At(b[^1], -2.5, 0, 0);
        var linuxcnc = WithRadii("linuxcnc-mill", """{ "4": 1.5 }""");
        At(Run("G21 G90 G17\nT4 M6\nG0 X0 Y-20\nG41 G1 X0 Y0 F100", linuxcnc)[^1], -1.5, 0, 0);
        At(Run("G21 G90 G17\nG0 X0 Y-20\nG10 L1 P5 R2\nG42 D5 G1 X0 Y0 F100", linuxcnc)[^1], 2, 0, 0);
    }

    public static TheoryData<string, string, int, int> Refused => new()
    {
        { DiagnosticCodes.NoCutterRadius, "G0 X0 Y-20\nG41 D9 G01 X0 Y0 F100", 2, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G02 X10 Y-10 R10 F100", 2, 8 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG03 X-4 Y4 R4", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG02 I10 J0", 3, 1 },
        { DiagnosticCodes.CompensationConcaveCorner, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG03 X12 Y-2 I6 J-1", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G18\nG0 X0 Y-20\nG41 D1 G01 X0 Y0 F100", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG18", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG42 D1 X10", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nD2 X10", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG81 X5 Y5 Z-1 R1", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG28 X0", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG53 G00 Z0", 3, 1 },
        { DiagnosticCodes.CompensationNotRunnable, "G0 X0 Y-20\nG68 X0 Y0 R30\nG41 D1 G01 X0 Y0 F100", 3, 1 },
        { DiagnosticCodes.CompensationEntryTooShort, "G0 X0 Y-4\nG41 D1 G01 X0 Y0 F100", 2, 8 },
        { DiagnosticCodes.CompensationConcaveCorner, "G0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nG02 X10 Y-10 R10\nG03 X16 Y-4 R6", 4, 1 },
    };

    [Theory]
    [MemberData(nameof(Refused))]
    public void What_the_host_cannot_compensate_is_refused_with_its_code_at_its_block(string code, string program, int line, int column)
    {
        var diags = Check("G21 G90 G17\n" + program, Fanuc);
        diags.Should().Contain(d => d.Code == code && d.Line == line + 1 && d.Column == column,
            "{0} expected at {1}:{2}, got: {3}", code, line + 1, column, string.Join(" | ", diags.Select(d => $"{d.Code}@{d.Line}:{d.Column} {d.Message}")));
    }

    [Fact]
    public void A_start_from_a_block_under_compensation_sends_G40_to_the_controller_whose_positions_are_compensated_already()
    {
        var state = Run("G21 G90 G17\nG00 X0 Y-20.\nG41 D1 G01 X0 Y0 F100", Fanuc)[^1].Modal;
        state.ToPreamble(null, forController: true).Should().Contain("G40").And.NotContain(l => l.Contains("G41", StringComparison.Ordinal));
        state.ToPreamble(null, forController: false).Should().Contain("G41 D1", "a program preamble keeps the program's code");
    }

    [Fact]
    public void A_straight_run_and_outside_corners_check_clean_and_G41_is_no_longer_a_code_the_controller_cannot_run()
    {
        var (summary, diags) = new Checker(Fanuc).CheckText("O1\nG21 G90 G17\nG0 X0 Y-20\nG41 D1 G01 X0 Y0 F100\nY10\nY20\nX10\nG40 X20 Y-20\nM30");
        diags.Should().BeEmpty();
        summary.NotYetCodes.Should().BeEmpty();
    }
}
