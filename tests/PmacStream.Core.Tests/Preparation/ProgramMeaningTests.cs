using System.Globalization;
using System.Text.RegularExpressions;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>
/// Nothing runs on the controller with a meaning other than the program's: the words a library routine reads reach
/// it, exact stop stays exact stop, and what the controller cannot mean is refused at the check.
/// </summary>
public partial class ProgramMeaningTests
{
    private static List<string> Body(string program, MachineProfile profile, bool force = false)
    {
        using var tp = new TempProgram(program);
        var o = new SplitOptions { CheckProfile = profile, AllowErrors = force, ProgramTail = "" };
        var r = tp.Split(o);
        return ChunkText.Body(r, o).Select(l => TrackingPrefix().Replace(l, string.Empty)).ToList();
    }

    private static List<Diagnostic> Check(string program, MachineProfile profile) =>
        new Checker(profile).CheckText(program).Diagnostics.ToList();

    /// <summary>A value the code takes for the word (its allowed values, else a distinctive one).</summary>
    private static double ValueFor(CodeDefinition def, char letter) =>
        def.Values.TryGetValue(letter, out var set) ? new[] { 2.0, 1.0, 3.0, 0.0, 45.0 }.First(set.Contains) : 7.25 + (letter - 'A');

    /// <summary>The letters a routine's <c>READ(...)</c> takes, empty when it reads none.</summary>
    private static string ReadLetters(string body) =>
        ReadList().Match(body) is { Success: true } m ? m.Groups[1].Value.Replace(",", string.Empty, StringComparison.Ordinal) : string.Empty;

    /// <summary>
    /// What the PMAC's <c>READ</c> takes after the code's call on the line: the words that follow it, up to the first
    /// letter it does not read.
    /// </summary>
    private static Dictionary<char, double> ReadAfterCall(List<string> body, char letter, double number, string letters)
    {
        foreach (var line in body)
        {
            var tokens = line.Split(' ', StringSplitOptions.RemoveEmptyEntries);
            for (var i = 0; i < tokens.Length; i++)
            {
                if (tokens[i][0] != letter || !double.TryParse(tokens[i].AsSpan(1), NumberStyles.Float, CultureInfo.InvariantCulture, out var n) || n != number)
                {
                    continue;
                }

                var read = new Dictionary<char, double>();
                for (var j = i + 1; j < tokens.Length && letters.Contains(tokens[j][0], StringComparison.Ordinal); j++)
                {
                    read[tokens[j][0]] = double.Parse(tokens[j].AsSpan(1), CultureInfo.InvariantCulture);
                }

                return read;
            }
        }

        throw new InvalidOperationException($"{letter}{number} is not sent: {string.Join(" | ", body)}");
    }

    public static TheoryData<string> BuiltIns => new(MachineProfile.BuiltInNames);

    [Theory]
    [MemberData(nameof(BuiltIns))]
    public void Every_library_code_that_reads_words_gets_them_in_plain_blocks_host_blocks_and_inch_blocks(string name)
    {
        var profile = MachineProfile.Named(name)!;
        var routines = Prog1000Library.Routines(profile);
        var walked = 0;
        foreach (var def in profile.GCodes.Concat(profile.MCodes))
        {
            var letter = def.Code[0];
            // A move's words are the controller's own; G10's words the host turns into the table entry it sets.
            if (def.Controller != ControllerSupport.Library || def.Words.Length == 0 ||
                (letter == 'G' && (CodeRoles.OfG(def.Key) == GRole.Motion || def.Key == 100)))
            {
                continue;
            }

            var routine = routines.Single(r => r.Code == def.Code.ToUpperInvariant());
            var reads = ReadLetters(routine.Body);
            foreach (var c in def.Words)
            {
                reads.Should().Contain(c.ToString(), "{0}'s routine reads every word the profile says {0} takes, or the controller would run it as a statement", def.Code);
            }

            var words = string.Join(' ', def.Words.Select(c => c + ValueFor(def, c).ToString(CultureInfo.InvariantCulture)));
            var number = def.Number;
            var inch = profile.Find('G', 20) != null;
            var start = (name == "grbl" ? string.Empty : "O1\n") + (inch ? "G21\n" : string.Empty);
            foreach (var (program, scale, how) in new[]
            {
                ($"{start}{def.Code} {words}\n", 1.0, "a block of its own"),
                ($"{start}T1 {def.Code} {words}\n", 1.0, "a host block (a T word)"),
                ($"{start}{string.Join(' ', def.Words.Reverse().Select(c => c + ValueFor(def, c).ToString(CultureInfo.InvariantCulture)))} {def.Code}\n", 1.0, "words before the code"),
                ($"{start.Replace("G21", "G20", StringComparison.Ordinal)}{def.Code} {words}\n", inch ? 25.4 : 1.0, "an inch program"),
            })
            {
                var body = Body(program, profile, force: true);
                var got = ReadAfterCall(body, letter, number, reads);
                foreach (var c in def.Words)
                {
                    var length = letter == 'G' && CodeRoles.WordIsLength(def.Key, c);
                    got.Should().ContainKey(c, "{0} {1} in {2} ({3})", def.Code, c, how, string.Join(" | ", body));
                    got[c].Should().BeApproximately(ValueFor(def, c) * (length ? scale : 1), 1e-9, "{0} {1} in {2}", def.Code, c, how);
                }
            }

            walked++;
        }

        walked.Should().BeGreaterThan(0, "every built-in profile has a library code that reads words (G04 at least)");
    }

