using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

public class MachineProfileTests
{
    /// <summary>paper-24g7m's set as the embedded default-mill.json had it before named profiles (code, group).</summary>
    private static readonly (string Code, string Group)[] PaperSet =
    [
        ("G00", "GA"), ("G01", "GA"), ("G02", "GA"), ("G03", "GA"), ("G20", "GB"), ("G21", "GB"), ("G90", "GC"), ("G91", "GC"),
        ("G54", "GD"), ("G55", "GD"), ("G56", "GD"), ("G57", "GD"), ("G58", "GD"), ("G59", "GD"), ("G17", "GE"), ("G18", "GE"),
        ("G19", "GE"), ("G43", "GF"), ("G49", "GF"), ("G04", "GG"), ("G40", "GH"), ("G41", "GH"), ("G42", "GH"), ("G09", "GI"),
        ("M00", "MA"), ("M30", "MA"), ("M03", "MB"), ("M04", "MB"), ("M05", "MB"), ("M08", "MC"), ("M09", "MC"),
    ];

    [Fact]
    public void Paper_profile_is_the_checking_papers_set_unchanged()
    {
        var p = MachineProfile.Named("paper-24g7m")!;
        p.Should().BeSameAs(MachineProfile.Paper);
        p.GCodes.Should().HaveCount(24);
        p.MCodes.Should().HaveCount(7);
        p.GCodes.Concat(p.MCodes).Select(c => (c.Code, c.Group)).Should().BeEquivalentTo(PaperSet);
        p.GGroups.Select(g => g.Name).Should().Equal(MachineProfile.GGroupNames);
        p.MGroups.Select(g => g.Name).Should().Equal(MachineProfile.MGroupNames);
        p.GGroups.Where(g => !g.Modal).Select(g => g.Name).Should().Equal("GG", "GI");
        p.MGroups.Where(g => !g.Modal).Select(g => g.Name).Should().Equal("MA");
        (p.Startup, p.ToolCount, p.Letters, p.ProgramTail, p.DwellPInMilliseconds).Should().Be(
            ("G00 G21 G90 G54 G17 G49 G40 M05 M09", 24, "NOGMXYZIJKRFSTHDP", "M05", true));
    }

    [Fact]
    public void Default_is_fanuc_mill_with_the_codes_milling_posts_write()
    {
        var p = MachineProfile.Default;
        p.Name.Should().Be("fanuc-mill");
        MachineProfile.Resolve(null).Should().BeSameAs(p);
        string[] issueList =
        [
            "G00", "G01", "G02", "G03", "G04", "G09", "G10", "G17", "G18", "G19", "G20", "G21", "G28", "G30", "G40", "G41", "G42",
            "G41.2", "G42.2", "G43", "G44", "G49", "G50", "G51", "G52", "G53", "G54", "G55", "G56", "G57", "G58", "G59", "G54.1",
            "G61", "G64", "G68", "G69", "G73", "G74", "G76", "G80", "G81", "G82", "G83", "G84", "G85", "G86", "G87", "G88", "G89",
            "G90", "G91", "G90.1", "G91.1", "G92", "G94", "G95", "G98", "G99",
            "M00", "M01", "M02", "M03", "M04", "M05", "M06", "M07", "M08", "M09", "M19", "M30",
        ];
        foreach (var code in issueList)
        {
            p.Find(code[0], double.Parse(code[1..], System.Globalization.CultureInfo.InvariantCulture)).Should().NotBeNull(code);
        }

        p.GGroups.Count.Should().BeGreaterThan(9, "FANUC has more modal groups than paper-24g7m's nine");
        p.Letters.Should().Contain("ABC").And.Contain("Q").And.Contain("L").And.Contain("E").And.NotContain("U", "a 3- or 4-axis mill has no U axis");
        (p.DwellPInMilliseconds, p.SlashInBlock, p.ExtendedWorkOffsets).Should().Be((true, true, true));
        p.GGroupOf(81).Should().NotBe(p.GGroupOf(1), "FANUC keeps canned cycles in group 09, apart from motion");
        p.GGroupOf(28).Should().Be(p.GGroupOf(4)).And.Be(p.GGroupOf(53), "one-shot codes share group 00");
        p.GGroups[p.GGroupOf(4)].Modal.Should().BeFalse();
    }

    [Theory]
    [InlineData("linuxcnc-mill", false, false, "G4", "G64")]
    [InlineData("grbl", false, false, "G4", "G61")]
    public void Other_dialects_keep_their_own_facts(string name, bool dwellMs, bool slash, string dwell, string pathMode)
    {
        var p = MachineProfile.Named(name)!;
        (p.DwellPInMilliseconds, p.SlashInBlock, p.ExtendedWorkOffsets).Should().Be((dwellMs, slash, false));
        p.Find('G', double.Parse(dwell[1..], System.Globalization.CultureInfo.InvariantCulture)).Should().NotBeNull();
        p.Find('G', double.Parse(pathMode[1..], System.Globalization.CultureInfo.InvariantCulture)).Should().NotBeNull();
        p.Find('G', 10)!.Values['L'].Contains(20).Should().BeTrue("G10 L20 sets an offset from the current position");
    }

