using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

public class Prog1000LibraryTests
{
    private static List<string> Lines(string text) => text.TrimEnd('\r', '\n').Split("\r\n").ToList();

    [Fact]
    public void Seed_table_1_conversions_are_generated_at_code_times_1000()
    {
        var text = Prog1000Library.Generate(MachineProfile.Default, new Prog1000Options { Comments = false });
        var lines = Lines(text);
        lines[0].Should().Be("CLOSE");
        lines[1].Should().Be("DEFINE TBUF 1");
        lines[2].Should().Be("OPEN PROG 1000 CLEAR");
        // The motion and distance modes are also kept in the library's state (Q31, Q30) for G53 and M06 to restore.
        lines.Should().Contain([
            "N0 RAPID Q31=0 RET", "N1000 LINEAR Q31=1 RET", "N2000 CIRCLE1 Q31=2 RET", "N3000 CIRCLE2 Q31=3 RET", "N4000 READ(P) DWELL(Q116) RET",
            "N9000 DWELL0 RET", "N17000 NORMAL K-1 RET", "N18000 NORMAL J-1 RET", "N19000 NORMAL I-1 RET",
            "N90000 ABS Q30=90 RET", "N91000 INC Q30=91 RET",
        ]);
        var m = lines.IndexOf("OPEN PROG 1001 CLEAR");
        m.Should().BeGreaterThan(1);
        lines[m - 1].Should().Be("CLOSE");
        lines[^2].Should().Be("CLOSE");
        lines[^1].Should().MatchRegex(@"^P7000=1 P7001=\d+$", "the library ends by recording which it is");
        lines.Should().OnlyContain(l => l.All(c => c < 128));
    }

    [Fact]
    public void Every_library_code_gets_exactly_one_label_ending_in_ret_and_not_yet_codes_none()
    {
        foreach (var name in MachineProfile.BuiltInNames)
        {
            var profile = MachineProfile.Named(name)!;
            var routines = Prog1000Library.Routines(profile);
            routines.Should().HaveCount(profile.GCodes.Count + profile.MCodes.Count);
            var text = Prog1000Library.Generate(profile, new Prog1000Options { Comments = false });
            foreach (var r in routines)
            {
                var code = double.Parse(r.Code[1..], System.Globalization.CultureInfo.InvariantCulture);
                r.Label.Should().Be((int)Math.Round((code % 100) * 1000));
                r.Converted.Should().Be(r.Controller == ControllerSupport.Library, $"{name} {r.Code}");
            }

            // Every converted code, and the library's six own routines, have one label; each routine ends in RET
            // (on its own line after a multi-line body, whose last line may be a one-line IF).
            var labelLines = Lines(text).Where(l => l.StartsWith('N')).ToList();
            labelLines.Should().HaveCount(routines.Count(r => r.Converted) + 6);

            // Each routine ends in RET: on its label's line, or on a line of its own after a one-line IF.
            var lines = Lines(text).ToList();
            foreach (var label in labelLines)
            {
                var end = lines.IndexOf(label);
                while (!lines[end].EndsWith("RET", StringComparison.Ordinal))
                {
                    end++;
                    lines[end].Should().NotStartWith("N", $"{name}: the routine of {label} ends in RET before the next label");
                    lines[end].Should().NotBe("CLOSE");
                }
            }
            var withComments = Prog1000Library.Generate(profile);
            Lines(withComments).Should().OnlyContain(l => l.All(c => c < 128), "the file is downloaded to the controller as ASCII");
            foreach (var r in routines.Where(r => !r.Converted))
            {
                withComments.Should().Contain(" " + r.Code, "a code without a routine is listed as not run yet");
            }
        }
    }

    [Fact]
    public void A_code_the_profile_marks_library_needs_a_routine_the_profile_can_give_its_own()
    {
        var missing = MachineProfile.Parse("""
            { "name": "m", "gCodes": [ { "code": "G112", "group": "00", "description": "polar interpolation", "controller": "library" } ] }
            """);
        var act = () => Prog1000Library.Generate(missing);
        act.Should().Throw<InvalidDataException>().Which.Message.Should().Contain("G112").And.Contain("routine");

        var own = MachineProfile.Parse("""
            { "name": "o", "mCodes": [ { "code": "M07", "group": "c", "description": "mist", "controller": "library", "routine": "M905=1" } ] }
            """);
        Lines(Prog1000Library.Generate(own, new Prog1000Options { Comments = false })).Should().Contain("N7000 M905=1 RET");
    }

