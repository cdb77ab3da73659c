using System.Net;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Sim.Servers;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 17's proof: a program streamed with the chunk strategy over TCP into the simulator (running the generated
/// library, with the machine's work offsets and tool table downloaded) ends every moving block where the interpreter
/// says, in machine coordinates, within 0.001 mm, and every moving line executes once, in order (a canned cycle's or
/// a reference return's moves all carry its line).
/// </summary>
public class PositionProofTests(ITestOutputHelper output)
{
    private const double Tolerance = 0.001;

    /// <summary>fanuc-mill with a machine's tables: offsets that are not zero, tool lengths, reference positions.</summary>
    public static MachineProfile Machine(string name = "fanuc-mill")
    {
        var json = JsonNode.Parse(MachineProfile.Named(name)!.ToJson())!.AsObject();
        json["workOffsets"] = new JsonObject
        {
            ["G54"] = new JsonArray(10.5, 20.25, -30),
            ["G55"] = new JsonArray(100, 50, -10),
            ["G56"] = new JsonArray(-40, 12.5, -5),
            ["G57"] = new JsonArray(1, 2, 3),
            ["G58"] = new JsonArray(-1, -2, -3),
            ["G59"] = new JsonArray(200, 0, -50),
        };
        json["referencePositions"] = new JsonObject { ["G28"] = new JsonArray(0, 0, 0), ["G30"] = new JsonArray(-100, -50, -20) };
        var tools = new JsonObject();
        for (var h = 1; h <= 20; h++)
        {
            tools[h.ToString(System.Globalization.CultureInfo.InvariantCulture)] = 40 + (h * 2.5);
        }

        json["toolLengths"] = tools;
        json["toolChangePosition"] = new JsonArray(-150, -80, 0);
        return MachineProfile.Parse(json.ToJsonString(), name + "+machine");
    }

    /// <summary>A program with every code of fanuc-mill the controller runs (library) or the host converts.</summary>
    public const string EveryCode = """
        %
        O1000 (EVERY FANUC-MILL CODE THE CONTROLLER RUNS)
        G90 G17 G21 G40 G49 G54 G64 G67 G69 G80 G94 G97 G98 G15 G50 G50.1 G23 G91.1
        G05.1 Q1
        G08 P1
        G187 P2 E0.01
        T1 M06
        S2000 M03
        M08
        G00 X10. Y10.
        G43 Z50. H1
        G01 Z2. F500.
        X20. Y15. F800.
        G02 X30. Y25. I10. J0
        G03 X20. Y35. R10.
        G09 G01 X25.
        G04 P250
        G04 X0.5
        G18 G02 X35. Z2. I5. K0
        G19 G03 Y45. Z2. J5. K0
        G17
        G55 G00 X0 Y0
        G56 X5. Y5.
        G57 X6.
        G58 X7.
        G59 X8.
        G54.1 P2 X9.
        G154 P3 X10.
        G10 L2 P1 X5. Y6. Z-20.
        G54 X1. Y1.
        G10 L2 P0 X1.5 Y-2. Z0.5
        G55 X2. Y2.
        G54 X1. Y1.
        G10 L2 P0 X0 Y0 Z0
        G10 L20 P2 X11. Y12. Z-13.
        G54.1 P2 X2.
        G10 L10 P1 R55.
        G10 L11 P1 R-0.25
        G43 H1 Z40.
        G44 H2 Z30.
        G49 Z60.
        G43 H3 Z50.
        G52 X10. Y-5.
        G00 X0 Y0
        G52 X0 Y0
        G92 X50. Y50.
        G01 X60. Y55. F300.
        G92.1
        G00 X0 Y0
        G53 G00 Z-5.
        G53 X-20. Y-30.
        G28 G91 Z0
        G90 G28 X0 Y0
        G30 Z10.
        G00 X0 Y0 Z20.
        G99 G81 X5. Y5. Z-3. R2. F200.
        X10.
        G98 G82 X15. Z-4. R2. P300
        G73 X20. Z-6. R2. Q1.5
        G83 X25. Z-7. R2. Q2.
        G84 X30. Z-5. R2. P100
        M04
        G74 X35. Z-5. R2. P100
        M03
        G76 X40. Z-8. R2. Q0.5 P200
        G85 X45. Z-5. R2.
        G86 X50. Z-5. R2.
        G87 X55. Z-5. R-10. Q0.5
        G88 X60. Z-5. R2. P100
        G89 X65. Z-5. R2. P100
        G91 G81 X5. Z-5. R-18. K3
        G90 G80
        G95 G01 X70. Y0 F0.2
        G94 G00 Z20.
        G90.1 G02 X80. Y0 I75. J0 F400.
        G91.1
        G20
        G01 X3.5 Y0.5 F20.
        G02 X3.5 Y0.5 I0.5 J0
        G91 G01 X0.1 Y-0.1
        G90 G21
        G00 Z30.
        G61
        G01 X10. Y10. F600.
        Y20.
        G64
        G68 X10. Y10. R30.
        G01 X20. Y10.
        Y20.
        G91 X-5.
        G90 G02 X5. Y20. I-5. J0
        G98 G81 X12. Y12. Z-3. R2.
        G80
        G69
        G51 X0 Y0 P1500
        G01 X10. Y10.
        G03 X0 Y20. R10.
        G50
        G51.1 X0
        G01 X10. Y5.
        G02 X0 Y-5. I-10. J0
        G50.1
        G93 G01 X20. Y20. F10.
        G02 X30. Y10. I0 J-10. F4.
        G94 G01 X0 F600.
        G00 Z30.
        M19 R45.
        M19
        M07
        M09
        M05
        M01
        M00
        G91 G28 Z0
        M30
        %
        """;

