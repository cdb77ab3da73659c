using System.Net;
using PmacStream.GCode;
using PmacStream.GCode.Expansion;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;
using PmacStream.Sim.Servers;
using PmacStream.Streaming;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// Issue 27: programs with FANUC subprograms and Custom Macro B, and with LinuxCNC o-words, split from their
/// expansion and streamed over TCP into the simulator: every expanded block executes once, in order (its
/// <c>M0==</c> is its expanded line), and ends where the interpreter says the expanded block ends, within 0.001 mm.
/// </summary>
public class ExpansionProofTests(ITestOutputHelper output)
{
    private const double Tolerance = 0.001;

    /// <summary>Subprograms (repeated), a macro with arguments and its own loop, a loop and a branch in the main program.</summary>
    public const string FanucMacros = """
        %
        O0001 (SUBPROGRAMS AND MACRO B)
        G21 G90 G17 G40 G49 G54 G80 G94
        T1 M06
        G43 H1 Z50.
        G00 X0 Y0 Z5.
        M98 P1002 L3
        G65 P9100 X20. Y10. R4. K6
        #1 = 0
        WHILE [#1 LT 4] DO1
        G01 X[30 + #1 * 2.5] Y[10 * SIN[#1 * 30]] Z-1. F600
        #1 = #1 + 1
        END1
        IF [#1 NE 4] GOTO 90
        G02 X45. Y0 R8.
        N90 G00 Z20.
        M30
        %
        O1002 (STEP)
        G91 G01 X5. Z-0.5 F300
        G90 G00 Z5.
        M99
        %
        O9100 (BOLT CIRCLE: X Y CENTRE, R RADIUS, K HOLES)
        #10 = 0
        WHILE [#10 LT #6] DO2
        G00 X[#24 + #18 * COS[#10 * 360 / #6]] Y[#25 + #18 * SIN[#10 * 360 / #6]]
        G01 Z-2. F200
        G00 Z5.
        #10 = #10 + 1
        END2
        M99
        %
        """;

    /// <summary>LinuxCNC o-words: a subroutine with parameters called in a while loop, repeat, if/else.</summary>
    public const string OWords = """
        G21 G90 G17 G94 G54
        o<square> sub
          G1 X[#1] Y0 Z-1 F500
          G1 Y[#1]
          G1 X0
          G1 Y0
        o<square> endsub
        #<size> = 10
        #2 = 0
        G0 X0 Y0 Z5
        o100 while [#2 LT 3]
          o<square> call [#<size> + #2*5]
          #2 = [#2 + 1]
        o100 endwhile
        o200 repeat [2]
          G0 Z[5 + #2]
          G2 X10 Y0 I5 J0
          G0 X0
        o200 endrepeat
        o300 if [#2 EQ 3]
          G0 X1
        o300 else
          G0 X2
        o300 endif
        M2
        """;

    [Fact]
    public async Task A_fanuc_program_with_subprograms_and_macro_b_streams_every_expanded_block_once_where_the_interpreter_says()
    {
        using var dir = new TestFolder("expand-proof");
        var path = Path.Combine(dir.Path, "macros.nc");
        await File.WriteAllTextAsync(path, FanucMacros);
        var profile = PositionProofTests.Machine();
        var report = await ProveAsync(path, profile);
        output.WriteLine($"{report.Lines} moving expanded blocks, largest difference {report.Largest:0.######} mm");
        report.Lines.Should().Be(3 + (3 * 2) + (6 * 3) + 4 + 1 + 1, "the start's three (tool change, G43, rapid), 3 steps of 2 moves, 6 holes of 3, 4 loop moves, the arc, the last rapid");

        // The split carries its map: the tracked line of a hole names the macro, its call and its iteration.
        var map = ExpansionMap.Load(Path.Combine(path + "_chunks", ExpansionMap.FileName));
        var hole = Enumerable.Range(1, (int)map.Lines).First(l => map.Describe(l).StartsWith("O9100 line 27", StringComparison.Ordinal) && map.Find(l)!.Value.Iteration == 4);
        map.Describe(hole).Should().Be("O9100 line 27, iteration 4, call 1 of 1 from line 8");
    }