    [Fact]
    public void Spindle_and_coolant_stops_wait_for_lookahead_with_dwell0()
    {
        var routines = Prog1000Library.Routines(MachineProfile.Default, new Prog1000Options { SpindleOn = "M1", SpindleReverse = "M2", Coolant = "M3" })
            .Where(r => r.Program == 1001).ToDictionary(r => r.Code);
        routines["M05"].Body.Should().Be("DWELL0 M1=0");
        routines["M30"].Body.Should().StartWith("DWELL0").And.Contain("M1=0").And.Contain("M3=0");
        routines["M03"].Body.Should().EndWith("M2=0 M1=1");
        routines["M04"].Body.Should().EndWith("M2=1 M1=1");
        routines["M08"].Body.Should().Be("M3=1");
        routines["M09"].Body.Should().StartWith("DWELL0");
    }

    [Fact]
    public void Codes_from_100_go_to_prog_1010()
    {
        var profile = MachineProfile.Parse("""
            { "name": "t", "gCodes": [ { "code": "G01", "group": "GA", "description": "line", "controller": "library" },
                                       { "code": "G112", "group": "GB", "description": "polar", "controller": "library", "routine": "NORMAL K-1" },
                                       { "code": "G64.1", "group": "GC", "description": "odd" } ],
              "mCodes": [ { "code": "M30", "group": "MA", "description": "end", "controller": "library" } ] }
            """);
        var routines = Prog1000Library.Routines(profile);
        routines.Single(r => r.Code == "G112").Should().Match<Prog1000Routine>(r => r.Program == 1010 && r.Label == 12000 && r.Converted);
        routines.Single(r => r.Code == "G64.1").Should().Match<Prog1000Routine>(r => r.Label == 64100 && !r.Converted);
        var lines = Lines(Prog1000Library.Generate(profile, new Prog1000Options { Comments = false }));
        lines.Should().ContainInOrder("OPEN PROG 1000 CLEAR", "N1000 LINEAR Q31=1 RET", "CLOSE", "OPEN PROG 1001 CLEAR", "CLOSE", "OPEN PROG 1010 CLEAR", "N12000 NORMAL K-1 RET", "CLOSE");
        lines.Should().NotContain(l => l.StartsWith("N64100", StringComparison.Ordinal), "a code without a routine gets no empty label that looks as if it ran");
    }

    [Fact]
    public void Dwell_in_seconds_profiles_scale_p_to_milliseconds()
    {
        var profile = MachineProfile.Parse("""
            { "name": "s", "dwellPInMilliseconds": false, "gCodes": [ { "code": "G04", "group": "GG", "description": "dwell", "controller": "library" } ], "mCodes": [] }
            """);
        Prog1000Library.Routines(profile).Single().Body.Should().Be("READ(P) DWELL(Q116*1000)");
    }

    [Fact]
    public void Fanuc_mill_machine_outputs_have_routines_setting_their_configured_variables_and_only_codes_that_wait_stay_not_yet()
    {
        var o = new Prog1000Options
        {
            ThroughSpindleCoolant = "M1909", FourthAxisBrake = "M1910", FifthAxisBrake = "M1911", ChipConveyor = "M1912",
            ChipConveyorReverse = "M1913", ThroughToolAir = "M1914", AirGun = "M1915",
        };
        var routines = Prog1000Library.Routines(MachineProfile.Default, o).Where(r => r.Code[0] == 'M').ToDictionary(r => r.Code);
        var expected = new Dictionary<string, string>
        {
            ["M88"] = "M1909=1", ["M89"] = "DWELL0 M1909=0", ["M10"] = "DWELL0 M1910=1", ["M11"] = "DWELL0 M1910=0",
            ["M12"] = "DWELL0 M1911=1", ["M13"] = "DWELL0 M1911=0", ["M31"] = "M1913=0 M1912=1", ["M32"] = "DWELL0 M1913=1 M1912=1",
            ["M33"] = "DWELL0 M1912=0", ["M73"] = "M1914=1", ["M74"] = "DWELL0 M1914=0", ["M83"] = "M1915=1", ["M84"] = "DWELL0 M1915=0",
        };
        foreach (var (code, body) in expected)
        {
            routines[code].Converted.Should().BeTrue(code);
            routines[code].Program.Should().Be(1001);
            routines[code].Label.Should().Be(int.Parse(code[1..], System.Globalization.CultureInfo.InvariantCulture) * 1000);
            routines[code].Body.Should().Be(body, code);
        }

        // Gear range changes wait for the gearbox; rigid tapping is not an output (subprograms are expanded on the host).
        routines.Values.Where(r => r.Controller == ControllerSupport.NotYet).Select(r => r.Code).Should()
            .BeEquivalentTo("M29", "M41", "M42");
        routines["M41"].Note.Should().Contain("in-gear input");
    }
}