    [Fact]
    public async Task A_program_using_every_fanuc_mill_code_ends_each_block_where_the_interpreter_says()
    {
        var folder = new TestFolder("proof");
        var dir = folder.Path;
        try
        {
            var path = Path.Combine(dir, "every.nc");
            await File.WriteAllTextAsync(path, EveryCode);
            var profile = Machine();
            var (lines, diags) = new Checker(profile).CheckText(EveryCode);
            diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty("the program is valid fanuc-mill");
            lines.NotYetCodes.Should().BeEmpty("every code it uses runs on the controller or on the host");
            var report = await ProveAsync(path, profile, force: false);
            output.WriteLine($"{report.Lines} moving lines, {report.Moves} moves, largest difference {report.Largest:0.######} mm");
            report.Lines.Should().BeGreaterThan(50);
            report.Moves.Should().BeGreaterThan(report.Lines + 50, "cycles and reference returns are several moves of one line");

            // The proof can fail: a controller without the machine's tables ends elsewhere.
            var without = () => ProveAsync(path, profile, force: false, tables: false);
            (await without.Should().ThrowAsync<Exception>()).Which.Message.Should().Contain("the interpreter says");
        }
        finally
        {
            folder.Dispose();
        }
    }

    [Fact]
    public async Task Arcs_off_their_circle_within_the_tolerance_and_a_short_R_end_each_block_where_the_interpreter_says()
    {
        // Issue 27: a post's 4-decimal inch arcs (radii 0.0002 in apart), an R 0.00004 in short of half the chord (sent as
        // the half circle's centre), a metric arc 0.02 mm off: the controller lands on each programmed end point.
        const string program = "O1\nG20 G90 G17 G54\nG00 X0 Y0 Z0.2\nG01 Z0 F20.\nG02 X2.0002 Y0 I1. J0\nG03 X0.0002 Y0 I-1. J0\n" +
            "G02 X2.0002 Y0 R0.99996\nG21 G01 X60. Y0\nG03 X80.02 Y0 I10. J0\nG00 Z10.\nM30\n";
        var folder = new TestFolder("proof");
        var dir = folder.Path;
        try
        {
            var path = Path.Combine(dir, "arcs.nc");
            await File.WriteAllTextAsync(path, program);
            new Checker(MachineProfile.Default).CheckText(program).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
            var report = await ProveAsync(path, MachineProfile.Default, force: false);
            output.WriteLine($"{report.Lines} moving lines, {report.Moves} moves, largest difference {report.Largest:0.######} mm");
            report.Lines.Should().Be(8);
        }
        finally
        {
            folder.Dispose();
        }
    }

