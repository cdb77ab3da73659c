using PmacStream.GCode;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Out-of-plane blocks between two compensated XY moves (issue 27 item 4): a plunge, a retract, a rapid, a dwell, a
/// coolant code after a move whose end the next XY move decides. rs274ngc queues them behind the held move and runs
/// them at the corner's crossing (<c>move_endpoint_and_flush</c>); the interpreter decides the same
/// (<see cref="CanonBlock.Hold"/>), and every block end it reports lies on rs274's moves, in order.
/// </summary>
public partial class Rs274ComparisonTests
{
    /// <summary>
    /// Contours with Z blocks between every pair of XY moves: pockets cut inside (every corner an inside one) and
    /// contours cut outside (every corner an outside one), G41 and G42, lines and arcs (R and I/J) before and after the
    /// Z blocks, metric and inch; the cutter radius is tool 4's (5 mm) by D.
    /// </summary>
    public static TheoryData<string, string> PlungedContours => new()
    {
        {
            "inside G41 arcs metric",
            "G21\nG0 X50 Y25 Z5\nG1 Z-2 F300\nG41 D4 X100 Y25\nZ-3\nY50\nG0 Z1\nG1 Z-2\nG3 X0 Y50 R60\nG4 P0.1\nG1 Z-2.5\nY0\nZ-3\n" +
            "G2 X50 Y0 R40\nG1 Z-2\nG2 X100 Y0 I25 J-31.225\nM8\nG1 Z-3\nY25\nG40 X50 Y25\nG0 Z5"
        },
        {
            "inside G42 arcs metric",
            "G21\nG0 X50 Y25 Z5\nG1 Z-2 F300\nG42 D4 X0 Y25\nZ-3\nY50\nG0 Z1\nG1 Z-2\nG2 X100 Y50 R60\nG1 Z-2.5\nY0\nZ-3\n" +
            "G3 X50 Y0 R40\nG1 Z-2\nG3 X0 Y0 I-25 J-31.225\nG1 Z-3\nY25\nG40 X50 Y25\nG0 Z5"
        },
        {
            "inside G41 rectangle, the entry's end moved with its plunge",
            "G21\nG0 X50 Y25 Z5\nG1 Z-2 F300\nG41 D4 X50 Y0\nZ-3\nX100\nZ-2\nY50\nZ-3\nZ-2.5\nX0\nZ-2\nY0\nZ-3\nX50\nG40 X50 Y25\nG0 Z5"
        },
        {
            "outside G41 with an arc metric",
            "G21\nG0 X50 Y70 Z5\nG1 Z-2 F300\nG41 D4 X50 Y50\nX100\nZ-3\nY0\nG0 Z1\nG1 Z-2\nX0\nZ-3\nG2 X0 Y50 R25\nG1 Z-2\nX50\nG40 X50 Y70\nG0 Z5"
        },
        {
            "outside G42 with an arc metric",
            "G21\nG0 X50 Y70 Z5\nG1 Z-2 F300\nG42 D4 X50 Y50\nX0\nZ-3\nY0\nG0 Z1\nG1 Z-2\nX100\nZ-3\nG3 X100 Y50 R25\nG1 Z-2\nX50\nG40 X50 Y70\nG0 Z5"
        },
        {
            "inside G41 arcs inch",
            "G20\nG0 X2 Y1 Z0.2\nG1 Z-0.08 F12\nG41 D4 X4 Y1\nZ-0.12\nY2\nG0 Z0.04\nG1 Z-0.08\nG3 X0 Y2 R2.4\nG4 P0.1\nG1 Z-0.1\nY0\nZ-0.12\n" +
            "G2 X2 Y0 R1.6\nG1 Z-0.08\nG2 X4 Y0 I1 J-1.249\nG1 Z-0.12\nY1\nG40 X2 Y1\nG0 Z0.2"
        },
        {
            "outside G42 inch",
            "G20\nG0 X2 Y2.8 Z0.2\nG1 Z-0.08 F12\nG42 D4 X2 Y2\nX0\nZ-0.12\nY0\nG0 Z0.04\nG1 Z-0.08\nX4\nZ-0.12\nG3 X4 Y2 R1\nG1 Z-0.08\nX2\nG40 X2 Y2.8\nG0 Z0.2"
        },
    };

    [SkippableTheory]
    [MemberData(nameof(PlungedContours))]
    public void Rs274_passes_through_every_block_end_of_a_contour_with_Z_blocks_between_its_compensated_moves(string name, string contour)
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274");
        var program = $"G90 G17 G94 G40 G49 G54 G21\nG10 L2 P1 X10.5 Y20.25 Z-30\n{contour}\nM2";
        var path = Path.Combine(temp.Path, "plunged.ngc");
        File.WriteAllText(path, program + "\n");
        var profile = Machine();
        new Checker(profile).CheckText(program).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty(name + " (E135 before issue 27 item 4 for the inside corners)");
        var (accepted, why) = Compare(rs274, path, profile, temp.Path);
        accepted.Should().BeTrue(why);
        output.WriteLine($"{name}: {why}");

        // Every Z block runs at the held move's end as the corner decides it: where an inside corner moved that end,
        // the Z blocks as reported before the next XY move was known are off rs274's path.
        var provisional = CanonBlockEnds.Of(path, profile, amend: false);
        var amended = CanonBlockEnds.Of(path, profile);
        amended.Should().HaveCount(provisional.Count);
        var lines = program.Split('\n');
        bool ZBlock(int line) => lines[line - 1].TrimStart().StartsWith('Z') || lines[line - 1].Contains(" Z", StringComparison.Ordinal);
        var moved = provisional.Zip(amended).Where(p => Distance(p.First.End, p.Second.End) > 0.01).Select(p => p.First.Line).ToList();
        if (name.StartsWith("inside", StringComparison.Ordinal))
        {
            moved.Where(ZBlock).Should().NotBeEmpty("a Z block queued behind a held move moved with it to the crossing");
        }
        else
        {
            moved.Where(ZBlock).Should().BeEmpty("outside corners move no end back (only the entry's, an inside corner)");
        }
    }
}
