using PmacStream.GCode;

namespace PmacStream.Core.Tests.GCode;

public class MachineProfileTests
{
    [Fact]
    public void Default_profile_follows_seed_002()
    {
        var p = MachineProfile.Default;
        p.GCodes.Should().HaveCount(24);
        p.MCodes.Should().HaveCount(7);
        p.GCodes.Select(c => c.Group).Distinct().Should().BeEquivalentTo(MachineProfile.GGroupNames);
        p.MCodes.Select(c => c.Group).Distinct().Should().BeEquivalentTo(MachineProfile.MGroupNames);
        foreach (var g in new[] { 0, 1, 2, 3, 4, 9, 17, 18, 19, 90, 91 })
        {
            p.GGroupOf(g).Should().BeGreaterThanOrEqualTo(0, $"G{g:00} is in the FANUC milling code table");
        }

        p.GGroupOf(0).Should().Be(p.GGroupOf(3));
        p.GGroupOf(17).Should().NotBe(p.GGroupOf(90));
        p.MGroupOf(3).Should().Be(p.MGroupOf(5));
        p.ProgramTail.Should().Be("M05");
        p.ToolCount.Should().BeGreaterThan(0);
    }

    [Fact]
    public void Json_round_trip_keeps_the_profile()
    {
        var again = MachineProfile.Parse(MachineProfile.Default.ToJson());
        again.GCodes.Should().BeEquivalentTo(MachineProfile.Default.GCodes);
        again.MCodes.Should().BeEquivalentTo(MachineProfile.Default.MCodes);
        (again.ToolCount, again.ProgramTail, again.RapidRate, again.Startup).Should().Be(
            (MachineProfile.Default.ToolCount, MachineProfile.Default.ProgramTail, MachineProfile.Default.RapidRate, MachineProfile.Default.Startup));
    }

    [Theory]
    [InlineData("{ not json", "not valid JSON")]
    [InlineData("{\"gCodes\":[{\"code\":\"G01\",\"group\":\"GZ\"}]}", "group 'GZ'")]
    [InlineData("{\"gCodes\":[{\"code\":\"X01\",\"group\":\"GA\"}]}", "code 'X01'")]
    [InlineData("{\"gCodes\":[{\"code\":\"G01\",\"group\":\"GA\"},{\"code\":\"G1\",\"group\":\"GB\"}]}", "listed twice")]
    [InlineData("{\"toolCount\":-1}", "toolCount")]
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
}