    [Fact]
    public async Task A_grbl_program_in_exact_path_mode_ends_each_block_where_the_interpreter_says()
    {
        // grbl's G61 is in force from power-on: every move ends at rest (G09.9 after it), in inch blocks too.
        const string program = "G21 G90 G54\nG10 L2 P0 X5 Y5\nG0 X0 Y0 Z5\nG1 Z-1 F300\nX10 Y10\nG2 X20 Y0 I10 J0\nG20 G1 X1 Y1\nG21 G4 P0.2\nG0 Z5\nM30\n";
        var folder = new TestFolder("proof");
        var dir = folder.Path;
        try
        {
            var path = Path.Combine(dir, "grbl.nc");
            await File.WriteAllTextAsync(path, program);
            var profile = Machine("grbl");
            new Checker(profile).CheckText(program).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
            var report = await ProveAsync(path, profile, force: false);
            report.Lines.Should().Be(7, "seven lines move or dwell");
        }
        finally
        {
            folder.Dispose();
        }
    }

    /// <summary>G41/G42 in G55 with a tool length: outside corners, a rapid corner, incremental and Z-only blocks, inch blocks, arcs outside and inside (I/J and R).</summary>
    public const string Compensated = """
        %
        O2000 (CUTTER RADIUS COMPENSATION)
        G90 G17 G21 G40 G49 G80
        G55
        T2 M06
        G43 H2
        G00 X0 Y-20. Z5.
        G01 Z-1. F500.
        G41 D1 X0 Y0
        Y30.
        X40.
        Y0
        G91 X-10. Y-5.
        G90 Z-2.
        X0 Y0
        G00 Y10.
        G01 X20. Y30.
        G40 X40. Y50.
        G00 Z5.
        X60. Y60.
        G01 Z-1. F300.
        G20 G42 D2 X2.3622 Y1.5748
        X3.1496 Y1.7717
        G21 X80.5 Y80.
        G00 X70. Y90.
        G01 X20. Y88.
        G40 X0 Y100.
        G00 Z5.
        X0 Y-20.
        G01 Z-1. F400.
        G41 D1 X0 Y0
        Y20.
        G02 X20. Y40. I20. J0
        G01 X40.
        G02 X50. Y30. I0 J-10.
        G01 Y0
        G02 X40. Y-10. R10.
        G01 X20.
        G03 X10. Y-20. I0 J-10.
        G01 Y-40.
        G02 X0 Y-30. I0 J10.
        G01 Y-10.
        G40 X-20. Y-10.
        G00 Z10.
        M30
        %
        """;

    [Fact]
    public async Task A_program_under_cutter_radius_compensation_ends_each_block_where_the_interpreter_says()
    {
        using var dir = new TestFolder("proof");
        var path = Path.Combine(dir.Path, "comp.nc");
        await File.WriteAllTextAsync(path, Compensated);
        var (json, profile) = WithRadii();
        var (lines, diags) = new Checker(profile).CheckText(Compensated);
        diags.Where(d => d.Severity == Severity.Error).Should().BeEmpty("straight moves with outside corners are compensated");
        lines.NotYetCodes.Should().BeEmpty("G41 and G42 are the host's");
        var report = await ProveAsync(path, profile, force: false);
        output.WriteLine($"{report.Lines} moving lines, {report.Moves} moves, largest difference {report.Largest:0.######} mm");
        report.Moves.Should().BeGreaterThan(report.Lines + 5, "outside corners are an arc (or a rapid) and a line of one block");

        // The proof can fail: the blocks sent as programmed (radius 0) do not end where the compensating interpreter says.
        json["toolRadii"] = new JsonObject { ["1"] = 0, ["2"] = 0 };
        var uncompensated = MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+zero");
        var sentPlain = () => ProveAsync(path, uncompensated, force: false, expectedFrom: profile);
        (await sentPlain.Should().ThrowAsync<Exception>()).Which.Message.Should().Contain("the interpreter says");
    }