    [Fact]
    public void Spindle_orientation_passes_its_angle_to_the_machine()
    {
        var o = new Prog1000Options();
        var fanuc = Prog1000Library.Routines(MachineProfile.Default).Single(r => r.Code == "M19").Body;
        fanuc.Should().StartWith("READ(R,P)").And.Contain($"{o.SpindleOrientAngle}=Q118").And.Contain($"{o.SpindleOrientAngle}=Q116", "Haas's P is whole degrees");
        var linuxcnc = Prog1000Library.Routines(MachineProfile.Named("linuxcnc-mill")!).Single(r => r.Code == "M19").Body;
        linuxcnc.Should().StartWith("READ(R,Q,P)").And.Contain($"{o.SpindleOrientAngle}=Q118").And.Contain($"{o.SpindleOrientDirection}=Q116", "LinuxCNC's P is the direction")
            .And.NotContain($"{o.SpindleOrientAngle}=Q116");
        Body("O1\nG20\nG00 X1.\nM19 R45.\nM30\n", MachineProfile.Default).Should().Contain("M19 R45", "an inch program's host block keeps the angle");
    }

    [Fact]
    public void Grbl_exact_path_mode_ends_every_move_at_rest_in_host_blocks_too()
    {
        var grbl = MachineProfile.Named("grbl")!;
        var body = Body("G21 G90\nG1 X1 F100\nX2\nG20\nX1\nG21\n", grbl);
        var moves = body.Select((l, i) => (l, i)).Where(t => t.l.Contains('X', StringComparison.Ordinal)).ToList();
        moves.Should().HaveCount(3);
        moves.Should().OnlyContain(t => body[t.i + 1] == HostConversion.ExactStopCode, "G61 is in force from power-on: each move ends at rest, in an inch block too");
        body.Should().Contain("X25.4 F(P500)").And.NotContain(l => l.Contains("G61", StringComparison.Ordinal));
        var library = Prog1000Library.Generate(grbl);
        library.Should().Contain($"N{LibraryRoutines.ExactStop} DWELL0 RET", "G09.9 is the library's own exact stop where the profile has no G09");
        library.Should().NotContain("N61000", "G61 has no routine that would let the controller blend");
    }

    [Fact]
    public void A_canned_cycle_in_inverse_time_is_refused_and_inverse_time_moves_need_their_f()
    {
        var fanuc = MachineProfile.Default;
        Check("O1\nG00 X0 Y0 Z10.\nG93 G81 X1. Y1. Z-1. R1. F2.\nM30\n", fanuc)
            .Should().Contain(d => d.Code == DiagnosticCodes.CycleInInverseTime && d.Line == 3 && d.Column == 5);
        Check("O1\nG00 X0 Y0 Z10.\nG81 X1. Y1. Z-1. R1. F100.\nG93\nX2.\nG80 G94\nM30\n", fanuc)
            .Should().Contain(d => d.Code == DiagnosticCodes.CycleInInverseTime && d.Line == 5, "a hole of a cycle already in force, after G93");
        Check("G21 G0 X0 Y0 Z10\nG93 G81 X1 Y1 Z-1 R1 F2\n", MachineProfile.Named("linuxcnc-mill")!)
            .Should().Contain(d => d.Code == DiagnosticCodes.CycleInInverseTime);
        var moves = Check("O1\nG93 G01 X1. F2.\nX2.\nG02 X3. Y0 R0.5\nG03 X4. Y0 R0.5 F3.\nG94\nM30\n", fanuc);
        moves.Where(d => d.Code == DiagnosticCodes.FeedMoveWithoutFeed).Select(d => d.Line).Should().Equal(3, 4);
        moves.Should().NotContain(d => d.Code == DiagnosticCodes.CycleInInverseTime);
    }