    [Fact]
    public async Task A_linuxcnc_program_with_o_words_streams_every_expanded_block_once_where_the_interpreter_says()
    {
        using var dir = new TestFolder("expand-proof");
        var path = Path.Combine(dir.Path, "owords.ngc");
        await File.WriteAllTextAsync(path, OWords + "\n");
        var report = await ProveAsync(path, PositionProofTests.Machine("linuxcnc-mill"));
        output.WriteLine($"{report.Lines} moving expanded blocks, largest difference {report.Largest:0.######} mm");
        report.Lines.Should().Be(1 + (3 * 4) + (2 * 3) + 1);
    }

    [SkippableFact]
    public async Task The_enclosure_corpus_program_runs_under_linuxcnc_mill()
    {
        var file = Requires.Corpus().Single(f => f.Contains("Enclosure", StringComparison.Ordinal));
        using var dir = new TestFolder("expand-proof");
        var path = Path.Combine(dir.Path, Path.GetFileName(file));
        File.Copy(file, path);
        var report = await ProveAsync(path, PositionProofTests.Machine("linuxcnc-mill"));
        output.WriteLine($"{report.Lines} moving expanded blocks, largest difference {report.Largest:0.######} mm");
        report.Lines.Should().BeGreaterThan(1500);
    }

    /// <summary>The outcome of one program's proof.</summary>
    public sealed record ProofReport(int Lines, double Largest);

    private static async Task<ProofReport> ProveAsync(string path, MachineProfile profile)
    {
        var name = Path.GetFileName(path);
        var split = Splitter.Split(path, new SplitOptions { CheckProfile = profile, BlocksPerChunk = 40, OutDir = path + "_chunks" });
        File.Exists(Path.Combine(split.OutputDirectory, ExpansionMap.FileName)).Should().BeTrue("an expanded split keeps its map");
        var program = ChunkedProgram.Open(split.ManifestPath);
        await using var host = new SimHost(new SimHostOptions
        {
            Simulator = new SimOptions { Speed = SimSpeed.Instant },
            TcpEndPoint = new IPEndPoint(IPAddress.Loopback, 0),
        });
        host.Start();
        await using (var eth = new EthernetConnection(new EthernetOptions { Port = host.TcpEndPoint!.Port, Timeout = TimeSpan.FromSeconds(10) }))
        {
            await eth.DownloadAsync(ControllerLibrary.Lines(profile, new Prog1000Options { ProgramStops = false }));
            await eth.DownloadAsync(ControllerLibrary.TableLines(profile));
            var session = new StreamingSession(eth, program, new StreamingOptions { Strategy = StrategyKind.Chunk, BufferWords = 60_000 });
            await session.StartAsync();
            var deadline = DateTime.UtcNow + TimeSpan.FromMinutes(3);
            while (session.State is not (SessionState.Completed or SessionState.Faulted or SessionState.Aborted) && DateTime.UtcNow < deadline)
            {
                await session.TickAsync();
                await Task.Delay(5);
            }

            session.State.Should().Be(SessionState.Completed, $"{name} should run to its end");
        }

        await host.StopAsync();
        var executed = host.Simulator.ExecutedMoves.Where(m => !(m.Kind == MoveKind.Dwell && m.Duration == 0)).ToList();
        var expected = Expected(path, profile);
        var largest = BlockEndProof.Check(executed, expected, Tolerance, name, "moving expanded block", line => $"{name}: expanded line {line}");
        return new ProofReport(expected.Count, largest);
    }

    /// <summary>The interpreter's end of every moving block of the expansion (expanded line numbers), machine millimetres.</summary>
    internal static List<(int Line, Point3 End)> Expected(string path, MachineProfile profile)
    {
        var expander = new MacroExpander(path, ProgramExpansion.For(profile, null));
        using var reader = new GCodeReader(new ExpandedStream(expander));
        var list = CanonBlockEnds.Of(reader, profile, blockDelete: true).Select(e => (e.Line, e.End)).ToList();
        expander.Error.Should().BeNull();
        return list;
    }
}