    /// <summary>Pockets whose corners are all inside ones: line to line (the entry's end too), line to arc, arc to line, arc to arc, an incremental entry under G42.</summary>
    public const string Pockets = """
        %
        O2001 (POCKETS UNDER CUTTER RADIUS COMPENSATION)
        G90 G17 G21 G40 G49 G80
        G55
        T2 M06
        G43 H2
        G00 X50. Y25. Z5.
        G01 Z-1. F500.
        G41 D1 X50. Y0
        X100.
        Y50.
        X0
        Y0
        X50.
        G40 X50. Y25.
        G41 D1 X100. Y25.
        Y50.
        G03 X0 Y50. R60.
        G01 Y0
        G02 X50. Y0 R40.
        G02 X100. Y0 I25. J-31.225
        G01 Y25.
        G40 X50. Y25.
        G91 G42 D2 X-50. Y-25.
        X-40.
        G90 G02 X-50. Y10. I0 J10.
        G01 Y40.
        G40 X50. Y25.
        G00 Z10.
        M30
        %
        """;

    [Fact]
    public async Task A_pocket_under_cutter_radius_compensation_ends_each_block_where_the_interpreter_moved_it_back_to()
    {
        using var dir = new TestFolder("proof");
        var path = Path.Combine(dir.Path, "pockets.nc");
        await File.WriteAllTextAsync(path, Pockets);
        var (_, profile) = WithRadii();
        new Checker(profile).CheckText(Pockets).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty("inside corners are computed");
        var report = await ProveAsync(path, profile, force: false);
        output.WriteLine($"{report.Lines} moving lines, {report.Moves} moves, largest difference {report.Largest:0.######} mm");
        report.Lines.Should().BeGreaterThan(20);
    }

    /// <summary>
    /// Z blocks between compensated XY moves (issue 27 item 4): plunges, retracts, a rapid, an incremental Z, a dwell
    /// and a coolant code queued behind the held move at inside corners (they run at the crossing), and at outside
    /// corners; lines and arcs before and after them; G41 and G42; an inch pocket.
    /// </summary>
    public const string PlungedPockets = """
        %
        O2002 (Z BLOCKS BETWEEN COMPENSATED MOVES)
        G90 G17 G21 G40 G49 G80
        G55
        T2 M06
        G43 H2
        G00 X50. Y25. Z5.
        G01 Z-1. F500.
        G41 D1 X100. Y25.
        Z-2.
        Y50.
        G00 Z1.
        G01 Z-1.
        G03 X0 Y50. R60.
        G04 X0.1
        G01 Z-1.5
        Y0
        M08
        G91 Z-0.5
        G90 G02 X50. Y0 R40.
        G01 Z-1.
        G02 X100. Y0 I25. J-31.225
        G01 Z-2.
        Y25.
        G40 X50. Y25.
        G00 Z5.
        X50. Y70.
        G01 Z-1.
        G42 D1 X50. Y50.
        X0
        Z-2.
        Y0
        G00 Z1.
        G01 Z-1.
        X100.
        Z-2.
        G03 X100. Y50. R25.
        G01 Z-1.
        X50.
        G40 X50. Y70.
        G00 Z5.
        G20 X1.9685 Y0.9843
        G01 Z-0.04 F20.
        G42 D2 X0 Y0.9843
        Z-0.06
        Y1.9685
        Z-0.05
        G02 X3.937 Y1.9685 R2.3622
        G01 Z-0.06
        Y0
        Z-0.04
        X0
        G40 X1.9685 Y0.9843
        G21 G00 Z10.
        M09
        M30
        %
        """;

