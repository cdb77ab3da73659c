using System.Diagnostics;
using System.Globalization;
using System.Text.RegularExpressions;
using PmacStream.GCode;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// An independent check of what the interpreter says a program means (issue 17): LinuxCNC's stand-alone interpreter
/// rs274 runs the program with the same tool table and offsets, and its canonical moves (program coordinates plus the
/// work offset, G92 offset and tool length offset it reports, in the units it reports them) must pass through every
/// block end the interpreter computes, in order, within 0.001 mm. Where rs274 refuses a program, that program is
/// named and left out.
/// </summary>
public partial class Rs274ComparisonTests(ITestOutputHelper output)
{
    private const double Tolerance = 0.001;

    // rs274 prints 4 decimals in the program's units: half of 0.0001 in is 0.00127 mm, for the position and again for
    // the tool length offset it reports.
    private const double InchTolerance = 0.0026;

    /// <summary>RS274/NGC with the codes of the every-code program rs274 knows (G04 P in seconds, G10 L20 from the position).</summary>
    private const string Program = """
        G21 G90 G17 G94 G40 G49 G54
        G10 L2 P2 X100 Y50 Z-10
        G10 L2 P1 X10.5 Y20.25 Z-30
        T1 M6
        G43 H1
        G0 X10 Y10 Z50
        G1 Z2 F500
        X20 Y15 F800
        G2 X30 Y25 I10 J0
        G3 X20 Y35 R10
        G4 P0.25
        G18 G2 X30 Z2 I5 K0
        G19 G3 Y45 Z2 J5 K0
        G17
        G55 G0 X0 Y0
        G10 L20 P1 X1 Y2 Z3
        G54 X5 Y5
        G43 H2 Z30
        G49 Z60
        G43 H3 Z50
        G52 X10 Y-5
        G0 X0 Y0
        G52 X0 Y0
        G92 X50 Y50
        G1 X60 Y55 F300
        G92.1
        G0 X0 Y0
        G53 G0 Z-5
        G91 G28 Z0
        G90 G0 X0 Y0 Z20
        G99 G81 X5 Y5 Z-3 R2 F200
        X10
        G98 G82 X15 Z-4 R2 P0.3
        G73 X20 Z-6 R2 Q1.5
        G83 X25 Z-7 R2 Q2
        G85 X45 Z-5 R2
        G89 X65 Z-5 R2 P0.1
        G91 G81 X5 Z-5 R-18 L3
        G90 G80
        G0 Z20
        G20
        G1 X3.5 Y0.5 F20
        G2 X3.5 Y0.5 I0.5 J0
        G91 G1 X0.1 Y-0.1
        G90 G21
        G0 Z30
        M2
        """;

    /// <summary>linuxcnc-mill with tool lengths (and the zero G28/G30 positions rs274 has without a parameter file).</summary>
    private static MachineProfile Machine() => MachineProfile.Parse(
        MachineProfile.Named("linuxcnc-mill")!.ToJson().Replace("\"referencePositions\": {}",
            "\"referencePositions\": {}, \"toolLengths\": { \"1\": 50, \"2\": 75.5, \"3\": 42.25 }, \"toolRadii\": { \"4\": 5, \"5\": 2.5 }"), "linuxcnc-mill+tools");

    /// <summary>
    /// G41/G42: entries, straight runs, outside corners (feed arcs and a rapid's straight way), an incremental block, a
    /// Z-only block, lines at any angle, arcs with the cutter outside (G41 G02) and inside (G41 G03), tangent or after a
    /// corner; tools 4 (radius 5) and 5 (radius 2.5) from the tool table.
    /// </summary>
    private const string Compensated = """
        G21 G90 G17 G94 G40 G49 G54
        G10 L2 P1 X10.5 Y20.25 Z-30
        T4 M6
        G43 H1
        G0 X0 Y-20 Z5
        G1 Z-1 F500
        G41 X0 Y0
        Y30
        X40
        Y0
        G91 X-10 Y-5
        G90 Z-2
        X0 Y0
        G0 Y10
        G1 X20 Y30
        G40 X40 Y50
        G0 Z5
        T5 M6
        G0 X60 Y60
        G1 Z-1 F300
        G42 X60 Y40
        X80 Y45
        X80.5 Y80
        G0 X70 Y90
        G1 X20 Y88
        G40 X0 Y100
        G0 Z5
        T4 M6
        G0 X0 Y-20 Z5
        G1 Z-1 F400
        G41 X0 Y0
        Y20
        G2 X20 Y40 I20 J0
        G1 X40
        G2 X50 Y30 I0 J-10
        G1 Y0
        G2 X40 Y-10 I-10 J0
        G1 X20
        G3 X10 Y-20 I0 J-10
        G1 Y-40
        G2 X0 Y-30 I0 J10
        G1 Y-10
        G40 X-20 Y-10
        G0 Z5
        M2
        """;

