using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

/// <summary>The interpreter's canonical moves (issue 24 item 3): what it tells its sink is what it decided.</summary>
public class CanonicalMovesTests
{
    private const string Program = """
        G90 G21 G54 G17
        (a comment line starts a block too)
        G00 X10 Y5 Z2 F300
        G01 Z-1
        G02 X20 Y5 I5 J0
        G04 P500
        G98 G81 X30 Y5 Z-3 R1
        G80
        G28 Z5
        M30
        """;

    [Fact]
    public void Settings_and_codes_are_called_in_the_order_written_with_the_words_a_library_routine_reads()
    {
        var canon = new CanonRecorder();
        var interp = new Interpreter(MachineProfile.Named("linuxcnc-mill")!) { Canon = canon };
        string[] lines = ["G20 G17 G18 G64 P0.01 Q0.02", "T2 M6 S1200 M3 M8 F10", "M19 R30 Q1 P0", "G04 P1.5", "G43 H2", "M9 M5 M30"];
        var calls = new List<string>();
        for (var n = 0; n < lines.Length; n++)
        {
            canon.Calls.Clear();
            interp.Execute(GCodeReader.LexLine(lines[n], n + 1));
            calls.Add(string.Join(", ", canon.Calls));
        }

        calls.Should().Equal(
            "Code G17, Code G64 P0.254 Q0.508",  // G18 is refused (a second code of the plane group); G64's tolerances in mm
            "SelectTool 2, ChangeTool 2 M6, SetSpindleSpeed 1200, Spindle Clockwise M3, Coolant Flood M8, SetFeedRate 10",
            "Spindle Orient M19 R30 Q1 P0",      // the routine reads R, Q and P in the profile's order, as given (not lengths)
            "Dwell 1.5",                         // LinuxCNC's P is in seconds
            "UseToolLengthOffset 43 2",
            "Coolant Off M9, Spindle Stop M5, ProgramStop End M30");
    }

    [Fact]
    public void Every_motion_is_the_decoded_blocks_motion_and_every_line_starts_where_the_last_ended()
    {
        var canon = new CanonRecorder();
        var withSink = new Interpreter(MachineProfile.Default) { Canon = canon };
        var plain = new Interpreter(MachineProfile.Default);
        var decoded = new List<DecodedBlock>();
        var lines = Program.Split('\n');
        for (var n = 0; n < lines.Length; n++)
        {
            withSink.Execute(GCodeReader.LexLine(lines[n], n + 1));
            if (plain.Step(GCodeReader.LexLine(lines[n], n + 1)) is { Motion: not MotionKind.None } b)
            {
                decoded.Add(b);
            }
        }

        canon.Starts.Should().HaveCount(lines.Length, "every line the interpreter takes starts a block, comments too");
        canon.Motions.Select(m => (m.Line, m.Kind, m.Start, m.End, m.Centre, m.Seconds))
            .Should().Equal(decoded.Select(b => (b.Line, b.Motion, b.Start, b.End, b.Center, b.DurationSeconds)));
        canon.Motions.Select(m => m.Kind).Should().Contain([MotionKind.ArcCw, MotionKind.Dwell, MotionKind.Cycle]);
        canon.Steps.Should().Contain(s => s.Kind == HostMoveKind.Feed && s.Target.Z == -3, "the hole's feed to its bottom");
        canon.Steps.Should().Contain(s => s.Kind == HostMoveKind.MachineRapid, "G28's way to the reference position");
        canon.Starts[3].Position.Should().Be(new Point3(10, 5, 2), "the G01 block starts where the rapid ended");
    }
}