    [Fact]
    public async Task Z_blocks_between_compensated_moves_end_where_the_interpreter_moved_them_to()
    {
        using var dir = new TestFolder("proof");
        var path = Path.Combine(dir.Path, "plunged.nc");
        await File.WriteAllTextAsync(path, PlungedPockets);
        var (_, profile) = WithRadii();
        new Checker(profile).CheckText(PlungedPockets).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty("Z blocks are queued behind the held move");
        var report = await ProveAsync(path, profile, force: false);
        output.WriteLine($"{report.Lines} moving lines, {report.Moves} moves, largest difference {report.Largest:0.######} mm");
        report.Lines.Should().BeGreaterThan(45);

        // The plunge after the entry runs where the inside corner ends the entry, not beside the programmed (100, 25).
        var ends = CanonBlockEnds.Of(path, profile, blockDelete: true);
        var plunge = ends.Single(e => e.Line == 10).End;
        var held = ends.Single(e => e.Line == 9).End;
        (plunge.X, plunge.Y).Should().Be((held.X, held.Y), "the plunge runs at the held move's end");
        var provisional = CanonBlockEnds.Of(path, profile, blockDelete: true, amend: false).Single(e => e.Line == 10).End;
        (provisional.X - plunge.X).Should().BeApproximately(5, 1e-9, "the entry's offset line (Y30) crosses Y50's (X95) 5 mm back from beside the programmed X100");
        provisional.Y.Should().BeApproximately(plunge.Y, 1e-9);
    }

    [Theory]
    [InlineData(13)]
    [InlineData(16)]
    [InlineData(35)]
    public async Task A_start_from_a_block_under_cutter_radius_compensation_ends_each_block_where_the_interpreter_says(int line)
    {
        using var dir = new TestFolder("proof");
        var path = Path.Combine(dir.Path, "comp.nc");
        await File.WriteAllTextAsync(path, Compensated);
        var report = await ProveAsync(path, WithRadii().Profile, force: false, fromLine: line);
        report.Lines.Should().BeGreaterThan(5, "the blocks from the start on ran");
    }