    [Fact]
    public void G10_l2_p0_is_the_external_offset_on_fanuc_and_the_current_offset_on_linuxcnc_and_grbl()
    {
        Interpreter Run(MachineProfile p, string program)
        {
            var interp = new Interpreter(p);
            foreach (var (line, i) in program.Split('\n').Select((l, i) => (l, i)))
            {
                interp.Execute(GCodeReader.LexLine(line, i + 1));
            }

            return interp;
        }

        const string program = "G21 G90 G55\nG10 L2 P0 X5. Y-2.\nG00 X0 Y0 Z0\nG54 X0 Y0 Z0";
        var fanuc = Run(MachineProfile.Default, program);
        fanuc.Position.Should().Be(new Point3(5, -2, 0), "the external offset shifts G54 as well as G55");
        var linuxcnc = Run(MachineProfile.Named("linuxcnc-mill")!, program);
        linuxcnc.Position.Should().Be(new Point3(0, 0, 0), "P0 set G55, the offset in force then; G54 is untouched");
        Run(MachineProfile.Named("linuxcnc-mill")!, "G21 G90 G55\nG10 L2 P0 X5. Y-2.\nG00 X0 Y0 Z0").Position.Should().Be(new Point3(5, -2, 0));
        Run(MachineProfile.Named("grbl")!, "G21 G90 G55\nG10 L2 P0 X5 Y-2\nG0 X0 Y0 Z0\nG54 X0 Y0 Z0").Position.Should().Be(new Point3(0, 0, 0));

        Body("O1\nG21 G90 G55\nG10 L2 P0 X5. Y-2.\nG00 X0 Y0\nM30\n", MachineProfile.Default).Should().Contain("G10 L2 P0 X5 Y-2 Z0");
        Body("G21 G90 G55\nG10 L2 P0 X5. Y-2.\nG00 X0 Y0\n", MachineProfile.Named("linuxcnc-mill")!).Should().Contain("G10 L2 P2 X5 Y-2 Z0");
        var map = new LibraryMap();
        Prog1000Library.Generate(MachineProfile.Default).Should().Contain($"+P{map.WorkOffsets}+", "the displacement adds the external offset (index 0)");
        Prog1000Library.Generate(MachineProfile.Named("linuxcnc-mill")!).Should().NotContain($"+P{map.WorkOffsets}+");
    }

    [Fact]
    public void Offsets_on_rotary_axes_that_the_controller_would_not_apply_are_refused()
    {
        var fanuc = MachineProfile.Default;
        string[] Codes(string program) => Check(program, fanuc).Where(d => d.Code == DiagnosticCodes.RotaryOffset).Select(d => $"{d.Line}:{d.Column}").ToArray();
        Codes("O1\nG10 L2 P2 A90.\nG55 G00 A0\nM30\n").Should().Equal("2:11");
        Codes("O1\nG52 B-5.\nG92 C0\nG10 L20 P1 A10.\nM30\n").Should().Equal("2:5", "3:5", "4:12");
        Codes("O1\nG10 L2 P2 X1. A0\nG52 A0\nG00 A90.\nM30\n").Should().BeEmpty("a zero rotary offset is what the controller does anyway");
        Codes("G21\nG10 L20 P2 A0\n").Should().BeEmpty("fanuc's G10 L20 sets an extended offset to the values");
        Check("G21\nG10 L20 P2 A0\n", MachineProfile.Named("linuxcnc-mill")!).Should().Contain(d => d.Code == DiagnosticCodes.RotaryOffset,
            "LinuxCNC's L20 makes the rotary position (not tracked) read as A0");
    }

    [GeneratedRegex(@"^M0==\d+ ")]
    private static partial Regex TrackingPrefix();

    [GeneratedRegex(@"READ\(([A-Z,]+)\)")]
    private static partial Regex ReadList();
}