    [SkippableFact]
    public void Rs274_passes_through_every_block_end_of_an_rs274ngc_program_using_the_offsets_cycles_and_units()
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274");
        var dir = temp.Path;
        var path = Path.Combine(dir, "every.ngc");
        File.WriteAllText(path, Program + "\n");
        var profile = Machine();
        var (summary, diags) = new Checker(profile).CheckText(Program);
        diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
        var (accepted, why) = Compare(rs274, path, profile, dir);
        accepted.Should().BeTrue(why);
        output.WriteLine(why);
    }

    [SkippableFact]
    public void Rs274_passes_through_every_block_end_of_a_program_under_cutter_radius_compensation()
    {
        var rs274 = Requires.Rs274();
        var folder = new TestFolder("rs274");
        var dir = folder.Path;
        try
        {
            var path = Path.Combine(dir, "comp.ngc");
            File.WriteAllText(path, Compensated + "\n");
            var profile = Machine();
            new Checker(profile).CheckText(Compensated).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
            var (accepted, why) = Compare(rs274, path, profile, dir);
            accepted.Should().BeTrue(why);
            output.WriteLine(why);

            // The comparison can fail: the same program without compensation does not pass through rs274's moves.
            var plain = Path.Combine(dir, "plain.ngc");
            File.WriteAllText(plain, Compensated.Replace("G41 ", string.Empty, StringComparison.Ordinal).Replace("G42 ", string.Empty, StringComparison.Ordinal) + "\n");
            var wrong = () => Compare(rs274, plain, profile, dir, canonFrom: path);
            wrong.Should().Throw<Exception>().WithMessage("*rs274 never reaches*");

            // An inside corner: rs274 moves the end of the move before it back to where the offset lines cross; so does the host.
            const string inside = "G21 G90 G17\nT4 M6\nG0 X-20 Y-20 Z5\nG1 Z-1 F500\nG42 X0 Y0\nY30\nX40\nG40 X60 Y60\nM2";
            var insidePath = Path.Combine(dir, "inside.ngc");
            File.WriteAllText(insidePath, inside + "\n");
            new Checker(profile).CheckText(inside).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
            Run(rs274, insidePath, dir).Canon.Should().Contain("STRAIGHT_FEED(5.0000, 25.0000", "rs274 ends the block before the corner where the next move's offset line crosses it");
            Compare(rs274, insidePath, profile, dir).Accepted.Should().BeTrue();
        }
        finally
        {
            folder.Dispose();
        }
    }

    /// <summary>
    /// Pockets cut with the cutter inside (G41 counter-clockwise, G42 clockwise: every corner an inside one), the radius
    /// from the tool table by D: a rectangle (line to line, the entry move's end moved back too), arc sides that meet
    /// lines and each other at inside corners (line to arc, arc to line, arc to arc; R and I/J), and a rectangle with
    /// tangent arc corners.
    /// </summary>
    public static TheoryData<string, string> Pockets => new()
    {
        { "rectangle G41", "G41 D4 X50 Y0\nX100\nY50\nX0\nY0\nX50" },
        { "rectangle G42", "G42 D4 X50 Y0\nX0\nY50\nX100\nY0\nX50" },
        { "arc sides G41", "G41 D4 X100 Y25\nY50\nG3 X0 Y50 R60\nG1 Y0\nG2 X50 Y0 R40\nG2 X100 Y0 I25 J-31.225\nG1 Y25" },
        { "arc sides G42", "G42 D4 X0 Y25\nY50\nG2 X100 Y50 R60\nG1 Y0\nG3 X50 Y0 R40\nG3 X0 Y0 I-25 J-31.225\nG1 Y25" },
        { "arc corners G41", "G41 D5 X50 Y0\nX90\nG3 X100 Y10 I0 J10\nG1 Y40\nG3 X90 Y50 I-10 J0\nG1 X10\nG3 X0 Y40 I0 J-10\nG1 Y10\nG3 X10 Y0 I10 J0\nG1 X50" },
        { "arc corners G42", "G42 D5 X50 Y0\nX10\nG2 X0 Y10 I0 J10\nG1 Y40\nG2 X10 Y50 I10 J0\nG1 X90\nG2 X100 Y40 I0 J-10\nG1 Y10\nG2 X90 Y0 I-10 J0\nG1 X50" },
    };

    [SkippableTheory]
    [MemberData(nameof(Pockets))]
    public void Rs274_passes_through_every_block_end_of_a_pocket_whose_corners_are_all_inside_ones(string name, string contour)
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274");
        var program = $"G21 G90 G17 G94 G40 G49 G54\nG10 L2 P1 X10.5 Y20.25 Z-30\nG0 X50 Y25 Z5\nG1 Z-2 F300\n{contour}\nG40 X50 Y25\nG0 Z5\nM2";
        var path = Path.Combine(temp.Path, "pocket.ngc");
        File.WriteAllText(path, program + "\n");
        var profile = Machine();
        new Checker(profile).CheckText(program).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty(name);
        var (accepted, why) = Compare(rs274, path, profile, temp.Path);
        accepted.Should().BeTrue(why);
        output.WriteLine($"{name}: {why}");

        // The comparison can fail: the ends as reported before the next move is known (not moved back) are not rs274's.
        var provisional = CanonBlockEnds.Of(path, profile, amend: false).Select(m => m.End).ToList();
        var amended = CanonBlockEnds.Of(path, profile).Select(m => m.End).ToList();
        provisional.Zip(amended).Count(p => Distance(p.First, p.Second) > 0.1).Should().BeGreaterThan(0, "inside corners moved ends back (the entry's at least)");
    }

    [SkippableFact]
    public void An_inside_corner_the_tool_cannot_reach_without_gouging_is_refused_by_both()
    {
        var rs274 = Requires.Rs274();
        using var temp = new TestFolder("rs274");
        const string program = "G21 G90 G17\nT4 M6\nG0 X0 Y-20\nG41 D4 G1 X0 Y0 F100\nG3 X12 Y-2 I6 J-1\nG40 X0 Y-20\nM2";
        var path = Path.Combine(temp.Path, "gouge.ngc");
        File.WriteAllText(path, program + "\n");
        Compare(rs274, path, Machine(), temp.Path).Why.Should().Contain("without gouging");
        new Checker(Machine()).CheckText(program).Diagnostics.Should().Contain(d => d.Code == DiagnosticCodes.CompensationConcaveCorner && d.Line == 5);
    }

    [SkippableFact]
    public void Rs274_agrees_on_every_corpus_program_it_accepts()
    {
        var rs274 = Requires.Rs274();
        var files = Requires.Corpus();
        var profile = Machine();
        using var temp = new TestFolder("rs274");
        var dir = temp.Path;
        var compared = 0;
        foreach (var file in files)
        {
            if (new Checker(profile).CheckFile(file, _ => { }).Errors > 0)
            {
                output.WriteLine($"{Path.GetFileName(file)}: not RS274/NGC for linuxcnc-mill (checker errors): left out");
                continue;
            }

            var (accepted, why) = Compare(rs274, file, profile, dir);
            output.WriteLine($"{Path.GetFileName(file)}: {why}");
            if (accepted)
            {
                compared++;
            }
        }

        compared.Should().BeGreaterThan(3, "rs274 takes most of the corpus");
    }

    /// <summary>
    /// Runs rs274 and matches the interpreter's block ends against its moves (of <paramref name="canonFrom"/> when given:
    /// another program's); (false, why) when rs274 refuses the program.
    /// </summary>
    private static (bool Accepted, string Why) Compare(string rs274, string path, MachineProfile profile, string dir, string? canonFrom = null)
    {
        var (exit, canon, err) = Run(rs274, canonFrom ?? path, dir, profile);
        if (exit is null)
        {
            return (false, "rs274 did not finish in 60 s");
        }

        // rs274 reports an interpreter error as a text line (and the block) among its canonical calls, exit code 0.
        var complaint = (err + canon).Split('\n').Select(l => l.Trim()).FirstOrDefault(l => l.Length > 0 && l != "executing" && !CanonLine().IsMatch(l));
        if (exit != 0 || complaint is not null)
        {
            return (false, $"rs274 refused it (exit {exit}): {complaint}");
        }

        var moves = Moves(canon, out var inch);
        var tolerance = inch ? InchTolerance : Tolerance;
        // The interpreter's canonical moves: every block that moves the machine (a dwell does not).
        var ends = CanonBlockEnds.Of(path, profile).Where(m => m.Kind != MotionKind.Dwell).Select(m => (m.Line, m.End)).ToList();

        var at = 0;
        var worst = 0.0;
        foreach (var (line, end) in ends)
        {
            while (at < moves.Count && Distance(moves[at], end) > tolerance)
            {
                at++;
            }

            at.Should().BeLessThan(moves.Count, $"{Path.GetFileName(path)}:{line}: rs274 never reaches ({end.X}, {end.Y}, {end.Z}) after the ends before it");
            worst = Math.Max(worst, Distance(moves[at], end));
            at++;
        }

        return (true, $"{ends.Count} block ends, all on rs274's {moves.Count} moves in order (largest difference {worst:0.######} mm)");
    }

    /// <summary>rs274 on <paramref name="path"/> with the profile's tool table: its exit code (null when it did not finish), canonical calls and errors.</summary>
    private static (int? Exit, string Canon, string Err) Run(string rs274, string path, string dir, MachineProfile? profile = null)
    {
        profile ??= Machine();
        // rs274 without LinuxCNC reads tool table lengths and diameters in inches (its stand-alone machine units): written so.
        var tools = Path.Combine(dir, "tool.tbl");
        // Tools 1-99 (a program may change to any of them); the profile's lengths and radii where it has them.
        File.WriteAllLines(tools, Enumerable.Range(1, 99).Select(t =>
            $"T{t} P{t} Z{(profile.ToolLength(t) / 25.4).ToString("0.##########", CultureInfo.InvariantCulture)} D{(profile.ToolRadius(t) is { } r ? 2 * r / 25.4 : 6).ToString("0.##########", CultureInfo.InvariantCulture)}"));
        var psi = new ProcessStartInfo(rs274, ["-t", tools, "-g", path, "/dev/stdout"]) { RedirectStandardOutput = true, RedirectStandardError = true, RedirectStandardInput = true };
        using var p = Process.Start(psi)!;
        p.StandardInput.Close();
        var stdout = p.StandardOutput.ReadToEndAsync();
        var stderr = p.StandardError.ReadToEndAsync();
        if (!p.WaitForExit(60_000))
        {
            p.Kill();
            return (null, string.Empty, string.Empty);
        }

        return (p.ExitCode, stdout.Result, stderr.Result);
    }

    private static double Distance(Point3 a, Point3 b) => Math.Max(Math.Abs(a.X - b.X), Math.Max(Math.Abs(a.Y - b.Y), Math.Abs(a.Z - b.Z)));

    /// <summary>rs274's move ends in machine millimetres: program coordinates + work offset + G92 offset + tool length, scaled from its units.</summary>
    private static List<Point3> Moves(string canon, out bool inch)
    {
        inch = false;
        var list = new List<Point3>();
        var scale = 1.0;
        var plane = "XY";
        Point3 work = default, g92 = default, tool = default;
        Point3 S(double x, double y, double z) => new(x * scale, y * scale, z * scale);
        foreach (var raw in canon.Split('\n'))
        {
            var m = Call().Match(raw);
            if (!m.Success)
            {
                continue;
            }

            var args = Numbers().Matches(m.Groups[2].Value).Select(x => double.Parse(x.Value, CultureInfo.InvariantCulture)).ToList();
            switch (m.Groups[1].Value)
            {
                case "SELECT_PLANE":
                    plane = raw.Contains("XZ", StringComparison.Ordinal) ? "XZ" : raw.Contains("YZ", StringComparison.Ordinal) ? "YZ" : "XY";
                    break;
                case "USE_LENGTH_UNITS":
                    scale = raw.Contains("INCHES", StringComparison.Ordinal) ? 25.4 : 1.0;
                    inch |= scale != 1.0;
                    break;
                case "SET_G5X_OFFSET":
                    work = S(args[1], args[2], args[3]);
                    break;
                case "SET_G92_OFFSET":
                    g92 = S(args[0], args[1], args[2]);
                    break;
                case "USE_TOOL_LENGTH_OFFSET":
                    tool = S(args[0], args[1], args[2]);
                    break;
                case "STRAIGHT_TRAVERSE" or "STRAIGHT_FEED" or "STRAIGHT_PROBE":
                    list.Add(S(args[0], args[1], args[2]) + work + g92 + tool);
                    break;
                case "ARC_FEED":
                    // ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end_point, a, b, c, ...)
                    // in the plane's own order; the plane is the one SELECT_PLANE chose.
                    var e = ArcEnd(args, plane);
                    list.Add(S(e.X, e.Y, e.Z) + work + g92 + tool);
                    break;
            }
        }

        return list;
    }

    private static Point3 ArcEnd(List<double> a, string plane) => plane switch
    {
        "XZ" => new Point3(a[1], a[5], a[0]),
        "YZ" => new Point3(a[5], a[0], a[1]),
        _ => new Point3(a[0], a[1], a[5]),
    };

    [GeneratedRegex(@"^\d+ N[\d.]*\s+[A-Z_0-9]+\(")]
    private static partial Regex CanonLine();

    [GeneratedRegex(@"N[\d.]*\s+([A-Z_0-9]+)\((.*)\)")]
    private static partial Regex Call();

    [GeneratedRegex(@"-?\d+(\.\d+)?(e[-+]?\d+)?")]
    private static partial Regex Numbers();
}