    private static (JsonObject Json, MachineProfile Profile) WithRadii()
    {
        var json = JsonNode.Parse(Machine().ToJson())!.AsObject();
        json["toolRadii"] = new JsonObject { ["1"] = 5, ["2"] = 2.5 };
        return (json, MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radii"));
    }

    /// <summary>A program that changes the offsets before its moves: work offset data, G52, G92, tool length, rotation.</summary>
    public const string OffsetsBeforeTheStart = """
        G21 G90 G17 G40 G49 G80
        G10 L2 P2 X30. Y-20. Z5.
        G55
        G52 X10. Y10.
        G43 H1
        S1000 M03
        G00 X0 Y0 Z10.
        G01 Z-1. F300.
        X20.
        G92 X0 Y0
        G01 X5. Y5.
        X10.
        G68 X0 Y0 R30.
        G01 X20. Y0
        X30. Y10.
        G69
        X40. Y10.
        G00 Z10.
        M30
        """;

    /// <summary>Extended work offsets, FANUC's external offset, a tool length set by the program, scaling.</summary>
    public const string TablesBeforeTheStart = """
        G21 G90 G17 G40 G49 G80
        G10 L2 P0 X1.5 Y-2. Z0.5
        G10 L20 P3 X-60. Y25. Z-15.
        G10 L10 P2 R55.
        G54.1 P3
        G43 H2
        G00 X0 Y0 Z10.
        G01 Z-2. F400.
        G51 X0 Y0 P2.
        G01 X10. Y5.
        X15.
        G50
        X20. Y0
        G00 Z10.
        M30
        """;

    [Theory]
    [InlineData("offsets", 8)]
    [InlineData("offsets", 11)]
    [InlineData("offsets", 14)]
    [InlineData("offsets", 17)]
    [InlineData("tables", 8)]
    [InlineData("tables", 11)]
    [InlineData("tables", 13)]
    public async Task A_start_from_a_block_after_offsets_were_set_ends_each_block_where_the_interpreter_says(string program, int line)
    {
        var text = program == "offsets" ? OffsetsBeforeTheStart : TablesBeforeTheStart;
        using var dir = new TestFolder("proof");
        var path = Path.Combine(dir.Path, program + ".nc");
        await File.WriteAllTextAsync(path, text);
        var profile = Machine();
        new Checker(profile).CheckText(text).Diagnostics.Where(d => d.Severity == Severity.Error).Should().BeEmpty();
        var report = await ProveAsync(path, profile, force: false, fromLine: line);
        report.Lines.Should().BeGreaterThan(0, "the blocks from the start on ran");
    }

    [SkippableFact]
    public async Task Every_corpus_program_ends_each_block_where_the_interpreter_says()
    {
        var files = Requires.Corpus();
        var profile = Machine();
        var folder = new TestFolder("proof");
        var dir = folder.Path;
        try
        {
            // Two at a time: the machine has two cores, and each run is a TCP server and a session.
            var runs = new List<Task<ProofReport>>();
            foreach (var file in files)
            {
                var copy = Path.Combine(dir, Path.GetFileName(file));
                File.Copy(file, copy);
                var errors = new Checker(profile).CheckFile(copy, _ => { }).Errors;
                runs.Add(ProveAsync(copy, profile, force: errors > 0));
                if (runs.Count % 2 == 0)
                {
                    await Task.WhenAll(runs);
                }
            }

            foreach (var r in await Task.WhenAll(runs))
            {
                output.WriteLine($"{r.Name}: {r.Lines} moving lines, {r.Moves} moves, largest difference {r.Largest:0.######} mm");
            }
        }
        finally
        {
            folder.Dispose();
        }
    }

    /// <summary>The outcome of one program's proof.</summary>
    public sealed record ProofReport(string Name, int Lines, int Moves, double Largest);

    private static async Task<ProofReport> ProveAsync(string path, MachineProfile profile, bool force, bool tables = true, int? fromLine = null, MachineProfile? expectedFrom = null)
    {
        var name = Path.GetFileName(path);
        var split = Splitter.Split(path, new SplitOptions
        {
            CheckProfile = profile, AllowErrors = force, BlocksPerChunk = 300, OutDir = path + (tables ? "_chunks" : "_chunks_bare"),
        });
        var program = ChunkedProgram.Open(split.ManifestPath);
        await using var host = new SimHost(new SimHostOptions
        {
            Simulator = new SimOptions { Speed = SimSpeed.Instant },
            TcpEndPoint = new IPEndPoint(IPAddress.Loopback, 0),
        });
        host.Start();
        await using (var eth = new EthernetConnection(new EthernetOptions { Port = host.TcpEndPoint!.Port, Timeout = TimeSpan.FromSeconds(10) }))
        {
            // Program stops would wait for an operator: this run has none, so M00/M01/M06 only wait for the moves ahead.
            await eth.DownloadAsync(ControllerLibrary.Lines(profile, new Prog1000Options { ProgramStops = false }));
            if (tables)
            {
                await eth.DownloadAsync(ControllerLibrary.TableLines(profile));
            }
            var session = new StreamingSession(eth, program, new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = 60_000 });
            if (fromLine is { } from)
            {
                // Start from a block as the HMI and --from-line do: the one start planner's preamble, then the chunks.
                var plan = StartFromLine.Plan(path, from, StartPlanOptions.For(program.Manifest, new StartPlanOptions { Profile = profile }));
                await session.StartAsync(plan.Line, plan.PmacLines);
                fromLine = plan.Line;
            }
            else
            {
                await session.StartAsync();
            }

            var deadline = DateTime.UtcNow + TimeSpan.FromMinutes(3);
            while (session.State is not (SessionState.Completed or SessionState.Faulted or SessionState.Aborted) && DateTime.UtcNow < deadline)
            {
                await session.TickAsync();
                await Task.Delay(5);
            }

            session.State.Should().Be(SessionState.Completed, $"{name} should run to its end");
        }

        await host.StopAsync();
        var executed = host.Simulator.ExecutedMoves
            .Where(m => !(m.Kind == MoveKind.Dwell && m.Duration == 0)) // DWELL0 of the library's routines: no block of the program
            .Where(m => m.SourceLine >= (fromLine ?? 0)) // a start from a block: its preamble's approach is no block of the program
            .ToList();
        var expected = Expected(path, expectedFrom ?? profile).Where(e => e.Line >= (fromLine ?? 0)).ToList();
        var largest = BlockEndProof.Check(executed, expected, Tolerance, name, "moving line", line => $"{name}:{line}");
        return new ProofReport(name, expected.Count, executed.Count, largest);
    }

    /// <summary>The interpreter's end of every moving block (its canonical moves), machine coordinates in millimetres.</summary>
    private static List<(int Line, Point3 End)> Expected(string path, MachineProfile profile) =>
        CanonBlockEnds.Of(path, profile, blockDelete: true).Select(m => (m.Line, m.End)).ToList();
}