    [Fact]
    public void Grbl_has_no_tool_changer_no_rotary_axes_and_no_program_numbers()
    {
        var p = MachineProfile.Named("grbl")!;
        p.Find('M', 6).Should().BeNull();
        p.AcceptsLetter('A').Should().BeFalse();
        p.TakesProgramNumbers.Should().BeFalse();
        p.Find('G', 10)!.Values['P'].Contains(6).Should().BeTrue();
        p.Find('G', 10)!.Values['P'].Contains(7).Should().BeFalse();
        p.GGroupOf(80).Should().Be(p.GGroupOf(1), "grbl's G80 is in the motion group");
    }

    [Fact]
    public void Every_code_of_every_built_in_profile_says_what_runs_it()
    {
        foreach (var name in MachineProfile.BuiltInNames)
        {
            var p = MachineProfile.Named(name)!;
            foreach (var c in p.GCodes.Concat(p.MCodes))
            {
                c.Description.Should().NotBeEmpty($"{name} {c.Code}");
                if (c.Controller == ControllerSupport.NotYet)
                {
                    c.Note.Should().NotBeEmpty($"{name} {c.Code} says why it does not run yet");
                }
            }

            foreach (var motion in new[] { 0, 1, 2, 3 })
            {
                p.Find('G', motion)!.Controller.Should().Be(ControllerSupport.Library, $"{name} G{motion} runs on the controller");
            }
        }
    }

    [Fact]
    public void Json_round_trip_keeps_every_built_in_profile()
    {
        foreach (var name in MachineProfile.BuiltInNames)
        {
            var p = MachineProfile.Named(name)!;
            var again = MachineProfile.Parse(p.ToJson());
            again.GCodes.Should().BeEquivalentTo(p.GCodes, name);
            again.MCodes.Should().BeEquivalentTo(p.MCodes, name);
            again.GGroups.Should().Equal(p.GGroups);
            again.MGroups.Should().Equal(p.MGroups);
            (again.ToolCount, again.ProgramTail, again.RapidRate, again.Startup, again.SlashInBlock, again.ExtendedWorkOffsets, again.DwellPInMilliseconds).Should().Be(
                (p.ToolCount, p.ProgramTail, p.RapidRate, p.Startup, p.SlashInBlock, p.ExtendedWorkOffsets, p.DwellPInMilliseconds));
        }
    }

    [Fact]
    public void Names_resolve_to_built_ins_files_load_and_anything_else_says_what_was_expected()
    {
        MachineProfile.Resolve("GRBL").Name.Should().Be("grbl");
        using (var temp = new TestFolder("profile"))
        {
            var file = Path.Combine(temp.Path, "my-mill.json");
            File.WriteAllText(file, MachineProfile.Paper.ToJson().Replace("\"paper-24g7m\"", "\"my-mill\""));
            MachineProfile.Resolve(file).Name.Should().Be("my-mill");
        }

        var act = () => MachineProfile.Resolve("haas-mill");
        act.Should().Throw<InvalidDataException>().Which.Message.Should().Contain("fanuc-mill").And.Contain("no such file");
    }

    [Theory]
    [InlineData("{ not json", "not valid JSON")]
    [InlineData("{\"gGroups\":[{\"name\":\"GA\"}],\"gCodes\":[{\"code\":\"G01\",\"group\":\"GZ\"}]}", "group 'GZ'")]
    [InlineData("{\"gCodes\":[{\"code\":\"X01\",\"group\":\"GA\"}]}", "code 'X01'")]
    [InlineData("{\"gCodes\":[{\"code\":\"G01\",\"group\":\"GA\"},{\"code\":\"G1\",\"group\":\"GB\"}]}", "listed twice")]
    [InlineData("{\"toolCount\":-1}", "toolCount")]
    [InlineData("{\"gCodes\":[{\"code\":\"G01\",\"group\":\"GA\",\"controller\":\"maybe\"}]}", "controller 'maybe'")]
    [InlineData("{\"gCodes\":[{\"code\":\"G10\",\"group\":\"00\",\"values\":{\"L\":\"2,x\"}}]}", "values.L")]
    [InlineData("{\"gGroups\":[{\"name\":\"01\"},{\"name\":\"01\"}]}", "listed twice")]
    public void Invalid_profiles_say_why(string json, string reason)
    {
        var act = () => MachineProfile.Parse(json, "bad.json");
        act.Should().Throw<InvalidDataException>().Which.Message.Should().Contain("bad.json").And.Contain(reason);
    }

    [Fact]
    public void A_profile_with_decimal_codes_accepts_them()
    {
        var p = MachineProfile.Parse("{\"gCodes\":[{\"code\":\"G00\",\"group\":\"GA\"},{\"code\":\"G64.1\",\"group\":\"GI\"}],\"startup\":\"G00\"}");
        var diags = new Checker(p).CheckText("O1\nG64.1\nG64.2").Diagnostics;
        diags.Should().ContainSingle(d => d.Code == DiagnosticCodes.DecimalCode).Which.Line.Should().Be(3);
    }

    [Fact]
    public void A_profile_without_declared_groups_takes_them_from_its_codes_and_a_code_without_controller_is_not_yet()
    {
        var p = MachineProfile.Parse("""
            { "gCodes": [ { "code": "G01", "group": "motion" }, { "code": "G04", "group": "once" }, { "code": "G00", "group": "motion" } ],
              "mCodes": [ { "code": "M30", "group": "end" } ], "startup": "G00" }
            """);
        p.GGroups.Select(g => (g.Name, g.Modal)).Should().Equal(("motion", true), ("once", false));
        p.MGroups.Should().ContainSingle().Which.Modal.Should().BeFalse();
        p.Find('G', 1)!.Controller.Should().Be(ControllerSupport.NotYet);
    }
}
